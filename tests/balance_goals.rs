//! Suspension and immersion goals against hand computations (paper eq. 2-5).

mod balance_support;
mod geometry_support;

use std::f64::consts::PI;

use balance_support::*;
use ballast::balance::{GoalOutcome, PoseEvaluation};
use ballast::design::Design;
use ballast::geometry::TriMesh;
use ballast::spec::model::Goal;
use geometry_support::box_mesh;
use nalgebra::{Isometry3, Point3, Vector3};

fn suspend(x: f64, y: f64, z: f64, component: usize, tolerance: f64) -> Goal {
    Goal::Suspend {
        point: Point3::new(x, y, z),
        component,
        tolerance,
        unique: false,
    }
}

fn immerse(fluid_density: f64, min_distance: f64, tolerance: f64, mass: Option<f64>) -> Goal {
    Goal::Immerse {
        fluid_density,
        min_distance,
        tolerance,
        mass_tolerance: mass,
        unique: false,
    }
}

fn tall_box() -> TriMesh {
    box_mesh(40.0, 60.0, 100.0)
}

fn met(result: &PoseEvaluation) -> Vec<bool> {
    result.goals.iter().map(|goal| goal.met).collect()
}

/// The suspension angle and point of goal `i`.
fn suspension(result: &PoseEvaluation, i: usize) -> (f64, [f64; 3]) {
    match &result.goals[i].outcome {
        GoalOutcome::Suspend { angle, point, .. } => (*angle, *point),
        other => panic!("expected a suspend outcome, got {other:?}"),
    }
}

#[test]
fn hanging_from_above_the_centre_hangs_straight() {
    let result = evaluate(
        &project(&["box"]),
        &[tall_box()],
        &design(vec![]),
        &rest_pose(1, vec![suspend(20.0, 30.0, 100.0, 0, 0.5)]),
    );
    let (angle, point) = suspension(&result, 0);
    assert_close("angle", angle, 0.0, 1e-6);
    assert_eq!(point, [20.0, 30.0, 100.0]);
    assert!(result.goals[0].met);
}

#[test]
fn hanging_from_a_corner_edge_leans_by_the_offset() {
    // From (0, 30, 100) the centre (20, 30, 50) is 20 across and 50 down.
    let result = evaluate(
        &project(&["box"]),
        &[tall_box()],
        &design(vec![]),
        &rest_pose(
            1,
            vec![
                suspend(0.0, 30.0, 100.0, 0, 21.0),
                suspend(0.0, 30.0, 100.0, 0, 22.0),
            ],
        ),
    );
    let (angle, _) = suspension(&result, 0);
    assert_close("angle", angle, 20f64.atan2(50.0).to_degrees(), 1e-9);
    // atan(0.4) = 21.8°.
    assert_eq!(met(&result), vec![false, true]);
}

#[test]
fn hanging_upside_down_is_the_worst_angle() {
    // The point below the centre of mass: the string would point up.
    let result = evaluate(
        &project(&["box"]),
        &[tall_box()],
        &design(vec![]),
        &rest_pose(1, vec![suspend(20.0, 30.0, 0.0, 0, 179.0)]),
    );
    let (angle, _) = suspension(&result, 0);
    assert_close("angle", angle, 180.0, 1e-6);
    assert!(!result.goals[0].met);
}

#[test]
fn a_suspension_point_moves_with_its_component() {
    // Base cube and arm; the arm swung 90° about y around (10, 10, 25). The arm's tip
    // (10, 10, 80) goes to (10 + 55, 10, 25).
    let meshes = vec![
        box_mesh(20.0, 20.0, 20.0),
        box_mesh(10.0, 10.0, 60.0).transformed(&Isometry3::translation(5.0, 5.0, 20.0)),
    ];
    let arm = rotation_about(Vector3::y(), 90.0, Point3::new(10.0, 10.0, 25.0));
    let lifted = Isometry3::translation(0.0, 0.0, 5.0);
    let result = evaluate(
        &project(&["base", "arm"]),
        &meshes,
        &design(vec![]),
        &pose(
            lifted,
            vec![Isometry3::identity(), arm],
            vec![suspend(10.0, 10.0, 80.0, 1, 90.0)],
        ),
    );
    let (angle, point) = suspension(&result, 0);
    assert_point("point", point, [65.0, 10.0, 30.0], 1e-9);
    let centre = [
        (8000.0 * 10.0 + 6000.0 * 35.0) / 14_000.0,
        10.0,
        (8000.0 * 10.0 + 6000.0 * 25.0) / 14_000.0 + 5.0,
    ];
    assert_point("centre", result.centre_of_mass, centre, 1e-9);
    let across = 65.0 - centre[0];
    let down = 30.0 - centre[2];
    assert_close("angle", angle, across.atan2(down).to_degrees(), 1e-9);
    assert!(result.goals[0].met);
}

