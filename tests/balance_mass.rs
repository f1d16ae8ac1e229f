//! Mass and centre of mass of posed models against closed forms (paper eq. 7-13).

mod balance_support;
mod geometry_support;

use std::f64::consts::PI;

use balance_support::*;
use ballast::spec::model::Units;
use geometry_support::{box_mesh, icosphere, prism};
use nalgebra::{Isometry3, Point3, Vector3};

/// The 40 × 60 × 100 mm box [0,40]×[0,60]×[0,100].
fn tall_box() -> ballast::geometry::TriMesh {
    box_mesh(40.0, 60.0, 100.0)
}

#[test]
fn solid_box_mass_volume_and_centre() {
    let result = evaluate(
        &project(&["box"]),
        &[tall_box()],
        &design(vec![]),
        &rest_pose(1, vec![]),
    );
    // 240 cm³ of PLA.
    assert_close("volume", result.volume, 240_000.0, 1e-9);
    assert_close("mass", result.mass, 240.0 * PLA, 1e-9);
    assert_point("centre", result.centre_of_mass, [20.0, 30.0, 50.0], 1e-9);
}

#[test]
fn the_same_box_in_centimetres() {
    let mut project = project(&["box"]);
    project.units = Units::Centimetre;
    let result = evaluate(
        &project,
        &[box_mesh(4.0, 6.0, 10.0)],
        &design(vec![]),
        &rest_pose(1, vec![]),
    );
    assert_close("volume", result.volume, 240.0, 1e-12);
    assert_close("mass", result.mass, 240.0 * PLA, 1e-9);
    assert_point("centre", result.centre_of_mass, [2.0, 3.0, 5.0], 1e-12);
}

#[test]
fn sphere_mass_converges_to_the_closed_form() {
    let r = 10.0;
    let centre = Point3::new(1.0, -2.0, 3.0);
    let exact = PI * 4.0 / 3.0 * r * r * r * PLA / 1000.0;
    let mut last_error = f64::INFINITY;
    for levels in 1..=5 {
        let result = evaluate(
            &project(&["ball"]),
            &[icosphere(levels, r, centre)],
            &design(vec![]),
            &rest_pose(1, vec![]),
        );
        let error = (exact - result.mass) / exact;
        // Inscribed polyhedra are smaller than the sphere, and each subdivision gets closer
        // (the error shrinks about fourfold).
        assert!(error > 0.0, "level {levels}: relative error {error}");
        assert!(
            error < last_error / 3.5,
            "level {levels}: {error} vs {last_error}"
        );
        last_error = error;
        assert_point("centre", result.centre_of_mass, centre.into(), 1e-9);
    }
    assert!(last_error < 1e-3, "finest relative error {last_error}");
}

#[test]
fn cylinder_mass() {
    let (n, r, h) = (512, 10.0, 50.0);
    let result = evaluate(
        &project(&["cylinder"]),
        &[prism(n, r, h)],
        &design(vec![]),
        &rest_pose(1, vec![]),
    );
    let angle = 2.0 * PI / f64::from(n);
    let prism_volume = f64::from(n) / 2.0 * r * r * angle.sin() * h;
    assert_close("mass", result.mass, prism_volume * PLA / 1000.0, 1e-9);
    let cylinder = PI * r * r * h * PLA / 1000.0;
    assert!((result.mass - cylinder).abs() / cylinder < 1e-4);
    assert_point("centre", result.centre_of_mass, [0.0, 0.0, 25.0], 1e-9);
}

#[test]
fn capsule_volume_is_a_cylinder_plus_a_sphere() {
    let c = capsule(
        0,
        Point3::new(1.0, 2.0, 3.0),
        Point3::new(1.0, 8.0, 11.0),
        3.0,
        0.0,
    );
    // Axis length 10: π·3²·10 + 4/3·π·3³ = 90π + 36π.
    assert_close("capsule volume", c.volume(), 126.0 * PI, 1e-9);

    // An empty capsule (no ball) removes exactly that much material at its axis midpoint.
    let result = evaluate(
        &project(&["box"]),
        &[tall_box()],
        &design(vec![c]),
        &rest_pose(1, vec![]),
    );
    let material = 240_000.0 - 126.0 * PI;
    assert_close("mass", result.mass, material * PLA / 1000.0, 1e-9);
    let expected = [
        (240_000.0 * 20.0 - 126.0 * PI * 1.0) / material,
        (240_000.0 * 30.0 - 126.0 * PI * 5.0) / material,
        (240_000.0 * 50.0 - 126.0 * PI * 7.0) / material,
    ];
    assert_point("centre", result.centre_of_mass, expected, 1e-9);
    // The outer volume is unchanged.
    assert_close("volume", result.volume, 240_000.0, 1e-9);
}

