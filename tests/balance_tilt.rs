//! The tilt margin with rolling balls against hand computations.
//!
//! A ball resting against the spherical cap at the end `e` of its capsule hangs from the cap's
//! centre: its weight acts along gravity through `e` whatever the tilt, so for toppling it counts
//! as a mass at `e`. The hand computations below use that, not ballast's own placement of the
//! ball, and find the worst direction by reasoning about the box's edges.

mod balance_support;
mod geometry_support;

use std::f64::consts::PI;

use balance_support::*;
use ballast::balance::{BallRest, PoseEvaluation};
use ballast::spec::model::Project;
use geometry_support::box_mesh;
use nalgebra::{Point3, Vector3};

/// The 40 mm cube at 10 % infill with one capsule through its centre, in the xz-plane, whose
/// `to` end is lower by `elevation` degrees (towards +x): radius 6.2, a 6 mm ball, axis 20 long.
fn cube_with_tilted_capsule(elevation: f64) -> (Project, PoseEvaluation, [Point3<f64>; 2]) {
    let half = 10.0;
    let (s, c) = elevation.to_radians().sin_cos();
    let from = Point3::new(20.0 - half * c, 20.0, 20.0 + half * s);
    let to = Point3::new(20.0 + half * c, 20.0, 20.0 - half * s);
    let mut project = project(&["cube"]);
    project.infill.value = 0.1;
    let mut design = design(vec![capsule(0, from, to, 6.2, 6.0)]);
    design.infill = 0.1;
    let result = evaluate(
        &project,
        &[box_mesh(40.0, 40.0, 40.0)],
        &design,
        &rest_pose(1, vec![stand(0.0)]),
    );
    (project, result, [from, to])
}

/// The centre of mass of that cube with its ball's mass at `ball` (by hand: the body's material
/// at the cube's centre less the void, plus the ball).
fn centre_with_ball_at(ball: Point3<f64>) -> Point3<f64> {
    let void = PI * 6.2 * 6.2 * (20.0 + 4.0 / 3.0 * 6.2);
    let body = 0.1 * PLA * (64_000.0 - void) / 1000.0;
    let steel = STEEL * ball_volume(6.0) / 1000.0;
    Point3::from((Vector3::new(20.0, 20.0, 20.0) * body + ball.coords * steel) / (body + steel))
}

fn atan_degrees(y: f64, x: f64) -> f64 {
    y.atan2(x).to_degrees()
}

#[test]
fn a_ball_that_rolls_before_the_model_topples_lowers_its_margin() {
    // At rest the ball is at the `to` end (+x). Tilting the ground down towards −x, the axis
    // goes horizontal at a tilt equal to its elevation, 30°, and the ball rolls to `from` (−x).
    // Its mass then at `from`, the cube topples over the x = 0 edge at atan(x / z) of that
    // centre, beyond 30°. Held still, the ball would leave the +x edge the critical one.
    let (_, result, [from, to]) = cube_with_tilted_capsule(30.0);
    let rolled = centre_with_ball_at(from);
    let resting = centre_with_ball_at(to);
    let expected = atan_degrees(rolled.x, rolled.z);
    let held = atan_degrees(40.0 - resting.x, resting.z);
    assert!(expected > 30.0 && expected < held, "{expected} {held}");
    // Held still, the ball rests against the bottom of its cap, 0.2 below the end point.
    let sitting = centre_with_ball_at(to - Vector3::z() * 0.2);
    let held_sitting = atan_degrees(40.0 - sitting.x, sitting.z);
    let support = &result.support;
    assert_close("rolling margin", support.tilt_margin, expected, 1e-6);
    assert_close("balls held", support.fixed_ball_margin, held_sitting, 1e-9);
    let direction = support.tilt_direction.expect("a direction");
    assert_point("direction", direction, [-1.0, 0.0, 0.0], 1e-6);
    assert_eq!(support.ball_moves.len(), 1);
    assert_eq!(support.ball_moves[0].to, BallRest::From);
    assert_close("rolls at", support.ball_moves[0].tilt, 30.0, 1e-9);
}

