//! The smooth maximum's bounds, the design vector's round trip, and finite results at degenerate
//! inputs.

mod balance_support;
mod geometry_support;
mod objective_support;

use balance_support::{rotation, stand};
use ballast::design::{Design, PlacedCapsule};
use ballast::objective::{smooth_max, smooth_min, DesignLayout, Objective, Parameters};
use ballast::random::SplitMix64;
use ballast::spec::model::Project;
use nalgebra::{Isometry3, Point3, Vector3};
use objective_support::*;

fn assert_finite(objective: &Objective, x: &[f64]) {
    let (value, gradient) = objective.value_and_gradient(x);
    assert!(value.is_finite(), "value {value}");
    assert!(
        gradient.iter().all(|g| g.is_finite()),
        "gradient {gradient:?}"
    );
    for (term, gradient) in objective.goal_terms(x) {
        assert!(term.is_finite(), "term {term}");
        assert!(
            gradient.iter().all(|g| g.is_finite()),
            "term gradient {gradient:?}"
        );
    }
    for (c, (value, gradient)) in objective.constraints(x).iter().enumerate() {
        assert!(value.is_finite(), "constraint {c}: {value}");
        assert!(
            gradient.iter().all(|g| g.is_finite()),
            "constraint {c}: {gradient:?}"
        );
    }
}

#[test]
fn the_smooth_max_bounds_the_max_and_tends_to_it() {
    let mut rng = SplitMix64::new(3);
    for _ in 0..20 {
        let values: Vec<f64> = (0..5).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let min = values.iter().copied().fold(f64::INFINITY, f64::min);
        let mut last = f64::INFINITY;
        for sharpness in [1.0, 10.0, 100.0, 1e3, 1e4, 1e6] {
            let smooth = smooth_max(&values, sharpness);
            assert!(smooth >= max, "{smooth} < {max}");
            assert!(smooth - max <= 5f64.ln() / sharpness + 1e-15);
            assert!(smooth <= last);
            last = smooth;
            assert!(smooth_min(&values, sharpness) <= min);
        }
        assert!((last - max).abs() <= 1e-5);
    }
}

#[test]
fn the_worst_goal_term_is_the_largest_term_and_can_be_met_where_f_is_not() {
    // Four poses alike, each standing with a goal met by 0.2°: every term is -0.2°, and their
    // smooth maximum lies above 0 by nearly ln(4)/α.
    let with_margin = |margin: f64| {
        let poses = (0..4)
            .map(|i| {
                let goals = vec![stand(margin)];
                named_pose(
                    &format!("p{i}"),
                    Isometry3::identity(),
                    vec![Isometry3::identity()],
                    goals,
                )
            })
            .collect();
        project_with(&["box"], poses)
    };
    let design = one_capsule(Point3::new(10.0, 20.0, 20.0), Point3::new(30.0, 40.0, 60.0));
    let objective_for = |project: &Project| {
        objective(
            project,
            &[tall_box()],
            &design,
            Parameters::for_project(project),
        )
    };
    let bare = objective_for(&with_margin(0.0));
    let x = bare.layout().to_vector(&design);
    let survives = -bare.goal_terms(&x)[0].0;
    assert!(survives > 0.1, "the box stands: {survives}");
    // Goal margins are in degrees.
    let project = with_margin(survives.to_degrees() - 0.2);
    let objective = objective_for(&project);
    let terms: Vec<f64> = objective.goal_terms(&x).iter().map(|t| t.0).collect();
    let worst = objective.worst_goal_term(&x);
    assert_eq!(
        worst,
        terms.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    );
    assert!(
        (worst.to_degrees() + 0.2).abs() < 1e-9,
        "{}",
        worst.to_degrees()
    );
    let f = objective.value(&x);
    let sharpness = objective.parameters().goal_sharpness;
    assert!(
        f > 0.0 && f <= worst + 4f64.ln() / sharpness + 1e-12,
        "f {f}, worst {worst}"
    );
    // Without goals, no term: nothing is missed.
    let none = objective_for(&project_with(&["box"], vec![]));
    assert_eq!(none.worst_goal_term(&x), f64::NEG_INFINITY);
}

#[test]
fn the_smooth_max_does_not_overflow() {
    let values: [f64; 4] = [1e3, 999.0, -1e3, 0.0];
    let smooth = smooth_max(&values, 100.0);
    assert!((smooth - 1e3).abs() < 1e-10, "{smooth}");
    assert_eq!(smooth_max::<f64>(&[], 100.0), 0.0);
    assert_eq!(smooth_max(&[1.0, 2.0], 0.0), 2.0);
    assert_eq!(smooth_max(&[1.0, 2.0], f64::INFINITY), 2.0);
}

