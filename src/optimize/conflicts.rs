//! Why no design meets the goals: which goals cannot be met even alone, and which pairs of goals
//! can each be met but not together.

use std::sync::Arc;

use serde::Serialize;

use super::problem::{Problem, StartCapsule};
use super::solver::Method;
use crate::balance::PartPrints;
use crate::cancel::Cancel;
use crate::fabrication::PrintSetup;
use crate::geometry::TriMesh;
use crate::objective::GridInterior;
use crate::parallel::{cores, map_each};
use crate::spec::model::Project;

/// One goal of one pose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub struct GoalRef {
    /// Index of the pose, project order.
    pub pose: usize,
    /// Index of the goal within the pose.
    pub goal: usize,
}

/// A goal, or a pair of goals, that the optimizer cannot meet.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Conflict {
    /// One goal (unreachable even alone) or two (each reachable alone, not together).
    pub goals: Vec<GoalRef>,
    /// How far the best design for just these goals is from meeting them: its smooth objective,
    /// degrees (positive: short by about that much).
    pub shortfall: f64,
}

/// The most sets of goals [`explain`] optimizes; the sets past it are taken as met (so no
/// conflict is named without a solve showing it).
pub const MAX_EXPLANATION_SOLVES: usize = 24;

/// What [`explain`] found: the conflicts, and whether it was cut short.
#[derive(Debug, Clone, PartialEq)]
pub struct Explanation {
    /// The goals unreachable alone, then the pairs that conflict, in project order; when cut
    /// short, those found before (each shown by a solve that finished).
    pub conflicts: Vec<Conflict>,
    /// Whether the cancel flag stopped the explanation before it had looked at every set.
    pub cut_short: bool,
}

/// The design space a build searches, which the explanation searches too.
pub struct Space<'a> {
    /// The starts, each a design of the space (e.g. the capsule count asked for): the heuristic's
    /// designs and the seeds of their rounds.
    pub starts: &'a [Vec<StartCapsule>],
}

/// Explains why the goals `unmet` (of `project`) were not met by optimizing for smaller sets of
/// goals: first each goal of the project alone, then each unmet goal paired with every other goal
/// that can be met alone. Each set of goals is optimized from every start of `space` (designs of
/// exactly the space the build searched, such as the capsule count asked for), keeping the best,
/// each design judged as the solution file would hold it. Returns the goals unreachable alone,
/// then the pairs that conflict, in project order.
///
/// `achieved` holds, per printable design the search already judged, the goals it meets: a set
/// of goals within one of them is met without a solve. At most [`MAX_EXPLANATION_SOLVES`] sets
/// are optimized, in the order above. `solving` hears the number (from 1) of each solve as it
/// starts.
///
/// Soon after `cancel` is set it stops, keeping the conflicts that solves finished before it
/// showed, and says it was cut short.
#[allow(clippy::too_many_arguments)]
pub fn explain(
    project: &Project,
    meshes: &[TriMesh],
    prints: &PartPrints,
    print: &PrintSetup,
    interior: &Arc<GridInterior>,
    space: &Space,
    unmet: &[GoalRef],
    achieved: &[Vec<GoalRef>],
    cancel: &Cancel,
    solving: &dyn Fn(usize),
) -> Explanation {
    let all: Vec<GoalRef> = project
        .poses
        .iter()
        .enumerate()
        .flat_map(|(pose, p)| (0..p.goals.len()).map(move |goal| GoalRef { pose, goal }))
        .collect();
    let solves = std::cell::Cell::new(0);
    // `None` once cancelled: a solve cut short shows nothing.
    let attempt = |goals: &[GoalRef]| -> Option<(bool, f64)> {
        let known = achieved
            .iter()
            .any(|met| goals.iter().all(|goal| met.contains(goal)));
        if cancel.is_cancelled() {
            return None;
        }
        if known || solves.get() >= MAX_EXPLANATION_SOLVES {
            return Some((true, f64::NEG_INFINITY));
        }
        solves.set(solves.get() + 1);
        solving(solves.get());
        let only = with_only(project, goals);
        let problem = Problem::new(
            &only,
            meshes,
            prints,
            print.clone(),
            interior.clone(),
            Method::Hybrid,
        )
        .with_cancel(cancel.clone());
        // The starts are independent: solved side by side, as many at a time as there are
        // cores, and compared in order. Only whether a set is met, and how far the best design
        // falls short when none meets it, is used: once a batch holds a design that meets it,
        // the starts after that batch can change neither.
        let better = |a: &(bool, f64), b: &(bool, f64)| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1));
        let mut best: Option<(bool, f64)> = None;
        let batch = cores();
        for first in (0..space.starts.len()).step_by(batch) {
            let count = batch.min(space.starts.len() - first);
            let reached = map_each(count, |i| {
                let start = &space.starts[first + i];
                let written = problem.optimize(start);
                (written.meets_goals, written.value.to_degrees())
            });
            for result in reached {
                if best.is_none_or(|best| better(&result, &best).is_ge()) {
                    best = Some(result);
                }
            }
            if best.is_some_and(|(met, _)| met) || cancel.is_cancelled() {
                break;
            }
        }
        let best = best.unwrap_or((false, f64::INFINITY));
        (!cancel.is_cancelled()).then_some(best)
    };
    let mut alone: Vec<(GoalRef, bool, f64)> = Vec::with_capacity(all.len());
    let mut cut_short = false;
    for &goal in &all {
        let Some((met, value)) = attempt(&[goal]) else {
            cut_short = true;
            break;
        };
        alone.push((goal, met, value));
    }
    let mut conflicts: Vec<Conflict> = alone
        .iter()
        .filter(|(goal, met, _)| !met && unmet.contains(goal))
        .map(|&(goal, _, shortfall)| Conflict {
            goals: vec![goal],
            shortfall,
        })
        .collect();
    // Pairs are only tried once every goal was tried alone.
    let pairs = if cut_short { &[][..] } else { &alone[..] };
    'pairs: for &(goal, met, _) in pairs {
        if !met || !unmet.contains(&goal) {
            continue;
        }
        for &(other, other_met, _) in &alone {
            let seen = unmet.contains(&other) && other < goal;
            if other == goal || !other_met || seen {
                continue;
            }
            let pair = if other < goal {
                [other, goal]
            } else {
                [goal, other]
            };
            let Some((met, shortfall)) = attempt(&pair) else {
                cut_short = true;
                break 'pairs;
            };
            if !met {
                conflicts.push(Conflict {
                    goals: pair.to_vec(),
                    shortfall,
                });
            }
        }
    }
    Explanation {
        conflicts,
        cut_short,
    }
}

/// `project` with every goal but `goals` removed.
fn with_only(project: &Project, goals: &[GoalRef]) -> Project {
    let mut only = project.clone();
    for (pose, p) in only.poses.iter_mut().enumerate() {
        let kept = std::mem::take(&mut p.goals)
            .into_iter()
            .enumerate()
            .filter(|(goal, _)| goals.contains(&GoalRef { pose, goal: *goal }))
            .map(|(_, g)| g)
            .collect();
        p.goals = kept;
    }
    only
}
