//! More capsules start from fewer: a capsule count whose design misses a goal, where the next
//! smaller count's design meets every goal, is solved again from that design with the capsules
//! it lacks added small.
//!
//! The heuristic's rounds go from many capsules to few, and a round's solves start from the
//! seeds: where those starts lead nowhere (the fish's three capsules ended 86° off its goal
//! while its two met it), the larger count's candidate says nothing of what that many capsules
//! can do. A design with more capsules can do at least what one with fewer does, its extra
//! capsules at the smallest radius carrying almost no mass; solved from there, the larger count
//! starts where the smaller one meets every goal.

use std::time::Instant;

use super::heuristic::Candidate;
use super::problem::{Outcome, Problem, StartCapsule};
use crate::parallel::map_each;

/// Whether `outcome` is a better design for its count than `kept`: it meets every goal where
/// `kept` does not, or, both meeting them or both missing, it has the lower objective.
fn replaces(outcome: &Outcome, kept: &Outcome) -> bool {
    (outcome.meets_goals, -outcome.value) > (kept.meets_goals, -kept.value)
}

/// The start of count `larger` from the design of count `smaller`: `smaller`'s capsules where
/// its design has them (pinned, named and of the origin its starts say), then each capsule of
/// `larger`'s starts that `smaller`'s starts do not hold (by component, origin and name) at
/// its start's axis with the radius `radius`. `None` when that is not `larger`'s count of
/// capsules (the two counts' starts are not one set and a part of it).
fn start_from(larger: &Candidate, smaller: &Candidate, radius: f64) -> Option<Vec<StartCapsule>> {
    let design = &smaller.outcome.design;
    if design.capsules.len() != smaller.starts.len() {
        return None;
    }
    let same = |a: &StartCapsule, b: &StartCapsule| {
        a.component == b.component && a.origin == b.origin && a.name == b.name
    };
    let mut start: Vec<StartCapsule> = smaller
        .starts
        .iter()
        .zip(&design.capsules)
        .map(|(started, placed)| StartCapsule {
            from: placed.from,
            to: placed.to,
            radius: placed.radius,
            ..started.clone()
        })
        .collect();
    let mut held = vec![false; smaller.starts.len()];
    for capsule in &larger.starts {
        let matched = smaller
            .starts
            .iter()
            .enumerate()
            .find(|&(i, s)| !held[i] && same(s, capsule));
        match matched {
            Some((i, _)) => held[i] = true,
            None => start.push(StartCapsule {
                radius: if capsule.pinned {
                    capsule.radius
                } else {
                    radius
                },
                ..capsule.clone()
            }),
        }
    }
    (start.len() == larger.capsules).then_some(start)
}

/// Each candidate to solve again and the one to start it from, as indices: one that misses a goal
/// where the candidate with the next fewer capsules meets every goal.
fn sources(candidates: &[Candidate]) -> Vec<(usize, usize)> {
    (0..candidates.len())
        .filter(|&k| !candidates[k].outcome.meets_goals)
        .filter_map(|k| {
            let count = candidates[k].capsules;
            let j = (0..candidates.len())
                .filter(|&j| candidates[j].capsules < count)
                .max_by_key(|&j| candidates[j].capsules)?;
            candidates[j].outcome.meets_goals.then_some((k, j))
        })
        .collect()
}

/// Solves again each candidate that misses a goal where the candidate with the next fewer
/// capsules meets every goal, from that design (`start_from`, the added capsules at the
/// smallest radius the smooth program allows), and replaces the candidate with the outcome when
/// that is better (`replaces`). Only from the next count: the fish's five capsules from its
/// two (three seeds added) missed by 58° after a judged design costing a third of its build.
/// The solves run side by side; deterministic. `starting` hears how many there are before they
/// start. Returns the solves run.
pub fn backfill(
    problem: &Problem,
    candidates: &mut [Candidate],
    starting: &dyn Fn(usize),
) -> usize {
    let radius = problem.parameters().min_radius;
    let starts: Vec<(usize, Vec<StartCapsule>)> = sources(candidates)
        .into_iter()
        .filter_map(|(k, j)| Some((k, start_from(&candidates[k], &candidates[j], radius)?)))
        .collect();
    if starts.is_empty() || problem.is_cancelled() {
        return 0;
    }
    starting(starts.len());
    let clock = Instant::now();
    let outcomes = map_each(starts.len(), |i| {
        (!problem.is_cancelled()).then(|| problem.optimize_near(&starts[i].1))
    });
    // Solves the cancellation reached mean nothing.
    if problem.is_cancelled() {
        return 0;
    }
    let seconds = clock.elapsed().as_secs_f64();
    for ((k, start), outcome) in starts.iter().zip(outcomes.into_iter().flatten()) {
        let candidate = &mut candidates[*k];
        if replaces(&outcome, &candidate.outcome) {
            *candidate = Candidate {
                capsules: candidate.capsules,
                outcome,
                starts: start.clone(),
                seconds,
            };
        }
    }
    starts.len()
}

