//! The capsule-count heuristic of section 4.5: optimize from every seed, remove the capsules that
//! did not grow, reset the rest to their seeds, and repeat down to no capsules.

use std::sync::mpsc::{channel, Sender};
use std::thread::ScopedJoinHandle;
use std::time::Instant;

use super::problem::{Outcome, Problem, StartCapsule};
use crate::parallel::{cores, map_each};

/// A capsule grew when its optimized radius exceeds its starting radius by this factor.
const GROWTH: f64 = 1.1;

/// One capsule count the heuristic tried.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// Number of capsules, pinned ones included.
    pub capsules: usize,
    /// What the optimization reached.
    pub outcome: Outcome,
    /// What each capsule of the outcome's design started from, in design order (its origin and
    /// name; the ends and radius of the round's start).
    pub starts: Vec<StartCapsule>,
    /// Wall-clock seconds the optimization took. Not deterministic: reports leave it out.
    pub seconds: f64,
}

/// Where the heuristic stands, as it starts a local solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Round {
    /// The round, from 1.
    pub round: usize,
    /// The most rounds there can be (each round removes at least one capsule); it may fall as
    /// rounds remove more.
    pub most_rounds: usize,
    /// Capsules optimized in this round, pinned ones included.
    pub capsules: usize,
    /// The solve starting, from 1.
    pub solve: usize,
    /// The solves this round runs: from the seeds, from the previous round's result, and with one
    /// movable capsule left from each other seed alone.
    pub solves: usize,
}

