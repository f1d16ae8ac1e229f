//! The front end: the project-file grammar and the typed project it describes.
//!
//! [`parse_project`] turns project-file text into a [`model::Project`] and every problem found;
//! [`parse_solution`] reads a solution file (the optimizer's capsules) against a project.

mod bounds;
mod check;
pub mod codes;
mod file;
mod guard;
mod mesh_frame;
pub mod model;
mod parse;
mod resolve;
mod rig;
mod solution;
pub mod stock;
pub(crate) mod syntax;
pub mod transform;
mod tree;
mod value;
pub mod vocabulary;

pub use file::{read_solution_source, read_source};
pub use parse::{parse_project, parse_project_with, Parsed, MAX_PROBLEMS};
pub use solution::{parse_solution, ParsedSolution};
pub use syntax::MAX_SOURCE_BYTES;
