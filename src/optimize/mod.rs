//! The optimizer: chooses the capsules (count, ends, radii) and the infill that meet a project's
//! goals with the largest margin (paper section 4).

mod bounds;
mod exhaustive;
mod grids;
mod heuristic;
mod problem;
mod solver;

pub use bounds::design_bounds;
pub use exhaustive::{rank, Ranking};
pub use grids::{content_hash, default_cell, GridCache};
pub use heuristic::{choose, run as run_heuristic, Candidate};
pub use problem::{Outcome, Problem, StartCapsule};
pub use solver::{solve, Bounds, Budget, Method, Solve};