/// Runs the heuristic from `seeds` (pinned capsules are kept in every round and never removed).
///
/// Each round solves the smooth program for the current capsules from their seeds (the paper's
/// reset) and, after the first round, also from where the previous round left them, keeping the
/// better solve (with one unpinned capsule left, also from each seed alone:
/// [`Problem::explore`]); then it marks the unpinned capsules whose radius did not grow by 10 %
/// in that solve, removes the least grown of them (at most half of the unpinned capsules, and
/// at least one even when none is marked) and starts the next round from the survivors' seeds.
/// Only the round's kept solve is refined into the design the judge weighs
/// ([`Problem::refine`]), beside the rounds that follow; when that design misses a goal, the
/// round's next best solve that reached another minimum ([`Problem::same_minimum`]) is refined
/// too and kept if it meets every goal (or has the lower objective). It stops after the round
/// with no
/// unpinned capsule left. With
/// `stop_at = Some(n)` it stops after the round with `n` capsules instead (seeds are split first
/// if there are fewer than `n`).
///
/// `starting` hears where the search stands as each local solve starts.
///
/// Returns one candidate per round, most capsules first; when the problem is cancelled, the
/// rounds finished before.
pub fn run(
    problem: &Problem,
    seeds: &[StartCapsule],
    stop_at: Option<usize>,
    starting: &dyn Fn(Round),
) -> Vec<Candidate> {
    let mut current = seeds.to_vec();
    if let Some(n) = stop_at {
        split_until(&mut current, n);
    }
    // The survivors of the previous round where that round's solve left them.
    let mut survivors_left: Option<Vec<StartCapsule>> = None;
    // Each round's refinement (the judge's corrections, stock balls, the exact check) needs
    // only that round's solve, and the next round only the solve too: the refinements run
    // beside the rounds that follow, at most one per core at a time (the next round waits for
    // whichever finishes first), and are collected in round order, so the candidates are those
    // of running everything one after another.
    let most_refining = cores();
    std::thread::scope(|scope| {
        let mut refining: Vec<Refining> = Vec::new();
        // Each refinement says here when it is done, by its round.
        let (done, finishing) = channel::<usize>();
        let mut finished: Vec<(usize, Option<Candidate>)> = Vec::new();
        let mut round = 0;
        loop {
            round += 1;
            let pinned = current.iter().filter(|c| c.pinned).count();
            let floor = stop_at.unwrap_or(0).max(pinned);
            let one_left = current.len() - pinned == 1;
            let (capsules, most_rounds) =
                (current.len(), round + current.len().saturating_sub(floor));
            // Survivors the last solve left where they started (none left to move) would only
            // repeat the solve from the seeds.
            let warm = survivors_left
                .take()
                .filter(|survivors| *survivors != current);
            // The round's solves are independent of each other: they run side by side on every
            // core, and are compared in the order of `starts`.
            let starts = round_starts(&current, warm.as_ref(), seeds, one_left);
            let solves = starts.len();
            for start in &starts {
                starting(Round {
                    round,
                    most_rounds,
                    capsules,
                    solve: start.solve,
                    solves,
                });
            }
            let clock = Instant::now();
            let mut explored = map_each(starts.len(), |i| problem.explore(&starts[i].capsules));
            if problem.is_cancelled() {
                break;
            }
            // Down to one movable capsule, every seed is tried on its own at little cost; the
            // round goes on with the capsules of the start kept.
            let mut best = 0;
            for (index, start) in starts.iter().enumerate().skip(1) {
                if explored[index].is_better_than(&explored[best]) {
                    best = index;
                    if start.alone {
                        current = start.capsules.clone();
                    }
                }
            }
            // The next best solve of the round, refined too when the kept one's refinement
            // misses a goal: the smooth program's order need not be the judge's. A solve that
            // reached the kept one's minimum is not another chance.
            let runner_up = (0..explored.len())
                .filter(|&i| i != best && !problem.same_minimum(&explored[i], &explored[best]))
                .reduce(|a, b| {
                    if explored[b].is_better_than(&explored[a]) {
                        b
                    } else {
                        a
                    }
                })
                .map(|i| (starts[i].capsules.clone(), explored[i].clone()));
            let chosen = explored.swap_remove(best);
            let growth: Vec<(usize, f64)> = current
                .iter()
                .zip(&chosen.design.capsules)
                .enumerate()
                .filter(|(_, (start, _))| !start.pinned)
                .map(|(j, (start, reached))| (j, reached.radius / start.radius))
                .collect();
            let reached: Vec<StartCapsule> = current
                .iter()
                .zip(&chosen.design.capsules)
                .map(|(start, reached)| StartCapsule {
                    from: reached.from,
                    to: reached.to,
                    radius: reached.radius,
                    ..start.clone()
                })
                .collect();
            while refining.len() >= most_refining {
                // Every running refinement holds a sender, and so does this loop: a message
                // always comes.
                let Ok(round) = finishing.recv() else { break };
                if let Some(at) = refining.iter().position(|r| r.round == round) {
                    finished.push((round, refining.swap_remove(at).join()));
                }
            }
            let explored_seconds = clock.elapsed().as_secs_f64();
            let done = Done(done.clone(), round);
            refining.push(Refining {
                round,
                starts: current.clone(),
                refined: scope.spawn(move || {
                    // Says the refinement is done when it returns or unwinds.
                    let _done = done;
                    let clock = Instant::now();
                    let mut outcome = problem.refine(&chosen);
                    let mut starts = None;
                    if let Some((other_starts, other)) = runner_up.filter(|_| !outcome.meets_goals)
                    {
                        let second = problem.refine(&other);
                        if second.meets_goals
                            || (!outcome.meets_goals && second.value < outcome.value)
                        {
                            outcome = second;
                            starts = Some(other_starts);
                        }
                    }
                    // A refinement the cancellation reached means nothing.
                    (!problem.is_cancelled()).then(|| Refined {
                        outcome,
                        starts,
                        seconds: explored_seconds + clock.elapsed().as_secs_f64(),
                    })
                }),
            });
            let floor = stop_at.unwrap_or(0);
            if growth.is_empty() || current.len() <= floor {
                break;
            }
            let gone = removed(&growth, current.len() - floor);
            let mut survivors = reached;
            for j in gone.into_iter().rev() {
                current.remove(j);
                survivors.remove(j);
            }
            survivors_left = Some(survivors);
        }
        finished.extend(refining.into_iter().map(|r| (r.round, r.join())));
        finished.sort_by_key(|&(round, _)| round);
        // The rounds finished before a cancellation.
        finished
            .into_iter()
            .map_while(|(_, candidate)| candidate)
            .collect()
    })
}

/// One start of a round's solves.
#[derive(Debug, Clone, PartialEq)]
struct RoundStart {
    /// The solve's number in the round, from 1.
    solve: usize,
    /// The capsules it starts from.
    capsules: Vec<StartCapsule>,
    /// Whether it is one unpinned seed alone beside the pinned capsules (not the round's own
    /// capsules): kept, it replaces them.
    alone: bool,
}

/// The starts of one round's solves, in the order they are compared: from `current` (the
/// round's capsules at their seeds), from where the last round left the survivors (`warm`), and
/// with one movable capsule left (`one_left`), from each unpinned seed alone beside the pinned
/// capsules. An alone start the same as `current` is left out; the starts are numbered from 1
/// in that order.
fn round_starts(
    current: &[StartCapsule],
    warm: Option<&Vec<StartCapsule>>,
    seeds: &[StartCapsule],
    one_left: bool,
) -> Vec<RoundStart> {
    let start = |solve, capsules: Vec<StartCapsule>, alone| RoundStart {
        solve,
        capsules,
        alone,
    };
    let mut starts = vec![start(1, current.to_vec(), false)];
    if let Some(warm) = warm {
        starts.push(start(2, warm.clone(), false));
    }
    if one_left {
        let pinned: Vec<StartCapsule> = current.iter().filter(|c| c.pinned).cloned().collect();
        for alone in seeds.iter().filter(|s| !s.pinned) {
            let mut capsules = pinned.clone();
            capsules.push(alone.clone());
            if capsules != current {
                starts.push(start(starts.len() + 1, capsules, true));
            }
        }
    }
    starts
}

