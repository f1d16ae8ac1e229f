//! The front end: the project-file grammar and the typed project it describes.
//!
//! [`parse_project`] turns project-file text into a [`model::Project`] and every problem found.

mod check;
pub mod codes;
mod guard;
pub mod model;
mod parse;
mod resolve;
mod syntax;
pub mod transform;
mod tree;
mod value;
pub mod vocabulary;

pub use parse::{parse_project, Parsed};
