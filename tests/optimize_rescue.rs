//! The search's second chance (`optimize::rescue`): random starts when no capsule count the
//! heuristic tried meets every goal. On the sheared cylinder, whose one capsule meets its goals
//! from almost any start, a heuristic that failed is simulated by marking its candidates as
//! missing their goals.

mod optimize_support;

use ballast::optimize::{rescue, run_heuristic, Candidate, Origin, RESCUE_ROUNDS, RESCUE_STARTS};
use optimize_support::with_example_problem;

/// The cylinder's candidates from the heuristic, then `check` run with them and a rescue of
/// candidates over its problem, interior and seeds.
fn with_cylinder(
    check: impl FnOnce(&mut Vec<Candidate>, &dyn Fn(&mut Vec<Candidate>, Option<usize>) -> usize),
) {
    with_example_problem("sheared_cylinder", |problem, prepared| {
        let seed = problem
            .project()
            .optimize
            .as_ref()
            .expect("an optimize node")
            .seed;
        let mut candidates = run_heuristic(problem, &prepared.seeds, None, &|_| {});
        let rescued = |candidates: &mut Vec<Candidate>, wanted: Option<usize>| {
            rescue(
                problem,
                prepared.interior.as_ref(),
                &prepared.seeds,
                candidates,
                wanted,
                seed,
                &|_, _| {},
            )
        };
        check(&mut candidates, &rescued);
    });
}

/// `candidates` as if the heuristic had found nothing meeting a goal: each marked as missing,
/// with an objective of 90°.
fn failed(candidates: &[Candidate]) -> Vec<Candidate> {
    candidates
        .iter()
        .cloned()
        .map(|mut c| {
            c.outcome.meets_goals = false;
            c.outcome.value = 90f64.to_radians();
            c
        })
        .collect()
}

#[test]
fn a_search_that_met_its_goals_is_left_alone() {
    with_cylinder(|candidates, rescued| {
        assert!(candidates.iter().any(|c| c.outcome.meets_goals));
        let before: Vec<f64> = candidates.iter().map(|c| c.outcome.value).collect();
        assert_eq!(rescued(candidates, None), 0);
        let after: Vec<f64> = candidates.iter().map(|c| c.outcome.value).collect();
        assert_eq!(before, after);
    });
}

#[test]
fn random_starts_replace_a_count_that_missed_and_stop_once_one_meets_every_goal() {
    with_cylinder(|candidates, rescued| {
        let counts: Vec<usize> = candidates.iter().map(|c| c.capsules).collect();
        assert_eq!(counts, vec![1, 0], "the cylinder's counts");
        let mut first = failed(candidates);
        // One count with a capsule to move: one round of its random starts.
        let solved = rescued(&mut first, None);
        assert!(
            solved == RESCUE_STARTS,
            "{solved} random starts, one round is {RESCUE_STARTS} (at most {RESCUE_ROUNDS} rounds)"
        );
        let one = &first[0];
        assert!(one.outcome.meets_goals, "{:?}", one.outcome.value);
        assert!(one.outcome.value < 0.0, "objective {}", one.outcome.value);
        assert!(one.starts.iter().all(|s| s.origin == Origin::Random));
        // The count without a capsule to move is left as it was.
        assert!(!first[1].outcome.meets_goals);
        // The same seed, the same design, bit for bit.
        let mut second = failed(candidates);
        rescued(&mut second, None);
        let ends = |c: &Candidate| -> Vec<[f64; 7]> {
            c.outcome
                .design
                .capsules
                .iter()
                .map(|k| {
                    [
                        k.from.x, k.from.y, k.from.z, k.to.x, k.to.y, k.to.z, k.radius,
                    ]
                })
                .collect()
        };
        assert_eq!(ends(&first[0]), ends(&second[0]));
        assert_eq!(
            first[0].outcome.design.infill,
            second[0].outcome.design.infill
        );
    });
}

#[test]
fn with_a_count_asked_for_only_that_count_decides_whether_to_rescue() {
    with_cylinder(|candidates, rescued| {
        // The one-capsule count missed; the count without capsules is marked as meeting every
        // goal. Asked for no particular count, a design meeting every goal exists: nothing to do.
        let mut some_met = failed(candidates);
        some_met[1].outcome.meets_goals = true;
        assert_eq!(rescued(&mut some_met.clone(), None), 0);
        // Asked for one capsule, that count's miss is what counts: its random starts are solved.
        assert_eq!(rescued(&mut some_met, Some(1)), RESCUE_STARTS);
        assert!(some_met[0].outcome.meets_goals);
    });
}
