//! Every smooth term and constraint's exact gradient against central finite differences, on
//! seeded random designs.

mod balance_support;
mod geometry_support;
mod objective_support;

use balance_support::{imbalance, rotation, stand};
use ballast::design::Design;
use ballast::objective::{smooth_max, Insertion, InteriorDistance, Objective, Parameters};
use ballast::random::SplitMix64;
use ballast::spec::model::{Print, Project, Units};
use nalgebra::{Isometry3, Point3, Vector3};
use num_dual::{Derivative, DualDVec64};
use objective_support::*;

/// Largest relative error allowed.
const TOLERANCE: f64 = 1e-6;

/// Odd seeds use the `fdm` mass model (solid shells, a shell around every capsule), even ones the
/// test projects' `uniform` one, so both are differentiated.
fn with_fdm_for_odd(project: &mut Project, seed: u64) {
    if seed % 2 == 1 {
        project.print = Print::defaults(Units::Millimetre);
    }
}

/// The box with three capsules, infill a variable, and a pose for every goal kind; the hanging
/// and floating goals ask for uniqueness, so their constraints are checked too.
fn box_case(seed: u64) -> (Project, Design, Objective) {
    let mut project = project_with(
        &["box"],
        vec![
            named_pose(
                "upright",
                Isometry3::identity(),
                vec![Isometry3::identity()],
                vec![stand(5.0), unique(immerse(1.0, 2.0, Some(5.0)))],
            ),
            named_pose(
                "tilted",
                rotation(Vector3::new(1.0, 1.0, 0.0), 35.0),
                vec![Isometry3::identity()],
                vec![imbalance(3.0)],
            ),
            named_pose(
                "hanging",
                rotation(Vector3::x(), 180.0),
                vec![Isometry3::identity()],
                vec![unique(suspend(Point3::new(20.0, 30.0, 100.0), 0))],
            ),
        ],
    );
    project.infill.range = Some((0.1, 1.0));
    with_fdm_for_odd(&mut project, seed);
    let mut rng = SplitMix64::new(seed);
    let capsules = (0..3)
        .map(|_| {
            random_capsule(
                &mut rng,
                0,
                Point3::origin(),
                Point3::new(40.0, 60.0, 100.0),
                false,
            )
        })
        .collect();
    let design = Design {
        capsules,
        infill: rng.uniform(0.2, 0.9),
    };
    let objective = objective(
        &project,
        &[tall_box()],
        &design,
        Parameters::for_project(&project),
    );
    (project, design, objective)
}

/// The two-part model, one capsule per part, the arm swung in one pose.
fn two_part_case(seed: u64) -> (Project, Design, Objective) {
    let mut project = project_with(
        &["base", "arm"],
        vec![
            named_pose(
                "straight",
                Isometry3::identity(),
                vec![Isometry3::identity(); 2],
                vec![stand(2.0), immerse(1.2, 1.0, None)],
            ),
            named_pose(
                "swung",
                Isometry3::identity(),
                vec![Isometry3::identity(), arm_swung(70.0)],
                vec![imbalance(1.0), suspend(Point3::new(10.0, 10.0, 80.0), 1)],
            ),
        ],
    );
    with_fdm_for_odd(&mut project, seed);
    let mut rng = SplitMix64::new(seed);
    let design = Design {
        capsules: vec![
            random_capsule(
                &mut rng,
                0,
                Point3::new(-2.0, -2.0, -2.0),
                Point3::new(22.0, 22.0, 22.0),
                false,
            ),
            random_capsule(
                &mut rng,
                1,
                Point3::new(2.0, 2.0, 20.0),
                Point3::new(18.0, 18.0, 80.0),
                false,
            ),
        ],
        infill: 1.0,
    };
    let objective = objective(
        &project,
        &two_parts(),
        &design,
        Parameters::for_project(&project),
    );
    (project, design, objective)
}

