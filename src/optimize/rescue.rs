//! The search's second chance: when no capsule count the heuristic tried meets every goal, random
//! starts of those counts, a few at a time, until one does.
//!
//! The heuristic follows one path per round, and which minimum a local solve reaches can turn
//! on the smallest change of the problem: moving 0.01 % of the fish's modelled plastic from solid
//! to sparse infill took it from meeting its goal to missing it by 4-90° at every count, at six
//! of nine such changes. Random starts reach its goal at one start in five to ten, so a few
//! rounds of them make the search's answer depend far less on that path.

use std::time::Instant;

use super::heuristic::Candidate;
use super::problem::{Outcome, Problem, StartCapsule};
use super::random_start::random_start;
use crate::objective::InteriorDistance;
use crate::parallel::map_each;
use crate::random::SplitMix64;

/// The most rounds of random starts the rescue runs.
pub const RESCUE_ROUNDS: usize = 4;

/// Random starts per capsule count in one round of the rescue.
pub const RESCUE_STARTS: usize = 2;

/// Mixed into the project's seed so that the rescue's starts are not the exhaustive ranking's.
const STREAM: u64 = 0x7265_7363_7565;

/// Whether `outcome` should replace a count's candidate `kept`: it meets every goal (and can be
/// printed), where `kept` does not or has a higher objective. A random start that misses a goal
/// replaces nothing: the heuristic's design, from the project's own seeds, stays the answer.
fn replaces(outcome: &Outcome, kept: &Outcome) -> bool {
    outcome.meets_goals && (!kept.meets_goals || outcome.value < kept.value)
}

/// When no candidate the answer may be taken from (every count, or only `wanted` when a count
/// is asked for) meets every goal, optimizes random starts ([`RESCUE_STARTS`] per capsule
/// count with a movable capsule, only the count `wanted` when one is asked for, the pinned
/// capsules of `seeds` kept) round by round, at most [`RESCUE_ROUNDS`] rounds, stopping after the
/// first round in which one of those counts meets every goal; a count's candidate is replaced by the
/// best of its random starts' outcomes that meet every goal, if any. `starting` hears each
/// round (from 1) and its number of starts as it starts. Deterministic for a given `seed`: a
/// round's starts are drawn before they are solved side by side. Returns the random starts
/// solved.
pub fn rescue(
    problem: &Problem,
    interior: &dyn InteriorDistance,
    seeds: &[StartCapsule],
    candidates: &mut [Candidate],
    wanted: Option<usize>,
    seed: u64,
    starting: &dyn Fn(usize, usize),
) -> usize {
    let pinned: Vec<StartCapsule> = seeds.iter().filter(|s| s.pinned).cloned().collect();
    // The counts the answer may be taken from: with a count asked for, only that one.
    let eligible = |c: &Candidate| wanted.is_none_or(|n| n == c.capsules);
    // Each such count with a movable capsule, with its own generator.
    let mut counts: Vec<(usize, usize, SplitMix64)> = candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| eligible(c))
        .filter_map(|(index, c)| {
            let free = c.capsules.checked_sub(pinned.len()).filter(|&f| f > 0)?;
            let stream = seed ^ STREAM ^ (c.capsules as u64).wrapping_mul(0x9e37_79b9);
            Some((index, free, SplitMix64::new(stream)))
        })
        .collect();
    let mut solved = 0;
    for round in 1..=RESCUE_ROUNDS {
        if counts.is_empty()
            || problem.is_cancelled()
            || candidates
                .iter()
                .any(|c| eligible(c) && c.outcome.meets_goals)
        {
            break;
        }
        let drawn: Vec<(usize, Vec<StartCapsule>)> = counts
            .iter_mut()
            .flat_map(|(index, free, random)| {
                (0..RESCUE_STARTS)
                    .map(|_| {
                        (
                            *index,
                            random_start(problem, interior, &pinned, *free, random),
                        )
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        starting(round, drawn.len());
        let clock = Instant::now();
        let outcomes = map_each(drawn.len(), |i| {
            (!problem.is_cancelled()).then(|| problem.optimize(&drawn[i].1))
        });
        // A round the cancellation reached is incomplete: what it found depends on when.
        if problem.is_cancelled() {
            break;
        }
        let seconds = clock.elapsed().as_secs_f64();
        solved += drawn.len();
        for ((index, start), outcome) in drawn.into_iter().zip(outcomes.into_iter().flatten()) {
            let candidate = &mut candidates[index];
            if replaces(&outcome, &candidate.outcome) {
                *candidate = Candidate {
                    capsules: candidate.capsules,
                    outcome,
                    starts: start,
                    seconds,
                };
            }
        }
    }
    solved
}