/// Which capsules a round removes, in design order, from each unpinned capsule's index and
/// radius growth: the least grown of those that did not grow by [`GROWTH`], at most half of
/// them, at least one, and at most `most` (the capsules above the count to stop at).
fn removed(growth: &[(usize, f64)], most: usize) -> Vec<usize> {
    let mut order = growth.to_vec();
    order.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    let marked = order.iter().filter(|(_, g)| *g <= GROWTH).count();
    let half = (growth.len() / 2).max(1);
    let remove = marked.clamp(1, half).min(most);
    let mut gone: Vec<usize> = order[..remove].iter().map(|(j, _)| *j).collect();
    gone.sort_unstable();
    gone
}

/// Sends its round when dropped: a refinement's thread holds it, so the loop hears when the
/// refinement is done, whether it returned or unwound.
struct Done(Sender<usize>, usize);

impl Drop for Done {
    fn drop(&mut self) {
        // The loop may have stopped listening (all its refinements joined): nothing to say.
        let _ = self.0.send(self.1);
    }
}

/// A round whose chosen solve is being refined beside the rounds that follow.
struct Refining<'scope> {
    /// The round, counted from 1.
    round: usize,
    /// The round's start capsules.
    starts: Vec<StartCapsule>,
    /// The judged outcome; `None` when cancelled.
    refined: ScopedJoinHandle<'scope, Option<Refined>>,
}

/// A round's refinement, finished.
struct Refined {
    /// The judged design.
    outcome: Outcome,
    /// The start capsules it came from when they are not the round's: the runner-up's,
    /// refined after the kept solve's design missed a goal.
    starts: Option<Vec<StartCapsule>>,
    /// The round's wall-clock seconds.
    seconds: f64,
}

impl Refining<'_> {
    /// The round's candidate, once refined; `None` when the refinement was cancelled.
    fn join(self) -> Option<Candidate> {
        let refined = self
            .refined
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        refined.map(|refined| Candidate {
            capsules: self.starts.len(),
            outcome: refined.outcome,
            starts: refined.starts.unwrap_or(self.starts),
            seconds: refined.seconds,
        })
    }
}