#[test]
fn the_design_vector_round_trips() {
    let mut project = project_with(&["box"], vec![]);
    project.infill.range = Some((0.2, 0.8));
    let design = Design {
        capsules: vec![PlacedCapsule {
            name: "c".to_string(),
            component: 0,
            from: Point3::new(1.0, 2.0, 3.0),
            to: Point3::new(4.0, 5.0, 6.0),
            radius: 3.0,
            ball_radius: 2.8,
        }],
        infill: 0.5,
    };
    let layout = DesignLayout::for_design(&project, &design);
    assert_eq!(layout.len(), 8);
    let x = layout.to_vector(&design);
    assert_eq!(x, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 3.0, 0.5]);
    assert_eq!(layout.to_design(&x, &project.ball, 1.0), design);
    // A short vector is padded with zeros; the ball never has a negative radius.
    let short = layout.to_design(&x[..5], &project.ball, 1.0);
    assert_eq!(short.capsules[0].radius, 0.0);
    assert_eq!(short.capsules[0].ball_radius, 0.0);
    assert_eq!(short.infill, 0.0);
}

/// A project of the box in `pose` with `goals`.
fn box_project(pose: Isometry3<f64>, goals: Vec<ballast::spec::model::Goal>) -> Project {
    project_with(
        &["box"],
        vec![named_pose("p", pose, vec![Isometry3::identity()], goals)],
    )
}

fn one_capsule(from: Point3<f64>, to: Point3<f64>) -> Design {
    Design {
        capsules: vec![PlacedCapsule {
            name: "c".to_string(),
            component: 0,
            from,
            to,
            radius: 4.0,
            ball_radius: 3.8,
        }],
        infill: 1.0,
    }
}

#[test]
fn a_zero_length_axis_gives_finite_results() {
    let project = box_project(
        Isometry3::identity(),
        vec![stand(1.0), suspend(Point3::new(20.0, 30.0, 100.0), 0)],
    );
    let point = Point3::new(20.0, 30.0, 40.0);
    let design = Design {
        capsules: vec![one_capsule(point, point).capsules[0].clone(); 2],
        infill: 1.0,
    };
    let objective = objective(
        &project,
        &[tall_box()],
        &design,
        Parameters::for_project(&project),
    );
    assert_finite(&objective, &objective.layout().to_vector(&design));
}

#[test]
fn a_centre_exactly_over_a_support_edge_gives_finite_results() {
    // The 40 × 40 × 40 cube on its edge: rotated 45° about x, the centre of mass lies exactly
    // above the line of contact.
    let project = project_with(
        &["cube"],
        vec![named_pose(
            "edge",
            rotation(Vector3::x(), 45.0),
            vec![Isometry3::identity()],
            vec![stand(0.0), balance_support::imbalance(0.0)],
        )],
    );
    let design = Design {
        capsules: vec![],
        infill: 1.0,
    };
    let cube = geometry_support::box_mesh(40.0, 40.0, 40.0);
    let objective = objective(
        &project,
        &[cube],
        &design,
        Parameters::for_project(&project),
    );
    assert_finite(&objective, &[]);
    let terms = objective.goal_terms(&[]);
    // On an edge it does not stand: the smooth stand objective is positive.
    assert!(terms[0].0 > 0.0, "{}", terms[0].0);
}

#[test]
fn strings_and_capsules_parallel_to_gravity_give_finite_results() {
    // arccos arguments of exactly +1 and −1: the centre straight below and straight above the
    // suspension point, and capsule axes exactly vertical (eq. 22).
    let vertical = one_capsule(Point3::new(20.0, 30.0, 20.0), Point3::new(20.0, 30.0, 80.0));
    for point in [
        Point3::new(20.0, 30.0, 200.0),
        Point3::new(20.0, 30.0, -200.0),
    ] {
        let project = box_project(Isometry3::identity(), vec![suspend(point, 0)]);
        let objective = objective(
            &project,
            &[tall_box()],
            &vertical,
            Parameters::for_project(&project),
        );
        assert_finite(&objective, &objective.layout().to_vector(&vertical));
    }
    // With the centre exactly on the suspension point, the angle is neutral (90°).
    let project = box_project(
        Isometry3::identity(),
        vec![suspend(Point3::new(20.0, 30.0, 50.0), 0)],
    );
    let empty = Design {
        capsules: vec![],
        infill: 1.0,
    };
    let objective = objective(
        &project,
        &[tall_box()],
        &empty,
        Parameters::for_project(&project),
    );
    assert_finite(&objective, &[]);
    let angle = objective.goal_terms(&[])[0].0 + 5f64.to_radians();
    assert!(
        (angle - std::f64::consts::FRAC_PI_2).abs() < 1e-9,
        "{angle}"
    );
}

