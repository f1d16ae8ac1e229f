//! `suspend` by simulation: the model hangs from a spherical joint at the suspension point and is
//! let go from several orientations.

use rapier3d_f64::prelude::*;

use super::body::{Build, Model, World};
use super::release::{angle_degrees, run_until_settled, starts, turned_about, Release, TIME_STEP};

/// Angular damping of the hanging model and its balls, 1/s (air and the string's friction, made
/// strong enough to settle in seconds).
pub(crate) const ANGULAR_DAMPING: f64 = 2.0;
/// Linear damping of the hanging model and its balls, 1/s.
pub(crate) const LINEAR_DAMPING: f64 = 0.5;

/// Hangs the model from `point` (body frame, metres), every body damped by `damping` (linear,
/// angular, 1/s), and lets it go from every start of [`starts`]. Each release's angle is the one between the final string (point to centre of
/// mass, balls where they ended) and the pose's gravity, both in the model's frame: how far the
/// hanging model has turned off its pose.
pub(crate) fn hang(model: &Model, point: Vector, damping: (f64, f64)) -> Vec<Release> {
    starts(model)
        .into_iter()
        .map(|(start, rotation)| hang_from(model, point, damping, start, rotation))
        .collect()
}

fn hang_from(
    model: &Model,
    point: Vector,
    damping: (f64, f64),
    start: String,
    rotation: Rotation,
) -> Release {
    let pose = turned_about(point, rotation);
    let mut world = World::new(
        model,
        &Build {
            start: pose,
            colliders: false,
            fused_balls: false,
            damping,
            time_step: TIME_STEP,
        },
    );
    let anchor = world
        .bodies
        .insert(RigidBodyBuilder::fixed().translation(point));
    // The anchor is the root of the multibody; the joint starts at coordinate 0, where the
    // anchor's joint frame (turned by the start rotation) meets the model's.
    let mut joint = SphericalJointBuilder::new()
        .local_anchor1(Vector::ZERO)
        .local_anchor2(point)
        .build();
    joint.data.local_frame1.rotation = rotation;
    world.joints.insert(anchor, world.model, joint, true);
    world.damp_joints(damping);
    let settled = run_until_settled(&mut world, model);
    let frame = *world.model_body().position();
    let string = frame.inverse_transform_point(world.centre_of_mass()) - point;
    let direction = string.normalize_or_zero();
    Release {
        start,
        angle: angle_degrees(string, -model.up),
        balls: world.ball_ends(model),
        settled,
        direction,
    }
}