#[test]
fn hanging_from_the_centre_of_mass_is_neutral() {
    let result = evaluate(
        &project(&["box"]),
        &[tall_box()],
        &design(vec![]),
        &rest_pose(1, vec![suspend(20.0, 30.0, 50.0, 0, 89.0)]),
    );
    assert_eq!(suspension(&result, 0).0, 90.0);
    assert!(!result.goals[0].met);
}

/// The 40 × 60 × 100 box with a vertical capsule at x = 10, y = 30 from z = 20 to 80 (r = 5)
/// and a 4.5 mm ball.
fn box_with_ball() -> Design {
    design(vec![capsule(
        0,
        Point3::new(10.0, 30.0, 20.0),
        Point3::new(10.0, 30.0, 80.0),
        5.0,
        4.5,
    )])
}

/// The immersion outcome of goal `i`: angle, distance, buoyancy centre, displaced mass,
/// residual.
fn immersion(result: &PoseEvaluation, i: usize) -> (f64, f64, [f64; 3], f64, f64) {
    match &result.goals[i].outcome {
        GoalOutcome::Immerse {
            angle,
            distance,
            buoyancy_centre,
            displaced_mass,
            mass_residual,
            ..
        } => (
            *angle,
            *distance,
            *buoyancy_centre,
            *displaced_mass,
            *mass_residual,
        ),
        other => panic!("expected an immerse outcome, got {other:?}"),
    }
}

#[test]
fn a_ball_low_in_a_box_rights_it_under_water() {
    // By hand: the void removes material at (10, 30, 50); the ball rests at (10, 30, 19.5).
    let void = PI * 25.0 * 60.0 + 4.0 / 3.0 * PI * 125.0;
    let ball = STEEL * ball_volume(4.5) / 1000.0;
    let material = PLA * (240_000.0 - void) / 1000.0;
    let mass = material + ball;
    let x = (PLA / 1000.0 * (240_000.0 * 20.0 - void * 10.0) + ball * 10.0) / mass;
    let z = (PLA / 1000.0 * (240_000.0 * 50.0 - void * 50.0) + ball * 19.5) / mass;
    // The centre of buoyancy is the box's centroid (20, 30, 50), above and beside the centre.
    let (dx, dz) = (20.0 - x, 50.0 - z);
    let angle = dx.abs().atan2(dz).to_degrees();
    let distance = dx.hypot(dz);
    assert!(dz > 0.0 && angle > 5.0 && angle < 85.0, "angle {angle}");

    let goals = vec![
        immerse(1.0, 0.0, angle + 0.5, None),
        immerse(1.0, 0.0, angle - 0.5, None),
        immerse(1.0, distance + 0.01, 90.0, None),
        immerse(1.0, 0.0, 90.0, Some(1.0)),
        immerse(mass / 240.0, 0.0, 90.0, Some(1e-6)),
    ];
    let result = evaluate(
        &project(&["box"]),
        &[tall_box()],
        &box_with_ball(),
        &rest_pose(1, goals),
    );
    assert_point("centre", result.centre_of_mass, [x, 30.0, z], 1e-9);
    let (got_angle, got_distance, buoyancy, displaced, residual) = immersion(&result, 0);
    assert_close("angle", got_angle, angle, 1e-7);
    assert_close("distance", got_distance, distance, 1e-9);
    assert_point("buoyancy centre", buoyancy, [20.0, 30.0, 50.0], 1e-9);
    // 240 cm³ of water.
    assert_close("displaced", displaced, 240.0, 1e-9);
    assert_close("residual", residual, mass - 240.0, 1e-9);
    assert!(residual > 50.0);
    assert_close("neutral residual", immersion(&result, 4).4, 0.0, 1e-9);
    assert_eq!(met(&result), vec![true, false, false, false, true]);
}