#[cfg(test)]
mod tests {
    use nalgebra::Point3;

    use super::*;
    use crate::design::PlacedCapsule;
    use crate::optimize::test_meshes::outcome;
    use crate::optimize::Origin;

    fn seed(site: usize, x: f64) -> StartCapsule {
        StartCapsule {
            component: 0,
            from: Point3::new(x, 0.0, 0.0),
            to: Point3::new(x, 0.0, 8.0),
            radius: 2.0,
            pinned: false,
            name: None,
            origin: Origin::Skeleton(site),
        }
    }

    fn candidate(starts: Vec<StartCapsule>, value: f64, meets_goals: bool) -> Candidate {
        let capsules = starts
            .iter()
            .map(|s| PlacedCapsule {
                name: String::new(),
                component: s.component,
                from: s.from + nalgebra::Vector3::new(0.5, 0.0, 0.0),
                to: s.to,
                radius: 3.0,
                ball_radius: 2.5,
            })
            .collect();
        Candidate {
            capsules: starts.len(),
            outcome: outcome(capsules, value, meets_goals),
            starts,
            seconds: 0.0,
        }
    }

    #[test]
    fn a_larger_count_starts_from_the_smaller_design_and_its_missing_seeds_made_small() {
        let larger = candidate(vec![seed(0, 0.0), seed(1, 10.0), seed(2, 20.0)], 1.5, false);
        let smaller = candidate(vec![seed(2, 20.0)], -0.1, true);
        let start = start_from(&larger, &smaller, 0.25).expect("one set and a part of it");
        assert_eq!(start.len(), 3);
        // The smaller design's capsule where its design has it, origin kept.
        assert_eq!(start[0].origin, Origin::Skeleton(2));
        assert_eq!(start[0].from, Point3::new(20.5, 0.0, 0.0));
        assert_eq!(start[0].radius, 3.0);
        // The seeds it lacks, on their own axes, at the small radius.
        assert_eq!(start[1].origin, Origin::Skeleton(0));
        assert_eq!(start[2].origin, Origin::Skeleton(1));
        assert_eq!(start[2].from, Point3::new(10.0, 0.0, 0.0));
        assert!(start[1..].iter().all(|c| c.radius == 0.25));
        // Counts whose starts are not one set and a part of it give no start.
        let other = candidate(vec![seed(5, 0.0), seed(6, 5.0)], -0.2, true);
        assert!(start_from(&larger, &other, 0.25).is_none());
    }

    #[test]
    fn only_a_count_missing_where_the_next_fewer_meets_every_goal_is_solved_again() {
        let count =
            |n: usize, meets| candidate((0..n).map(|i| seed(i, i as f64)).collect(), 0.0, meets);
        // Most capsules first, as the heuristic lists them.
        let candidates = [
            count(5, false),
            count(3, false),
            count(2, true),
            count(1, false),
            count(0, false),
        ];
        assert_eq!(sources(&candidates), vec![(1, 2)]);
        let all_met = [count(4, true), count(2, true), count(1, true)];
        assert!(sources(&all_met).is_empty());
        let none_met = [count(2, false), count(1, false), count(0, false)];
        assert!(sources(&none_met).is_empty());
    }

    #[test]
    fn a_design_meeting_every_goal_or_lower_replaces_one_that_misses() {
        let at = |value, meets| outcome(Vec::new(), value, meets);
        assert!(replaces(&at(2.0, true), &at(-1.0, false)));
        assert!(!replaces(&at(-1.0, false), &at(2.0, true)));
        assert!(replaces(&at(-1.0, true), &at(-0.5, true)));
        assert!(replaces(&at(30.0, false), &at(60.0, false)));
        assert!(!replaces(&at(60.0, false), &at(60.0, false)));
    }
}
