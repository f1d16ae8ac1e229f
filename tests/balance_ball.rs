//! Where the balls rest: the end gravity sends them to, or undetermined near horizontal.

mod balance_support;
mod geometry_support;

use balance_support::*;
use ballast::balance::{BallRest, PoseEvaluation};
use ballast::design::PlacedCapsule;
use geometry_support::box_mesh;
use nalgebra::{Isometry3, Point3, Vector3};

/// A vertical capsule from (10, 30, 20) to (10, 30, 80), radius 5, ball radius 4.5, in a
/// 40 × 60 × 100 box.
fn vertical() -> PlacedCapsule {
    capsule(
        0,
        Point3::new(10.0, 30.0, 20.0),
        Point3::new(10.0, 30.0, 80.0),
        5.0,
        4.5,
    )
}

fn evaluate_one(c: PlacedCapsule, transform: Isometry3<f64>) -> PoseEvaluation {
    evaluate(
        &project(&["box"]),
        &[box_mesh(40.0, 60.0, 100.0)],
        &design(vec![c]),
        &pose(transform, vec![Isometry3::identity()], vec![]),
    )
}

#[test]
fn upright_the_ball_rests_at_the_lower_end() {
    let result = evaluate_one(vertical(), Isometry3::identity());
    let ball = &result.balls[0];
    assert_eq!(ball.rest, BallRest::From);
    assert_close("elevation", ball.elevation, 90.0, 1e-9);
    // Touching the bottom of the cap: 5 − 4.5 below the end point.
    assert_point("centre", ball.centre, [10.0, 30.0, 19.5], 1e-12);
    assert_point("world", ball.centre_world, [10.0, 30.0, 19.5], 1e-12);
    assert_eq!(ball.capsule, "c0");
    assert_eq!(ball.component, 0);
}

#[test]
fn upside_down_the_ball_rests_at_the_other_end() {
    // Half a turn about x: (x, y, z) → (x, −y, −z). Gravity in the component frame is +z, so the
    // ball rolls to z = 80 and touches the cap above it (in the rest frame).
    let result = evaluate_one(vertical(), rotation(Vector3::x(), 180.0));
    let ball = &result.balls[0];
    assert_eq!(ball.rest, BallRest::To);
    assert_point("centre", ball.centre, [10.0, 30.0, 80.5], 1e-9);
    assert_point("world", ball.centre_world, [10.0, -30.0, -80.5], 1e-9);
}

#[test]
fn a_tilted_capsule_sends_the_ball_down_its_axis() {
    // Tilted 30° about x the axis rises 60° above horizontal.
    let result = evaluate_one(vertical(), rotation(Vector3::x(), 30.0));
    let ball = &result.balls[0];
    assert_eq!(ball.rest, BallRest::From);
    assert_close("elevation", ball.elevation, 60.0, 1e-9);
    // Gravity in the rest frame is R⁻¹(−z) = (0, −sin 30°, −cos 30°).
    let s = 30f64.to_radians();
    let expected = [10.0, 30.0 - 0.5 * s.sin(), 20.0 - 0.5 * s.cos()];
    assert_point("centre", ball.centre, expected, 1e-9);
}

/// A horizontal capsule along x, from (5, 30, 50) to (35, 30, 50).
fn horizontal() -> PlacedCapsule {
    capsule(
        0,
        Point3::new(5.0, 30.0, 50.0),
        Point3::new(35.0, 30.0, 50.0),
        5.0,
        4.5,
    )
}

#[test]
fn near_horizontal_the_rest_is_undetermined() {
    // Turning about y by −2° lifts the +x end: the axis is 2° from horizontal, below the 3°
    // minimum.
    let result = evaluate_one(horizontal(), rotation(Vector3::y(), -2.0));
    let ball = &result.balls[0];
    assert_eq!(ball.rest, BallRest::Undetermined);
    assert_close("elevation", ball.elevation, 2.0, 1e-9);
    assert_point("centre", ball.centre, [20.0, 30.0, 50.0], 1e-12);

    let level = evaluate_one(horizontal(), Isometry3::identity());
    assert_eq!(level.balls[0].rest, BallRest::Undetermined);
    assert_close("level elevation", level.balls[0].elevation, 0.0, 1e-12);
}

#[test]
fn past_the_minimum_angle_the_ball_rolls() {
    // −4° about y lifts the +x end (to): the ball rolls to from. +4° lowers it: to.
    let lifted = evaluate_one(horizontal(), rotation(Vector3::y(), -4.0));
    assert_eq!(lifted.balls[0].rest, BallRest::From);
    assert_close("elevation", lifted.balls[0].elevation, 4.0, 1e-9);
    let lowered = evaluate_one(horizontal(), rotation(Vector3::y(), 4.0));
    assert_eq!(lowered.balls[0].rest, BallRest::To);
    // The ball's lowest point is the capsule's lowest point: centre + 4.5 down = to + 5 down.
    let ball = Point3::from(lowered.balls[0].centre_world);
    let end = rotation(Vector3::y(), 4.0) * Point3::new(35.0, 30.0, 50.0);
    assert_close("lowest point", ball.z - 4.5, end.z - 5.0, 1e-9);
}

#[test]
fn a_bent_component_decides_for_its_own_capsule() {
    // Two boxes; the capsule is in the second, whose own transform turns it upside down
    // (about the line x = 5, z = 50). The whole model stays upright.
    let flip = rotation_about(Vector3::x(), 180.0, Point3::new(5.0, 30.0, 50.0));
    let c = capsule(
        1,
        Point3::new(5.0, 30.0, 30.0),
        Point3::new(5.0, 30.0, 70.0),
        3.0,
        2.5,
    );
    let result = evaluate(
        &project(&["a", "b"]),
        &[box_mesh(10.0, 10.0, 10.0), box_mesh(10.0, 60.0, 100.0)],
        &design(vec![c]),
        &pose(
            Isometry3::identity(),
            vec![Isometry3::identity(), flip],
            vec![],
        ),
    );
    let ball = &result.balls[0];
    assert_eq!(ball.rest, BallRest::To);
    assert_point("centre", ball.centre, [5.0, 30.0, 70.5], 1e-9);
    // (5, 30, 70.5) flipped about (y, z) = (30, 50): (5, 30, 29.5).
    assert_point("world", ball.centre_world, [5.0, 30.0, 29.5], 1e-9);
}

#[test]
fn the_minimum_angle_comes_from_the_project() {
    let mut project = project(&["box"]);
    project.ball.min_angle = 1.0;
    let result = evaluate(
        &project,
        &[box_mesh(40.0, 60.0, 100.0)],
        &design(vec![horizontal()]),
        &pose(
            rotation(Vector3::y(), 2.0),
            vec![Isometry3::identity()],
            vec![],
        ),
    );
    assert_eq!(result.balls[0].rest, BallRest::To);
}
