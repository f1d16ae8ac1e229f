//! The optimizer: chooses the capsules (count, ends, radii) and the infill that meet a project's
//! goals with the largest margin (paper section 4).

mod bounds;
mod solver;

pub use bounds::design_bounds;
pub use solver::{solve, Bounds, Budget, Method, Solve};
