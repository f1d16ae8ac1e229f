//! The warnings about what a design does in its poses: goals the solid model meets and the
//! design breaks, poses that settle away from their written rotation, balls whose rest end cannot
//! be trusted, and other stable states of hanging and floating goals.

use super::{GoalName, Optimization};
use crate::balance::{
    evaluate_pose, BallRest, ComponentBody, GoalOutcome, PoseEvaluation, MAX_ENUMERATED_BALLS,
    SNAP_WARNING,
};
use crate::design::Design;
use crate::diagnostic::Problem;
use crate::spec::model::Project;

/// The goals the model without capsules, at `design`'s infill, meets in `poses` and `design`
/// does not (none when the design has no capsules).
pub(super) fn solid_goals_lost(
    project: &Project,
    bodies: &[ComponentBody],
    design: &Design,
    poses: &[PoseEvaluation],
) -> Vec<GoalName> {
    if design.capsules.is_empty() {
        return Vec::new();
    }
    let solid = Design {
        capsules: Vec::new(),
        infill: design.infill,
    };
    let mut lost = Vec::new();
    for (pose, evaluation) in project.poses.iter().zip(poses) {
        if evaluation.goals.iter().all(|goal| goal.met) {
            continue;
        }
        let solid_evaluation = evaluate_pose(project, bodies, &solid, pose);
        for (index, (with, without)) in evaluation
            .goals
            .iter()
            .zip(&solid_evaluation.goals)
            .enumerate()
        {
            if without.met && !with.met {
                lost.push(GoalName {
                    pose: pose.name.value.clone(),
                    goal: index,
                    kind: pose.goals[index].value.keyword(),
                });
            }
        }
    }
    lost
}

/// A warning per goal the design breaks that the model without capsules meets, saying, for an
/// optimized design that misses some goal, that no design the optimizer tried met them all.
pub(super) fn lost_goal_warnings(
    project: &Project,
    lost: &[GoalName],
    optimization: Option<&Optimization>,
) -> Vec<Problem> {
    let help = match optimization {
        Some(optimization) if !optimization.meets_goals => {
            "no design the optimizer tried meets every goal, and the one chosen (the lowest objective) gives this goal up: the build names the goals that conflict; remove or loosen one of them"
        }
        _ => "move or remove capsules, or let the optimizer place them (`optimize`)",
    };
    lost.iter()
        .filter_map(|name| {
            let pose = project.poses.iter().find(|p| p.name.value == name.pose)?;
            let goal = pose.goals.get(name.goal)?;
            Some(
                Problem::warning(
                    "ballast::design::loses_goal",
                    format!(
                        "in pose `{}`, the design does not meet the `{}` goal, which the model without capsules meets",
                        name.pose, name.kind
                    ),
                )
                .with_label(goal.span, "met without capsules")
                .with_help(help),
            )
        })
        .collect()
}

/// A warning for every pose that settling on the hull turned by more than [`SNAP_WARNING`]: the
/// written rotation puts no facet on the ground.
pub(super) fn settled_poses(project: &Project, poses: &[PoseEvaluation]) -> Vec<Problem> {
    let mut warnings = Vec::new();
    for (pose, evaluation) in project.poses.iter().zip(poses) {
        let Some(resting) = &evaluation.resting else {
            continue;
        };
        if resting.correction <= SNAP_WARNING {
            continue;
        }
        let [x, y, z] = resting.down;
        warnings.push(
            Problem::warning(
                "ballast::pose::settles",
                format!(
                    "pose `{}` puts no facet of the model's hull on the ground: it settles {:.2}° away, onto the facet facing {x:.6} {y:.6} {z:.6} ({} corners, area {:.4})",
                    pose.name.value, resting.correction, resting.corners, resting.area
                ),
            )
            .with_label(pose.name.span, "this pose is evaluated as it settles")
            .with_help(format!("to rest on that facet exactly, write `down {x:.6} {y:.6} {z:.6}` instead of the rotation; `ballast poses` lists the facets")),
        );
    }
    warnings
}