#[test]
fn turned_over_the_ball_drops_to_the_other_end() {
    // Half a turn about x: the ball rolls to the rest frame's z = 80.5, now the lowest; the
    // centre of buoyancy goes to (20, −30, −50). Mirrored, the angle is the same as upright.
    let void = PI * 25.0 * 60.0 + 4.0 / 3.0 * PI * 125.0;
    let ball = STEEL * ball_volume(4.5) / 1000.0;
    let mass = PLA * (240_000.0 - void) / 1000.0 + ball;
    let x = (PLA / 1000.0 * (240_000.0 * 20.0 - void * 10.0) + ball * 10.0) / mass;
    let z = (PLA / 1000.0 * (240_000.0 * 50.0 - void * 50.0) + ball * 80.5) / mass;
    let result = evaluate(
        &project(&["box"]),
        &[tall_box()],
        &box_with_ball(),
        &pose(
            rotation(Vector3::x(), 180.0),
            vec![Isometry3::identity()],
            vec![immerse(1.0, 0.0, 90.0, None)],
        ),
    );
    assert_point("centre", result.centre_of_mass, [x, -30.0, -z], 1e-9);
    let (angle, _, buoyancy, _, _) = immersion(&result, 0);
    assert_point("buoyancy centre", buoyancy, [20.0, -30.0, -50.0], 1e-9);
    assert_close(
        "angle",
        angle,
        (20.0 - x).abs().atan2(z - 50.0).to_degrees(),
        1e-7,
    );
    assert!(result.goals[0].met);
}

#[test]
fn an_empty_void_near_the_bottom_turns_it_over() {
    // No ball: the void makes the bottom lighter, so the centre of mass sits straight above the
    // centre of buoyancy.
    let void = capsule(
        0,
        Point3::new(20.0, 30.0, 10.0),
        Point3::new(20.0, 30.0, 30.0),
        5.0,
        0.0,
    );
    let result = evaluate(
        &project(&["box"]),
        &[tall_box()],
        &design(vec![void.clone()]),
        &rest_pose(1, vec![immerse(1.0, 0.0, 179.0, None)]),
    );
    let v = void.volume();
    let z = (240_000.0 * 50.0 - v * 20.0) / (240_000.0 - v);
    assert_point("centre", result.centre_of_mass, [20.0, 30.0, z], 1e-9);
    let (angle, distance, ..) = immersion(&result, 0);
    assert_close("angle", angle, 180.0, 1e-6);
    assert_close("distance", distance, z - 50.0, 1e-9);
    assert!(!result.goals[0].met);
}

#[test]
fn a_homogeneous_solid_has_no_preferred_orientation() {
    // Two posed parts without capsules: the centres of mass and buoyancy coincide at the
    // volume-weighted centroid.
    let meshes = vec![
        box_mesh(20.0, 20.0, 20.0),
        box_mesh(10.0, 10.0, 60.0).transformed(&Isometry3::translation(5.0, 5.0, 20.0)),
    ];
    let arm = rotation_about(Vector3::y(), 90.0, Point3::new(10.0, 10.0, 25.0));
    let result = evaluate(
        &project(&["base", "arm"]),
        &meshes,
        &design(vec![]),
        &pose(
            Isometry3::identity(),
            vec![Isometry3::identity(), arm],
            vec![
                immerse(1.0, 0.0, 89.0, None),
                immerse(1.0, 0.1, 180.0, None),
            ],
        ),
    );
    let (angle, distance, buoyancy, displaced, _) = immersion(&result, 0);
    let expected = [
        (8000.0 * 10.0 + 6000.0 * 35.0) / 14_000.0,
        10.0,
        (8000.0 * 10.0 + 6000.0 * 25.0) / 14_000.0,
    ];
    assert_point("buoyancy centre", buoyancy, expected, 1e-9);
    assert_close("displaced", displaced, 14.0, 1e-9);
    assert!(distance < 1e-9);
    // The direction between coinciding centres is undefined: reported as neutral, 90°.
    assert_eq!(angle, 90.0);
    // One goal fails on the angle, the other on the distance.
    assert_eq!(met(&result), vec![false, false]);
}