/// The candidate to use: with `wanted = Some(n)`, the one with `n` capsules. Otherwise, among the
/// candidates that meet every goal, the one whose objective plus `tolerance_degrees` per capsule
/// is lowest: each capsule (a ball to buy, a cavity, perhaps a pause) must gain that much
/// objective to be worth making. When none meets every goal, the lowest objective. Ties go to
/// fewer capsules, then to the lower objective.
pub fn choose(candidates: &[Candidate], wanted: Option<usize>, tolerance_degrees: f64) -> usize {
    if let Some(n) = wanted {
        if let Some(i) = candidates.iter().position(|c| c.capsules == n) {
            return i;
        }
    }
    let per_capsule = tolerance_degrees.to_radians();
    let effort = |c: &Candidate| c.outcome.value + per_capsule * c.capsules as f64;
    let meeting = candidates
        .iter()
        .enumerate()
        .filter(|(_, c)| c.outcome.meets_goals)
        .min_by(|a, b| {
            effort(a.1)
                .total_cmp(&effort(b.1))
                .then(a.1.capsules.cmp(&b.1.capsules))
                .then(a.1.outcome.value.total_cmp(&b.1.outcome.value))
        });
    if let Some((i, _)) = meeting {
        return i;
    }
    candidates
        .iter()
        .enumerate()
        .min_by(|a, b| {
            a.1.outcome
                .value
                .total_cmp(&b.1.outcome.value)
                .then(a.1.capsules.cmp(&b.1.capsules))
        })
        .map_or(0, |(i, _)| i)
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
        // Both halves keep the seed's name and origin: that is where they came from.
        let half = |centre| StartCapsule {
            from: centre - quarter / 2.0,
            to: centre + quarter / 2.0,
            ..seed.clone()
        };
        seeds[i] = half(nalgebra::center(&seed.from, &middle));
        seeds.insert(i + 1, half(nalgebra::center(&middle, &seed.to)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::test_meshes::outcome;

    fn candidate(capsules: usize, degrees: f64, meets_goals: bool) -> Candidate {
        Candidate {
            capsules,
            outcome: outcome(Vec::new(), degrees.to_radians(), meets_goals),
            starts: Vec::new(),
            seconds: 0.0,
        }
    }

    #[test]
    fn each_capsule_must_gain_the_tolerance_to_be_chosen() {
        let candidates = [
            candidate(4, -9.0, true),
            candidate(2, -8.5, true),
            candidate(1, -7.0, true),
            candidate(0, 5.0, false),
        ];
        // At 1° a capsule: 2 capsules gain 1.5° over 1, 4 gain only 0.5° more over 2.
        assert_eq!(choose(&candidates, None, 1.0), 1);
        // At 2.5° a capsule, the second is not worth it.
        assert_eq!(choose(&candidates, None, 2.5), 2);
        // At 0.1°, every gain is.
        assert_eq!(choose(&candidates, None, 0.1), 0);
        assert_eq!(choose(&candidates, Some(4), 1.0), 0);
        // Five capsules 2.4° better than one, which meets every goal already: not worth four more.
        let t_shape = [candidate(5, -9.9, true), candidate(1, -7.5, true)];
        assert_eq!(choose(&t_shape, None, 1.0), 1);
        // A tie goes to fewer capsules.
        let tie = [candidate(3, -3.0, true), candidate(2, -2.0, true)];
        assert_eq!(choose(&tie, None, 1.0), 1);
    }

    #[test]
    fn a_design_that_misses_a_goal_is_chosen_only_when_none_meets_them_all() {
        let some = [candidate(3, -9.0, false), candidate(1, -2.0, true)];
        assert_eq!(choose(&some, None, 1.0), 1);
        let none = [candidate(3, 4.0, false), candidate(1, 2.0, false)];
        assert_eq!(choose(&none, None, 1.0), 1);
    }

    #[test]
    fn a_round_removes_the_least_grown_of_the_marked_at_most_half() {
        // Two did not grow by 10 %: both go (half of four).
        let growth = [(0, 1.0), (1, 2.0), (2, 1.05), (3, 3.0)];
        assert_eq!(removed(&growth, 4), vec![0, 2]);
        // Three marked of four: still only half.
        let growth = [(0, 1.0), (1, 0.5), (2, 1.05), (3, 3.0)];
        assert_eq!(removed(&growth, 4), vec![0, 1]);
        // None marked: the least grown goes all the same.
        assert_eq!(removed(&[(0, 2.0), (1, 1.5)], 2), vec![1]);
        // No more than the capsules above the count to stop at.
        assert_eq!(
            removed(&[(0, 1.0), (1, 1.0), (2, 1.0), (3, 1.0)], 1),
            vec![0]
        );
    }

    #[test]
    fn a_round_with_one_capsule_left_starts_from_every_other_seed_alone() {
        let capsule = |x: f64, pinned| StartCapsule {
            component: 0,
            from: nalgebra::Point3::new(x, 0.0, 0.0),
            to: nalgebra::Point3::new(x, 0.0, 8.0),
            radius: 1.0,
            pinned,
            name: None,
            origin: crate::optimize::Origin::Written,
        };
        let seeds = [capsule(0.0, true), capsule(1.0, false), capsule(2.0, false)];
        let current = vec![capsule(0.0, true), capsule(1.0, false)];
        let warm = vec![capsule(0.0, true), capsule(1.5, false)];
        let starts = round_starts(&current, Some(&warm), &seeds, true);
        let numbers: Vec<usize> = starts.iter().map(|s| s.solve).collect();
        // The first seed alone is the current start: left out.
        assert_eq!(numbers, vec![1, 2, 3]);
        assert_eq!(
            starts[2].capsules,
            vec![capsule(0.0, true), capsule(2.0, false)]
        );
        let alone: Vec<bool> = starts.iter().map(|s| s.alone).collect();
        assert_eq!(alone, vec![false, false, true]);
        // With more than one movable capsule, only the two starts.
        assert_eq!(round_starts(&current, Some(&warm), &seeds, false).len(), 2);
        assert_eq!(round_starts(&current, None, &seeds, false).len(), 1);
    }

    #[test]
    fn splitting_seeds_keeps_pinned_ones_and_reaches_the_count() {
        let seed = |pinned| StartCapsule {
            component: 0,
            from: nalgebra::Point3::new(0.0, 0.0, 0.0),
            to: nalgebra::Point3::new(0.0, 0.0, 8.0),
            radius: 1.0,
            pinned,
            name: None,
            origin: crate::optimize::Origin::Written,
        };
        let mut seeds = vec![seed(true), seed(false)];
        split_until(&mut seeds, 4);
        assert_eq!(seeds.len(), 4);
        assert!(seeds[0].pinned);
        assert_eq!(seeds.iter().filter(|s| s.pinned).count(), 1);
        let mut only_pinned = vec![seed(true)];
        split_until(&mut only_pinned, 3);
        assert_eq!(only_pinned.len(), 1);
    }
}
