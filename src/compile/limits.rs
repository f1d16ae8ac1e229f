//! The bounds on the optimizer's work that depend on the meshes or on the command line: the
//! nodes of each distance grid at the project's `grid-cell`, and a `--capsules` count (the
//! project's own counts are bounded by the front end). docs/limits.md, "Optimizer".

use super::optimize::OptimizeOptions;
use crate::diagnostic::Problem;
use crate::geometry::{DistanceGrid, TriMesh};
use crate::spec::codes::{GRID_TOO_FINE, TOO_MANY_CAPSULES};
use crate::spec::model::{Optimize, Project, MAX_OPTIMIZED_CAPSULES, MAX_POSE_CAPSULES};

/// The most nodes of one component's distance grid (2²⁴, 128 MB of `f64`).
pub const MAX_GRID_NODES: f64 = 16_777_216.0;

/// Every bound the optimizer run `options` on `project` (which optimizes as `settings` say)
/// breaks, with `meshes` in component order.
pub fn optimizer_limits(
    project: &Project,
    settings: &Optimize,
    meshes: &[TriMesh],
    options: &OptimizeOptions,
) -> Vec<Problem> {
    let mut problems = Vec::new();
    if let Some(cell) = settings.grid_cell {
        for (index, mesh) in meshes.iter().enumerate() {
            let nodes = DistanceGrid::planned_nodes(mesh, cell);
            if nodes > MAX_GRID_NODES {
                let coarsest = finest_cell(mesh, cell);
                let mut problem = Problem::error(
                    GRID_TOO_FINE,
                    format!(
                        "`grid-cell={cell}` gives component `{}` a distance grid of {nodes:.3e} nodes; \
                         the most is {MAX_GRID_NODES:.0}",
                        project.component_name(index)
                    ),
                )
                .with_help(format!(
                    "use `grid-cell={coarsest}` or more, or leave `grid-cell=` out for the default \
                     (docs/limits.md, \"Optimizer\")"
                ));
                if let Some(span) = settings.grid_cell_span {
                    problem = problem.with_label(span, "too fine for this mesh");
                }
                problems.push(problem);
            }
        }
    }
    if let Some(count) = options.capsules {
        let work = count.max(1).saturating_mul(project.poses.len());
        if count > MAX_OPTIMIZED_CAPSULES || work > MAX_POSE_CAPSULES {
            problems.push(
                Problem::error(
                    TOO_MANY_CAPSULES,
                    format!(
                        "`--capsules {count}` with {} poses: the optimizer places at most \
                         {MAX_OPTIMIZED_CAPSULES} capsules and weighs at most {MAX_POSE_CAPSULES} \
                         poses × capsules",
                        project.poses.len()
                    ),
                )
                .with_help("ask for fewer capsules (docs/limits.md, \"Optimizer\")"),
            );
        }
    }
    problems
}

/// The smallest spacing, rounded up to two significant digits and written out, that keeps `mesh`'s grid within
/// [`MAX_GRID_NODES`], found by doubling from `cell` and then halving the interval.
fn finest_cell(mesh: &TriMesh, cell: f64) -> String {
    let fits = |c: f64| DistanceGrid::planned_nodes(mesh, c) <= MAX_GRID_NODES;
    let mut hi = cell.max(f64::MIN_POSITIVE);
    while !fits(hi) && hi < f64::MAX / 4.0 {
        hi *= 2.0;
    }
    let mut lo = hi / 2.0;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if fits(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let exponent = hi.log10().floor() as i32 - 1;
    let scale = 10f64.powi(exponent);
    let mut rounded = (hi / scale).ceil() * scale;
    // Rounding the digits can land a hair below the bound.
    if !fits(rounded) {
        rounded += scale;
    }
    let decimals = usize::try_from(-exponent).unwrap_or(0);
    format!("{rounded:.decimals$}")
}
