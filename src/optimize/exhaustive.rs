//! Exhaustive search as in the paper's Table 1: many random starts per capsule count, to rank
//! the heuristic's result against.

use nalgebra::{Point3, Vector3};
use serde::Serialize;

use super::heuristic::Candidate;
use super::problem::{Origin, Problem, StartCapsule};
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
            .map(|_| {
                let mut start = pinned.clone();
                start.extend((0..free).map(|_| random_capsule(problem, interior, &mut random)));
                start
            })
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

/// A capsule of the smallest radius at a random point inside a random component (up to 64 tries
/// for a point with room for it), along a random direction, up to a sixth of the component's
/// bounding-box diagonal long.
fn random_capsule(
    problem: &Problem,
    interior: &dyn InteriorDistance,
    random: &mut SplitMix64,
) -> StartCapsule {
    let meshes = problem.meshes();
    let component = random.below(meshes.len().max(1));
    let radius = problem.parameters().min_radius;
    let room = radius + problem.project().wall;
    let (lo, hi) = meshes
        .get(component)
        .and_then(|m| m.bounding_box())
        .unwrap_or_default();
    let mut centre = nalgebra::center(&lo, &hi);
    for _ in 0..64 {
        let point = Point3::from(lo.coords + (hi - lo).component_mul(&random.vector()));
        if interior.distance(component, &point).0 > room {
            centre = point;
            break;
        }
    }
    let direction = loop {
        let v = random.vector() * 2.0 - Vector3::repeat(1.0);
        let norm = v.norm();
        if norm > 1e-3 && norm <= 1.0 {
            break v / norm;
        }
    };
    let half = radius.max((hi - lo).norm() / 12.0 * random.unit());
    StartCapsule::centred(component, centre, direction * half, radius, Origin::Random)
}
