//! The optimizer: chooses the capsules (count, ends, radii) and the infill that meet a project's
//! goals with the largest margin (paper section 4).

mod backfill;
mod bounds;
mod cache;
mod conflicts;
mod disk_cache;
mod exhaustive;
mod grids;
mod heuristic;
mod problem;
mod random_start;
mod repair;
mod rescue;
mod seeds;
mod solver;
mod stock;
#[cfg(test)]
mod test_meshes;

pub use backfill::backfill;
pub use bounds::design_bounds;
pub use cache::{Built, GridKey, PrecomputeCache};
pub use conflicts::{
    explain as explain_conflicts, Conflict, Explanation, GoalRef, Space as ConflictSpace,
    MAX_EXPLANATION_SOLVES,
};
pub use disk_cache::DiskCache;
pub use exhaustive::{rank, Ranking};
pub use grids::{content_hash, default_cell};
pub use heuristic::{choose, run as run_heuristic, Candidate, Round};
pub use problem::{Origin, Outcome, Problem, StartCapsule};
pub use repair::{repair_seeds, Rules, SeedRepair};
pub use rescue::{rescue, RESCUE_ROUNDS, RESCUE_STARTS};
pub use seeds::{has_room, skeleton_seeds, SeedSite};
pub use solver::{solve, Bounds, Budget, Method, Solve};
pub use stock::{
    capsule_radius, grid_scale, length_decimals, smallest_capsule_radius, snap as snap_to_stock,
};
