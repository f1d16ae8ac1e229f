//! Exhaustive search as in the paper's Table 1: many random starts per capsule count, to rank
//! the heuristic's result against.

use serde::Serialize;

use super::heuristic::Candidate;
use super::problem::{Problem, StartCapsule};
use super::random_start::random_start;
use crate::objective::InteriorDistance;
use crate::parallel::map_each;
use crate::random::SplitMix64;

/// The random starts for one capsule count and where the heuristic's result ranks among them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ranking {
    /// Number of capsules (pinned ones included).
    pub capsules: usize,
    /// Random starts optimized.
    pub starts: usize,
    /// The lowest objective any random start reached, degrees.
    pub best_objective: f64,
    /// The worst stand tilt margin of that best start, degrees.
    pub best_tilt_margin: Option<f64>,
    /// How many random starts met every goal.
    pub meeting_goals: usize,
    /// The heuristic's objective for this count, degrees.
    pub heuristic_objective: f64,
    /// 1 + the number of random starts that reached a lower objective than the heuristic.
    pub rank: usize,
}

/// Optimizes `starts` random initialisations for every capsule count the heuristic tried (its
/// `candidates`), keeping the pinned capsules of `seeds`, and ranks the heuristic's objective
/// among them. Deterministic for a given `seed`.
pub fn rank(
    problem: &Problem,
    interior: &dyn InteriorDistance,
    seeds: &[StartCapsule],
    candidates: &[Candidate],
    starts: usize,
    seed: u64,
) -> Vec<Ranking> {
    let pinned: Vec<StartCapsule> = seeds.iter().filter(|s| s.pinned).cloned().collect();
    let mut rankings = Vec::new();
    for candidate in candidates {
        let Some(free) = candidate.capsules.checked_sub(pinned.len()) else {
            continue;
        };
        if free == 0 {
            continue;
        }
        let mut random = SplitMix64::new(seed ^ (candidate.capsules as u64).wrapping_mul(0x9e37));
        let mut values = Vec::with_capacity(starts);
        let mut best: Option<(f64, Option<f64>)> = None;
        let mut meeting_goals = 0;
        // Every start drawn first, in the generator's order; then solved side by side on every
        // core (each solve depends only on its start, so the ranking is the same on any count).
        let drawn: Vec<Vec<StartCapsule>> = (0..starts)
            .map(|_| random_start(problem, interior, &pinned, free, &mut random))
            .collect();
        // Once cancelled (Ctrl-C, the time limit), the starts not yet begun are skipped: each
        // would still be set up and judged, seconds over thousands of starts.
        let outcomes = map_each(drawn.len(), |i| {
            (!problem.is_cancelled()).then(|| problem.optimize(&drawn[i]))
        });
        if problem.is_cancelled() {
            return rankings;
        }
        for outcome in outcomes.into_iter().flatten() {
            meeting_goals += usize::from(outcome.meets_goals);
            if best.is_none_or(|(v, _)| outcome.value < v) {
                best = Some((outcome.value, outcome.worst_tilt_margin));
            }
            values.push(outcome.value);
        }
        let heuristic_value = candidate.outcome.value;
        let (best_value, best_tilt_margin) = best.unwrap_or((f64::INFINITY, None));
        rankings.push(Ranking {
            capsules: candidate.capsules,
            starts,
            best_objective: best_value.to_degrees(),
            best_tilt_margin,
            meeting_goals,
            heuristic_objective: heuristic_value.to_degrees(),
            rank: 1 + values.iter().filter(|&&v| v < heuristic_value).count(),
        });
    }
    rankings
}
