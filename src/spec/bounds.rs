//! The bounds on what a project asks the optimizer to do, so that no project makes it run
//! without end: the capsule count and the poses × capsules it weighs ([`MAX_OPTIMIZED_CAPSULES`],
//! [`MAX_POSE_CAPSULES`]; docs/limits.md, "Optimizer"). The grid's node count depends on the
//! meshes and is bounded by the driver.

use super::codes;
use super::model::{Capsule, Optimize, Pose, MAX_OPTIMIZED_CAPSULES, MAX_POSE_CAPSULES};
use crate::diagnostic::Problem;

/// The bounds on what the optimizer is asked to do: at most [`MAX_OPTIMIZED_CAPSULES`] capsules
/// (asked for, or written as its seeds) and [`MAX_POSE_CAPSULES`] poses × capsules.
pub(super) fn optimizer_bounds(
    settings: &Optimize,
    capsules: &[Capsule],
    poses: &[Pose],
) -> Vec<Problem> {
    let (count, span, what) = match settings.capsules {
        Some(count) => (count, settings.span, "asks for"),
        None => (
            capsules.len(),
            capsules.first().map_or(settings.span, |c| c.span),
            "starts from",
        ),
    };
    if count > MAX_OPTIMIZED_CAPSULES {
        return vec![Problem::error(
            codes::TOO_MANY_CAPSULES,
            format!(
                "`optimize` {what} {count} capsules; the most the optimizer places is \
                 {MAX_OPTIMIZED_CAPSULES}"
            ),
        )
        .with_label(span, "too many capsules")
        .with_help(format!(
            "ask for at most {MAX_OPTIMIZED_CAPSULES} capsules; the limit is fixed (docs/limits.md, \"Optimizer\")"
        ))];
    }
    let work = count.max(1).saturating_mul(poses.len());
    if work > MAX_POSE_CAPSULES {
        return vec![Problem::error(
            codes::TOO_MANY_CAPSULES,
            format!(
                "`optimize` would weigh {} poses × {} capsules = {work}; the most is \
                 {MAX_POSE_CAPSULES}",
                poses.len(),
                count.max(1)
            ),
        )
        .with_label(settings.span, "too much work")
        .with_help(format!(
            "ask for fewer capsules (`optimize capsules=`) or optimize fewer poses at once: at most \
             {MAX_POSE_CAPSULES} poses × capsules (docs/limits.md, \"Optimizer\")"
        ))];
    }
    Vec::new()
}