/// A box with one vertical capsule (r = 5, from z = 20 to 80 at x = 10, y = 30) and a 4.5 mm ball:
/// mass and centre of mass at the given infill, by hand.
fn box_with_ball_by_hand(infill: f64) -> (f64, [f64; 3]) {
    let box_volume = 240_000.0;
    let void = PI * 25.0 * 60.0 + 4.0 / 3.0 * PI * 125.0;
    let material = PLA * infill * (box_volume - void) / 1000.0;
    let material_centre = [
        (box_volume * 20.0 - void * 10.0) / (box_volume - void),
        30.0,
        (box_volume * 50.0 - void * 50.0) / (box_volume - void),
    ];
    let ball = STEEL * 4.0 / 3.0 * PI * 4.5f64.powi(3) / 1000.0;
    // Upright, the ball lies at the lower end, touching the cap: z = 20 − (5 − 4.5).
    let ball_centre = [10.0, 30.0, 19.5];
    let mass = material + ball;
    let centre = [0, 1, 2].map(|i| (material * material_centre[i] + ball * ball_centre[i]) / mass);
    (mass, centre)
}

fn box_with_ball(infill: f64) -> ballast::balance::PoseEvaluation {
    let mut d = design(vec![capsule(
        0,
        Point3::new(10.0, 30.0, 20.0),
        Point3::new(10.0, 30.0, 80.0),
        5.0,
        4.5,
    )]);
    d.infill = infill;
    evaluate(&project(&["box"]), &[tall_box()], &d, &rest_pose(1, vec![]))
}

#[test]
fn box_with_a_capsule_and_ball() {
    let (mass, centre) = box_with_ball_by_hand(1.0);
    let result = box_with_ball(1.0);
    assert_close("mass", result.mass, mass, 1e-9);
    assert_point("centre", result.centre_of_mass, centre, 1e-9);
    assert_close(
        "ball mass",
        result.balls[0].mass,
        STEEL * ball_volume(4.5) / 1000.0,
        1e-12,
    );
}

#[test]
fn infill_scales_the_material_only() {
    let (mass, centre) = box_with_ball_by_hand(0.25);
    let result = box_with_ball(0.25);
    assert_close("mass", result.mass, mass, 1e-9);
    assert_point("centre", result.centre_of_mass, centre, 1e-9);
    // Less material, same ball: the centre moves towards the ball.
    let solid = box_with_ball(1.0);
    assert!(result.centre_of_mass[2] < solid.centre_of_mass[2]);
}

#[test]
fn the_design_infill_is_used_not_the_projects() {
    let mut project = project(&["box"]);
    project.infill.value = 0.5;
    let result = evaluate(
        &project,
        &[tall_box()],
        &design(vec![]),
        &rest_pose(1, vec![]),
    );
    assert_close("mass", result.mass, 240.0 * PLA, 1e-9);
}

/// A 20 mm cube base and a 10 × 10 × 60 arm standing on it, rest frame.
fn base_and_arm() -> Vec<ballast::geometry::TriMesh> {
    vec![
        box_mesh(20.0, 20.0, 20.0),
        box_mesh(10.0, 10.0, 60.0).transformed(&Isometry3::translation(5.0, 5.0, 20.0)),
    ]
}