fn cases() -> Vec<(Project, Design, Objective)> {
    (1..=4)
        .map(box_case)
        .chain((11..=13).map(two_part_case))
        .collect()
}

#[test]
fn every_goal_term_matches_finite_differences() {
    let mut worst = 0.0f64;
    let mut kinds = 0;
    for (project, design, objective) in cases() {
        let x = objective.layout().to_vector(&design);
        let terms = objective.goal_terms(&x);
        let goals: Vec<&str> = project
            .poses
            .iter()
            .flat_map(|p| p.goals.iter().map(|g| g.value.keyword()))
            .collect();
        assert_eq!(terms.len(), goals.len());
        for (t, (value, gradient)) in terms.iter().enumerate() {
            assert!(value.is_finite());
            assert!(gradient.iter().any(|g| *g != 0.0), "{}: flat", goals[t]);
            let f = |x: &[f64]| objective.goal_terms(x)[t].0;
            let error = finite_difference_error(&f, &x, gradient, 1e-9);
            assert!(error <= TOLERANCE, "{}: relative error {error}", goals[t]);
            worst = worst.max(error);
            kinds += 1;
        }
    }
    assert!(kinds >= 20);
    eprintln!("goal terms: worst relative gradient error {worst:.2e} over {kinds} terms");
}

#[test]
fn the_combined_objective_matches_finite_differences() {
    let mut worst = 0.0f64;
    for (_, design, objective) in cases() {
        let x = objective.layout().to_vector(&design);
        let (value, gradient) = objective.value_and_gradient(&x);
        assert_eq!(value, objective.value(&x));
        let error = finite_difference_error(&|x| objective.value(x), &x, &gradient, 1e-9);
        assert!(error <= TOLERANCE, "relative error {error}");
        worst = worst.max(error);
    }
    eprintln!("combined objective: worst relative gradient error {worst:.2e}");
}

#[test]
fn the_smooth_max_matches_finite_differences() {
    let mut rng = SplitMix64::new(7);
    let mut worst = 0.0f64;
    for sharpness in [1.0, 10.0, 100.0, 1000.0] {
        let values: Vec<f64> = (0..6).map(|_| rng.uniform(-0.5, 0.5)).collect();
        let n = values.len();
        let duals: Vec<DualDVec64> = values
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                DualDVec64::new(
                    v,
                    Derivative::derivative_generic(nalgebra::Dyn(n), nalgebra::U1, i),
                )
            })
            .collect();
        let result = smooth_max(&duals, sharpness);
        let gradient: Vec<f64> = result
            .eps
            .unwrap_generic(nalgebra::Dyn(n), nalgebra::U1)
            .iter()
            .copied()
            .collect();
        assert!((gradient.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        let f = |v: &[f64]| smooth_max(v, sharpness);
        let error = finite_difference_error(&f, &values, &gradient, 1e-9);
        assert!(
            error <= TOLERANCE,
            "sharpness {sharpness}: relative error {error}"
        );
        worst = worst.max(error);
    }
    eprintln!("smooth max: worst relative gradient error {worst:.2e}");
}

/// Distance to the surface of the box [0,40]×[0,60]×[0,100], positive inside.
struct BoxInterior;

impl InteriorDistance for BoxInterior {
    fn distance(&self, _component: usize, point: &Point3<f64>) -> (f64, Vector3<f64>) {
        let faces = [
            (point.x, Vector3::x()),
            (40.0 - point.x, -Vector3::x()),
            (point.y, Vector3::y()),
            (60.0 - point.y, -Vector3::y()),
            (point.z, Vector3::z()),
            (100.0 - point.z, -Vector3::z()),
        ];
        faces
            .into_iter()
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .unwrap_or((0.0, Vector3::zeros()))
    }
}