#[test]
fn a_massless_model_and_odd_inputs_give_finite_results() {
    let mut project = box_project(
        Isometry3::identity(),
        vec![stand(0.0), immerse(1.0, 1.0, Some(1.0))],
    );
    project.infill.range = Some((0.0, 1.0));
    let design = one_capsule(Point3::new(20.0, 30.0, 20.0), Point3::new(20.0, 30.0, 80.0));
    let objective = objective(
        &project,
        &[tall_box()],
        &design,
        Parameters::for_project(&project),
    );
    // Zero infill, zero radius: no mass at all.
    let mut x = objective.layout().to_vector(&design);
    x[6] = 0.0;
    x[7] = 0.0;
    assert_finite(&objective, &x);
    // Too short and too long vectors are padded or cut.
    assert_finite(&objective, &x[..3]);
    let mut long = x.clone();
    long.extend([1.0, 2.0]);
    assert_eq!(objective.value(&long), objective.value(&x));
}

#[test]
fn the_constraints_are_counted_by_the_layout_and_the_goals() {
    // Two poses with the same immersion goal: eq. 5 in each, eq. 3 once.
    let goals = || vec![immerse(1.0, 2.0, Some(5.0))];
    let mut project = project_with(
        &["box"],
        vec![
            named_pose(
                "a",
                Isometry3::identity(),
                vec![Isometry3::identity()],
                goals(),
            ),
            named_pose(
                "b",
                rotation(Vector3::x(), 180.0),
                vec![Isometry3::identity()],
                goals(),
            ),
        ],
    );
    project.infill.range = Some((0.1, 1.0));
    let mut rng = SplitMix64::new(5);
    let design = Design {
        capsules: (0..3)
            .map(|_| {
                random_capsule(
                    &mut rng,
                    0,
                    Point3::origin(),
                    Point3::new(40.0, 60.0, 100.0),
                    false,
                )
            })
            .collect(),
        infill: 0.5,
    };
    let parameters = Parameters {
        axis_samples: 4,
        ..Parameters::for_project(&project)
    };
    let objective = objective(&project, &[tall_box()], &design, parameters);
    let x = objective.layout().to_vector(&design);
    // Per capsule 3 + one per pose; 3 pairs; infill 2; eq. 5 twice; eq. 3 once (2).
    let expected = 3 * (3 + 2) + 3 + 2 + 2 + 2;
    assert_eq!(objective.constraints(&x).len(), expected);
    // Moving the design does not change the count.
    let moved: Vec<f64> = x.iter().map(|v| v * 0.5).collect();
    assert_eq!(objective.constraints(&moved).len(), expected);
}

#[test]
fn an_immersion_without_capsules_gives_finite_results() {
    // The design the heuristic's last round reaches: no capsule, the infill fixed, so the
    // design vector is empty and the centre of mass can sit right on the centre of buoyancy.
    for infill in [1.0, 0.15, 0.0] {
        let mut project = box_project(Isometry3::identity(), vec![immerse(1.0, 1.0, Some(1.0))]);
        project.infill.value = infill;
        let empty = Design {
            capsules: vec![],
            infill,
        };
        let objective = objective(
            &project,
            &[tall_box()],
            &empty,
            Parameters::for_project(&project),
        );
        assert_finite(&objective, &[]);
        assert!(objective.value(&[]).is_finite(), "infill {infill}");
    }
}

#[test]
fn the_smooth_max_of_an_infinite_value_is_that_value() {
    assert_eq!(smooth_max(&[1.0, f64::INFINITY], 100.0), f64::INFINITY);
    assert_eq!(
        smooth_max(&[f64::NEG_INFINITY; 2], 100.0),
        f64::NEG_INFINITY
    );
    assert_eq!(smooth_max(&[f64::NEG_INFINITY, 1.0], 100.0), 1.0);
}

#[test]
fn the_smooth_mass_constraint_keeps_a_slack_inside_the_tolerance() {
    // The 40 × 60 × 100 mm box displaces 240 g of water: the smooth program keeps the mass a
    // thousandth of that (0.24 g) inside the goal's tolerance, at most half the tolerance. The
    // two mass constraints, τ' − r and τ' + r, sum to 2τ' whatever the residual r.
    for (tolerance, kept) in [(1.0, 1.0 - 0.24), (5.0, 5.0 - 0.24), (0.2, 0.1)] {
        let project = box_project(
            Isometry3::identity(),
            vec![immerse(1.0, 1.0, Some(tolerance))],
        );
        let empty = Design {
            capsules: vec![],
            infill: project.infill.value,
        };
        let objective = objective(
            &project,
            &[tall_box()],
            &empty,
            Parameters::for_project(&project),
        );
        let values = objective.constraint_values(&[]);
        let [.., below, above] = values[..] else {
            panic!("no mass constraints: {values:?}");
        };
        assert!(
            (below + above - 2.0 * kept).abs() < 1e-9,
            "tolerance {tolerance}: {below} + {above}, expected 2 × {kept}"
        );
    }
}