#[test]
fn posed_two_part_model() {
    // The arm turned 90° about y around (10, 10, 25): its centroid (10, 10, 50) goes to
    // (10 + 25, 10, 25 − 0) = (35, 10, 25).
    let arm = rotation_about(Vector3::y(), 90.0, Point3::new(10.0, 10.0, 25.0));
    let result = evaluate(
        &project(&["base", "arm"]),
        &base_and_arm(),
        &design(vec![]),
        &pose(
            Isometry3::identity(),
            vec![Isometry3::identity(), arm],
            vec![],
        ),
    );
    let expected = [
        (8000.0 * 10.0 + 6000.0 * 35.0) / 14_000.0,
        10.0,
        (8000.0 * 10.0 + 6000.0 * 25.0) / 14_000.0,
    ];
    assert_point("centre", result.centre_of_mass, expected, 1e-9);
    assert_close("mass", result.mass, 14.0 * PLA, 1e-9);

    // The whole model then turned 90° about z and moved 100 along x: (x, y) → (100 − y, x).
    let whole = Isometry3::translation(100.0, 0.0, 0.0) * rotation(Vector3::z(), 90.0);
    let result = evaluate(
        &project(&["base", "arm"]),
        &base_and_arm(),
        &design(vec![]),
        &pose(whole, vec![Isometry3::identity(), arm], vec![]),
    );
    let moved = [100.0 - expected[1], expected[0], expected[2]];
    assert_point("moved centre", result.centre_of_mass, moved, 1e-9);
}

#[test]
fn a_capsule_moves_with_its_component() {
    // A capsule in the arm, along the arm's axis, with a ball: in the bent pose the axis is
    // horizontal, the ball undetermined at the midpoint (10, 10, 50) → world (35, 10, 25).
    let arm = rotation_about(Vector3::y(), 90.0, Point3::new(10.0, 10.0, 25.0));
    let c = capsule(
        1,
        Point3::new(10.0, 10.0, 30.0),
        Point3::new(10.0, 10.0, 70.0),
        3.0,
        2.5,
    );
    let result = evaluate(
        &project(&["base", "arm"]),
        &base_and_arm(),
        &design(vec![c.clone()]),
        &pose(
            Isometry3::identity(),
            vec![Isometry3::identity(), arm],
            vec![],
        ),
    );
    let void = c.volume();
    let ball = STEEL * ball_volume(2.5) / 1000.0;
    let material = PLA * (14_000.0 - void) / 1000.0;
    let mass = material + ball;
    assert_close("mass", result.mass, mass, 1e-9);
    // The void and the ball are both at the arm's centroid, world (35, 10, 25).
    let moment_x = PLA / 1000.0 * (8000.0 * 10.0 + 6000.0 * 35.0 - void * 35.0) + ball * 35.0;
    let moment_z = PLA / 1000.0 * (8000.0 * 10.0 + 6000.0 * 25.0 - void * 25.0) + ball * 25.0;
    assert_point(
        "centre",
        result.centre_of_mass,
        [moment_x / mass, 10.0, moment_z / mass],
        1e-9,
    );
}

/// A measured body (the box's material with the void already empty, as a sliced file deposits
/// it) weighs its deposit plus the ball: the void is not removed a second time and no shell is
/// added, whatever the infill; the outer volume stays the box's.
#[test]
fn a_measured_body_has_its_voids_already_empty() {
    let (mass, centre) = box_with_ball_by_hand(1.0);
    let box_volume = 240_000.0;
    let void = PI * 25.0 * 60.0 + 4.0 / 3.0 * PI * 125.0;
    let deposit = ballast::geometry::Region {
        volume: box_volume - void,
        centroid: Point3::new(
            (box_volume * 20.0 - void * 10.0) / (box_volume - void),
            30.0,
            (box_volume * 50.0 - void * 50.0) / (box_volume - void),
        ),
    };
    let mesh = tall_box();
    let bodies = [ballast::balance::ComponentBody::measured(
        &mesh,
        ballast::geometry::mass_properties(&mesh),
        deposit,
    )];
    let mut d = design(vec![capsule(
        0,
        Point3::new(10.0, 30.0, 20.0),
        Point3::new(10.0, 30.0, 80.0),
        5.0,
        4.5,
    )]);
    d.infill = 0.25;
    let result =
        ballast::balance::evaluate_pose(&project(&["box"]), &bodies, &d, &rest_pose(1, vec![]));
    assert_close("mass", result.mass, mass, 1e-9);
    assert_point("centre", result.centre_of_mass, centre, 1e-9);
    assert_close("volume", result.volume, box_volume, 1e-9);
}