/// Print directions that are no axis, one per component, and the first capsule left free (as a
/// pinned one is).
fn insertion(design: &Design) -> Insertion {
    let ups = [
        Vector3::new(0.3, -0.5, 0.8).normalize(),
        Vector3::new(-0.6, 0.2, 0.7).normalize(),
    ];
    Insertion {
        up: design
            .capsules
            .iter()
            .enumerate()
            .map(|(j, c)| (j > 0).then(|| ups[c.component % 2]))
            .collect(),
        clearance: 0.2,
        layer_height: 0.3,
        pause_clearance: 0.2,
        slack: 0.02,
    }
}

#[test]
fn the_insertion_constraint_is_the_rise_beyond_a_layer_long_window() {
    for (_, design, objective) in cases() {
        let x = objective.layout().to_vector(&design);
        let without = objective.constraint_values(&x);
        let insertion = insertion(&design);
        let with = objective.with_insertion(insertion.clone());
        let values = with.constraint_values(&x);
        let added = &values[without.len()..];
        assert_eq!(&values[..without.len()], &without[..]);
        let expected: Vec<f64> = design
            .capsules
            .iter()
            .zip(&insertion.up)
            .filter_map(|(c, up)| {
                let up = (*up)?;
                // u·(q − p) − (r − 3c + 2h + g + slack): the window
                // [z_P − r + 2b + h + g, z_Q + r − b] of the widest ball b = r − c is then at
                // least a layer and the slack long.
                Some(up.dot(&(c.to - c.from)) - (c.radius - 0.6 + 0.6 + 0.2 + 0.02))
            })
            .collect();
        assert_eq!(added.len(), expected.len());
        assert!(!added.is_empty());
        for (a, e) in added.iter().zip(&expected) {
            assert!((a - e).abs() < 1e-9, "{a} is not {e}");
        }
    }
}

#[test]
fn every_constraint_matches_finite_differences() {
    let mut worst = 0.0f64;
    let mut count = 0;
    for (i, (_, design, objective)) in cases().into_iter().enumerate() {
        // Every case carries the insertion constraints; the box cases also the interior hook of
        // eq. 15.
        let objective = objective.with_insertion(insertion(&design));
        let objective = if i < 4 {
            objective.with_interior(Box::new(BoxInterior))
        } else {
            objective
        };
        let x = objective.layout().to_vector(&design);
        let constraints = objective.constraints(&x);
        // The values with gradients (those of one or two capsules from dual numbers of their
        // own unknowns, the rest from dual numbers of every unknown) are the values alone, in
        // the same order (up to the last bits dual arithmetic rounds otherwise).
        let alone = objective.constraint_values(&x);
        assert_eq!(constraints.len(), alone.len(), "case {i}");
        for (c, ((with, _), alone)) in constraints.iter().zip(&alone).enumerate() {
            let close = (with - alone).abs() <= 1e-12 * alone.abs().max(1.0);
            assert!(close, "case {i}, constraint {c}: {with} against {alone}");
        }
        let values: Vec<Vec<f64>> = (0..x.len())
            .flat_map(|k| {
                let h = 1e-6 * x[k].abs().max(1.0);
                let mut plus = x.clone();
                let mut minus = x.clone();
                plus[k] += h;
                minus[k] -= h;
                [plus, minus]
            })
            .map(|y| objective.constraints(&y).into_iter().map(|c| c.0).collect())
            .collect();
        for (c, (value, gradient)) in constraints.iter().enumerate() {
            assert!(value.is_finite());
            let numeric: Vec<f64> = (0..x.len())
                .map(|k| {
                    let h = 1e-6 * x[k].abs().max(1.0);
                    (values[2 * k][c] - values[2 * k + 1][c]) / (2.0 * h)
                })
                .collect();
            let difference = gradient
                .iter()
                .zip(&numeric)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt();
            let scale = numeric.iter().map(|v| v * v).sum::<f64>().sqrt().max(1e-9);
            let error = difference / scale;
            assert!(error <= TOLERANCE, "constraint {c}: relative error {error}");
            worst = worst.max(error);
            count += 1;
        }
    }
    eprintln!("constraints: worst relative gradient error {worst:.2e} over {count} constraints");
}
