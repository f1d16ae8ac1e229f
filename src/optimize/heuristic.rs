//! The capsule-count heuristic of section 4.5: optimize from every seed, remove the capsules that
//! did not grow, reset the rest to their seeds, and repeat down to no capsules.

use std::time::Instant;

use super::problem::{Outcome, Problem, StartCapsule};

/// A capsule grew when its optimized radius exceeds its starting radius by this factor.
const GROWTH: f64 = 1.1;

/// One capsule count the heuristic tried.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// Number of capsules, pinned ones included.
    pub capsules: usize,
    /// What the optimization reached.
    pub outcome: Outcome,
    /// Wall-clock seconds the optimization took. Not deterministic: reports leave it out.
    pub seconds: f64,
}

/// Runs the heuristic from `seeds` (pinned capsules are kept in every round and never removed).
///
/// Each round optimizes the current capsules from their seeds (the paper's reset) and, after the
/// first round, also from where the previous round left them, keeping the better; then it marks the unpinned capsules
/// whose radius did not grow by 10 %, removes the least grown of them (at most half of the
/// unpinned capsules, and at least one even when none is marked) and starts the next round from
/// the survivors' seeds. It stops after the round with no unpinned capsule left. With
/// `stop_at = Some(n)` it stops after the round with `n` capsules instead (seeds are split first
/// if there are fewer than `n`).
///
/// Returns one candidate per round, most capsules first.
pub fn run(problem: &Problem, seeds: &[StartCapsule], stop_at: Option<usize>) -> Vec<Candidate> {
    let mut current = seeds.to_vec();
    if let Some(n) = stop_at {
        split_until(&mut current, n);
    }
    let mut candidates = Vec::new();
    // The survivors of the previous round where that round's optimization left them.
    let mut warm: Option<Vec<StartCapsule>> = None;
    loop {
        let clock = Instant::now();
        let mut outcome = problem.optimize(&current);
        if let Some(warm) = &warm {
            let resumed = problem.optimize(warm);
            if better(&resumed, &outcome) {
                outcome = resumed;
            }
        }
        let seconds = clock.elapsed().as_secs_f64();
        let growth: Vec<(usize, f64)> = current
            .iter()
            .zip(&outcome.design.capsules)
            .enumerate()
            .filter(|(_, (start, _))| !start.pinned)
            .map(|(j, (start, reached))| (j, reached.radius / start.radius))
            .collect();
        let reached: Vec<StartCapsule> = current
            .iter()
            .zip(&outcome.design.capsules)
            .map(|(start, reached)| StartCapsule {
                from: reached.from,
                to: reached.to,
                radius: reached.radius,
                ..start.clone()
            })
            .collect();
        candidates.push(Candidate {
            capsules: current.len(),
            outcome,
            seconds,
        });
        let floor = stop_at.unwrap_or(0);
        if growth.is_empty() || current.len() <= floor {
            break;
        }
        let mut order = growth.clone();
        order.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        let marked = order.iter().filter(|(_, g)| *g <= GROWTH).count();
        let most = (growth.len() / 2).max(1);
        let remove = marked.clamp(1, most).min(current.len() - floor);
        let mut gone: Vec<usize> = order[..remove].iter().map(|(j, _)| *j).collect();
        gone.sort_unstable();
        let mut survivors = reached;
        for j in gone.into_iter().rev() {
            current.remove(j);
            survivors.remove(j);
        }
        warm = Some(survivors);
    }
    candidates
}

/// The candidate to use: with `wanted = Some(n)`, the one with `n` capsules. Otherwise, among the
/// candidates that meet every goal, the one with the fewest capsules whose objective is within
/// `tolerance_degrees` of the best; when none meets every goal, the lowest objective. Ties go to
/// the lower objective, then to fewer capsules.
pub fn choose(candidates: &[Candidate], wanted: Option<usize>, tolerance_degrees: f64) -> usize {
    if let Some(n) = wanted {
        if let Some(i) = candidates.iter().position(|c| c.capsules == n) {
            return i;
        }
    }
    let lowest = |pool: &mut dyn Iterator<Item = (usize, &Candidate)>| {
        pool.min_by(|a, b| {
            a.1.outcome
                .value
                .total_cmp(&b.1.outcome.value)
                .then(a.1.capsules.cmp(&b.1.capsules))
        })
        .map(|(i, _)| i)
    };
    let meeting = || {
        candidates
            .iter()
            .enumerate()
            .filter(|(_, c)| c.outcome.meets_goals)
    };
    let Some(best) = lowest(&mut meeting()) else {
        return lowest(&mut candidates.iter().enumerate()).unwrap_or(0);
    };
    let threshold = candidates[best].outcome.value + tolerance_degrees.to_radians();
    meeting()
        .filter(|(_, c)| c.outcome.value <= threshold)
        .min_by(|a, b| {
            a.1.capsules
                .cmp(&b.1.capsules)
                .then(a.1.outcome.value.total_cmp(&b.1.outcome.value))
        })
        .map_or(best, |(i, _)| i)
}

/// Whether `a` is the better outcome: it meets every goal and `b` does not, or both or neither do
/// and `a` reached a lower objective.
fn better(a: &Outcome, b: &Outcome) -> bool {
    match (a.meets_goals, b.meets_goals) {
        (true, false) => true,
        (false, true) => false,
        _ => a.value < b.value,
    }
}

/// Splits the longest unpinned seed in two along its axis until there are `n` seeds (or none can
/// be split).
fn split_until(seeds: &mut Vec<StartCapsule>, n: usize) {
    while seeds.len() < n {
        let longest = seeds
            .iter()
            .enumerate()
            .filter(|(_, s)| !s.pinned)
            .max_by(|a, b| {
                let la = (a.1.to - a.1.from).norm();
                let lb = (b.1.to - b.1.from).norm();
                la.total_cmp(&lb).then(b.0.cmp(&a.0))
            })
            .map(|(i, _)| i);
        let Some(i) = longest else {
            return;
        };
        let seed = seeds[i].clone();
        let middle = nalgebra::center(&seed.from, &seed.to);
        let quarter = (seed.to - seed.from) / 4.0;
        let half = |centre| StartCapsule {
            from: centre - quarter / 2.0,
            to: centre + quarter / 2.0,
            name: None,
            ..seed.clone()
        };
        seeds[i] = half(nalgebra::center(&seed.from, &middle));
        seeds.insert(i + 1, half(nalgebra::center(&middle, &seed.to)));
    }
}