#[test]
fn a_ball_that_rolls_onto_the_wrong_side_topples_the_model_at_once() {
    // At 40° the ball only rolls once the ground tilts by 40° towards −x, and with its mass at
    // `from` the cube's toppling angle over x = 0 is already below 40°: it topples as the ball
    // rolls. Every other direction needs more tilt (the ball rolls later, or not at all).
    let (_, result, [from, to]) = cube_with_tilted_capsule(40.0);
    let rolled = centre_with_ball_at(from);
    let resting = centre_with_ball_at(to);
    assert!(atan_degrees(rolled.x, rolled.z) < 40.0);
    assert!(atan_degrees(40.0 - resting.x, resting.z) > 40.0);
    assert!(atan_degrees(20.0, resting.z) > 40.0);
    let support = &result.support;
    assert_close("rolling margin", support.tilt_margin, 40.0, 1e-6);
    assert_point(
        "direction",
        support.tilt_direction.unwrap(),
        [-1.0, 0.0, 0.0],
        1e-6,
    );
    assert_close("rolls at", support.ball_moves[0].tilt, 40.0, 1e-9);
}

#[test]
fn a_ball_against_its_cap_counts_at_the_cap_centre() {
    // A vertical capsule whose ball never changes end: as the ground tilts the ball slides down
    // its cap, but its weight still acts through the cap's centre, so the margin is that of the
    // centre of mass with the ball's mass at the end point, not at the resting ball's centre.
    let from = Point3::new(10.0, 20.0, 10.0);
    let to = Point3::new(10.0, 20.0, 12.0);
    let result = evaluate(
        &project(&["cube"]),
        &[box_mesh(40.0, 40.0, 40.0)],
        &design(vec![capsule(0, from, to, 4.0, 3.5)]),
        &rest_pose(1, vec![stand(0.0)]),
    );
    let void = PI * 16.0 * 2.0 + 4.0 / 3.0 * PI * 64.0;
    let material = PLA * (64_000.0 - void) / 1000.0;
    let ball = STEEL * ball_volume(3.5) / 1000.0;
    let mass = material + ball;
    let x = (PLA / 1000.0 * (64_000.0 * 20.0 - void * 10.0) + ball * 10.0) / mass;
    let z = (PLA / 1000.0 * (64_000.0 * 20.0 - void * 11.0) + ball * 10.0) / mass;
    assert_close(
        "rolling margin",
        result.support.tilt_margin,
        atan_degrees(x, z),
        1e-6,
    );
    assert!(result.support.tilt_margin < result.support.fixed_ball_margin);
    assert!(result.support.ball_moves.is_empty());
}

#[test]
fn a_toppling_model_needs_the_tilt_to_its_nearest_corner() {
    // The box [0, 10]² × [0, 40] turned so its centre of mass is beyond a corner, not an edge:
    // the tilt that would make it stand brings the centre's foot to that corner, farther than
    // either edge's line.
    let mesh = box_mesh(10.0, 10.0, 40.0);
    let mut skewed = mesh.clone();
    for p in &mut skewed.positions {
        // Shear: the top moves by (12, 16) over the height, the base stays put.
        let t = p.z / 40.0;
        p.x += 12.0 * t;
        p.y += 16.0 * t;
    }
    let result = evaluate(
        &project(&["leaning"]),
        &[skewed],
        &design(vec![]),
        &rest_pose(1, vec![imbalance(0.0)]),
    );
    // The centroid of a sheared box is the sheared centroid: (5 + 6, 5 + 8, 20).
    let (dx, dy): (f64, f64) = (11.0 - 10.0, 13.0 - 10.0);
    let corner = atan_degrees((dx * dx + dy * dy).sqrt(), 20.0);
    assert_close("rescue tilt", result.support.tilt_margin, -corner, 1e-6);
    assert!(result.support.fixed_ball_margin > result.support.tilt_margin);
}
