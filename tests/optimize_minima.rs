//! Which solves of a round reached the same minimum of the smooth program
//! (`Problem::same_minimum`): the T's one-capsule round, solved from each of its seeds alone,
//! reaches two minima (the capsule along the crossbar tilted one way or the other), each from
//! several seeds.

mod optimize_support;

use ballast::optimize::{default_cell, StartCapsule};
use optimize_support::with_example_problem;

#[test]
fn solves_from_different_seeds_to_one_minimum_are_told_from_solves_to_another() {
    with_example_problem("t_shape", |problem, prepared| {
        let alone: Vec<Vec<StartCapsule>> =
            prepared.seeds.iter().map(|s| vec![s.clone()]).collect();
        assert!(alone.len() >= 4, "{} seeds", alone.len());
        let explored: Vec<_> = alone.iter().map(|start| problem.explore(start)).collect();
        // A solve is its own minimum, and a solve run again is the same.
        assert!(problem.same_minimum(&explored[0], &problem.explore(&alone[0])));
        let cell = default_cell(&problem.meshes()[0], problem.parameters().min_radius);
        let (mut same, mut different) = (0, 0);
        for (i, a) in explored.iter().enumerate() {
            assert!(problem.same_minimum(a, a));
            for b in &explored[i + 1..] {
                let verdict = problem.same_minimum(a, b);
                assert_eq!(verdict, problem.same_minimum(b, a));
                let (ca, cb) = (&a.design.capsules[0], &b.design.capsules[0]);
                let apart = (ca.from - cb.from)
                    .norm()
                    .max((ca.to - cb.to).norm())
                    .max((ca.radius - cb.radius).abs());
                if verdict {
                    same += 1;
                    assert!(apart <= cell, "{apart} mm apart, the grid's cell {cell}");
                } else {
                    different += 1;
                }
            }
        }
        // Pairs of different seeds reach each minimum; pairs across the two minima are told apart.
        assert!(same >= 2, "{same} pairs at one minimum");
        assert!(different >= 4, "{different} pairs at different minima");
    });
}