/// A warning for every ball whose rest end cannot be trusted in a pose, pointing at the capsule's
/// node when the project file has it.
pub(super) fn undetermined_balls(
    project: &Project,
    design: &Design,
    poses: &[PoseEvaluation],
) -> Vec<Problem> {
    let mut warnings = Vec::new();
    for (pose, evaluation) in project.poses.iter().zip(poses) {
        for (capsule, ball) in design.capsules.iter().zip(&evaluation.balls) {
            if ball.rest != BallRest::Undetermined {
                continue;
            }
            let mut warning = Problem::warning(
                "ballast::capsule::undetermined",
                format!(
                    "in pose `{}`, capsule `{}` is {:.1}° from horizontal, less than the ball's min-angle of {}°: its ball may rest anywhere along it",
                    pose.name.value, capsule.name, ball.elevation, project.ball.min_angle
                ),
            );
            if let Some(written) = project
                .capsules
                .iter()
                .find(|c| c.name.value == capsule.name)
            {
                warning = warning.with_label(written.span, "this capsule");
            }
            warnings.push(
                warning
                    .with_label(pose.name.span, "in this pose")
                    .with_help("tilt the capsule's axis, or the result in this pose assumes the ball in the middle"),
            );
        }
    }
    warnings
}

/// The other stable states one `other_state` warning lists before it only counts the rest.
const OTHER_STATES_LISTED: usize = 4;

/// A warning for every hanging or floating goal with stable states other than the wanted one,
/// listing them, when the goal does not ask for uniqueness (with `unique=#true` the goal fails
/// instead), and one for every goal whose enumeration of ball ends was cut.
pub(super) fn other_states(project: &Project, poses: &[PoseEvaluation]) -> Vec<Problem> {
    let mut warnings = Vec::new();
    for (pose, evaluation) in project.poses.iter().zip(poses) {
        for (goal, outcome) in pose.goals.iter().zip(&evaluation.goals) {
            let (verb, unique, equilibria) = match &outcome.outcome {
                GoalOutcome::Suspend {
                    unique, equilibria, ..
                } => ("hangs", *unique, equilibria),
                GoalOutcome::Immerse {
                    unique, equilibria, ..
                } => ("floats", *unique, equilibria),
                _ => continue,
            };
            let others: Vec<String> = equilibria.unwanted().map(|s| s.describe()).collect();
            if !unique && !others.is_empty() {
                let states = listed_states(&others);
                warnings.push(
                    Problem::warning(
                        "ballast::goal::other_state",
                        format!(
                            "in pose `{}`, the model also {verb} stably {states}",
                            pose.name.value,
                        ),
                    )
                    .with_label(goal.span, "this goal")
                    .with_help(format!(
                        "set `unique=#true` on the `{}` goal to have the optimizer remove other stable states",
                        goal.value.keyword()
                    )),
                );
            }
            if !equilibria.complete {
                warnings.push(
                    Problem::warning(
                        "ballast::goal::states_cut",
                        format!(
                            "in pose `{}`, more than {MAX_ENUMERATED_BALLS} balls can roll: only {} assignments of ball ends (at most two balls moved) were tried for other stable states",
                            pose.name.value, equilibria.assignments
                        ),
                    )
                    .with_label(goal.span, "this goal"),
                );
            }
        }
    }
    warnings
}

/// One other stable state as it describes itself; several as "in N other states: " and the
/// first [`OTHER_STATES_LISTED`] of them, then how many more.
fn listed_states(others: &[String]) -> String {
    if let [one] = others {
        return one.clone();
    }
    let listed = others.len().min(OTHER_STATES_LISTED);
    let mut text = format!(
        "in {} other states: {}",
        others.len(),
        others[..listed].join("; ")
    );
    if others.len() > listed {
        text += &format!("; and {} more", others.len() - listed);
    }
    text
}

#[cfg(test)]
mod tests {
    use super::listed_states;

    #[test]
    fn other_states_are_listed_in_one_line_and_counted_past_four() {
        let states: Vec<String> = (1..=6).map(|i| format!("{i}0.0° off")).collect();
        assert_eq!(listed_states(&states[..1]), "10.0° off");
        assert_eq!(
            listed_states(&states[..2]),
            "in 2 other states: 10.0° off; 20.0° off"
        );
        assert_eq!(
            listed_states(&states),
            "in 6 other states: 10.0° off; 20.0° off; 30.0° off; 40.0° off; and 2 more"
        );
    }
}
