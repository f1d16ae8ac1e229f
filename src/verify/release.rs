//! Releases from several starting orientations, shared by `suspend` and `immerse`, and the
//! distinct final states they reach.

use rapier3d_f64::prelude::*;
use serde::Serialize;

use super::body::{BallEnd, Model, World};

/// Time step of the hanging and floating simulations, seconds.
pub(crate) const TIME_STEP: f64 = 1.0 / 120.0;
/// The longest a release is simulated, seconds.
pub(crate) const MAX_TIME: f64 = 40.0;
/// A release has settled once no point of the model or a ball has moved faster than this, in
/// model sizes per second, for [`QUIET_TIME`].
const QUIET_SPEED: f64 = 1e-3;
/// See [`QUIET_SPEED`], seconds.
const QUIET_TIME: f64 = 1.0;
/// Two final states are one when their angles to the pose's orientation differ by at most this
/// many degrees and every ball is at the same end.
const SAME_STATE_DEGREES: f64 = 2.0;

/// Where one release of the model ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Release {
    /// How the model was turned from its pose before it was let go.
    pub start: String,
    /// The final angle the goal measures, degrees.
    pub angle: f64,
    /// Where each ball ended, in the design's order.
    pub balls: Vec<BallEnd>,
    /// Whether the model came to rest within the simulated time.
    pub settled: bool,
    /// The final direction from the model's reference point the angle is measured to (the
    /// centre of mass for a hang, the centre of buoyancy for a float), unit, in the pose's frame.
    #[serde(skip)]
    pub direction: Vector,
}

/// A final state reached by one or more releases.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FinalState {
    /// The goal's angle in this state, degrees (of its first release).
    pub angle: f64,
    /// Where each ball is, in the design's order.
    pub balls: Vec<BallEnd>,
    /// The releases that ended here, by their `start`.
    pub releases: Vec<String>,
}

/// The starting orientations: the pose's own, then ±30° and ±90° about two horizontal axes,
/// then upside down. Rotations of the pose's frame, each with a label.
pub(crate) fn starts(model: &Model) -> Vec<(String, Rotation)> {
    let (first, second) = model.horizontal_axes();
    let mut starts = vec![("pose".to_string(), Rotation::IDENTITY)];
    for axis in [first, second] {
        for degrees in [30.0, -30.0, 90.0, -90.0] {
            starts.push((
                format!("{degrees:+}° about {}", axis_name(axis)),
                Rotation::from_axis_angle(axis, f64::to_radians(degrees)),
            ));
        }
    }
    starts.push((
        "upside down".to_string(),
        Rotation::from_axis_angle(first, std::f64::consts::PI),
    ));
    starts
}

/// The name of the world axis `axis` lies along (`x`, `y` or `z`).
fn axis_name(axis: Vector) -> &'static str {
    let a = axis.abs();
    if a.x >= a.y && a.x >= a.z {
        "x"
    } else if a.y >= a.z {
        "y"
    } else {
        "z"
    }
}

/// The pose `rotation` about `centre` (body frame) gives the model's body frame.
pub(crate) fn turned_about(centre: Vector, rotation: Rotation) -> Pose3 {
    Pose3::from_translation(centre)
        * Pose3::from_rotation(rotation)
        * Pose3::from_translation(-centre)
}

/// Runs `world` until it has settled or [`MAX_TIME`] has passed. Returns whether it settled.
pub(crate) fn run_until_settled(world: &mut World, model: &Model) -> bool {
    let steps = (MAX_TIME / world.time_step()).ceil() as usize;
    let quiet_steps = (QUIET_TIME / world.time_step()).ceil() as usize;
    let mut quiet = 0;
    for _ in 0..steps {
        world.step();
        if world.motion(model.size, model.up) < QUIET_SPEED * model.size {
            quiet += 1;
            if quiet >= quiet_steps {
                return true;
            }
        } else {
            quiet = 0;
        }
    }
    false
}

/// The angle between `a` and `b`, degrees in [0, 180]; 90 when either is zero.
pub(crate) fn angle_degrees(a: Vector, b: Vector) -> f64 {
    let lengths = a.length() * b.length();
    if lengths == 0.0 {
        return 90.0;
    }
    (a.dot(b) / lengths).clamp(-1.0, 1.0).acos().to_degrees()
}

/// The distinct final states of `releases`, in the order they were first reached.
pub(crate) fn distinct_states(releases: &[Release]) -> Vec<FinalState> {
    let mut states: Vec<(Vector, FinalState)> = Vec::new();
    for release in releases {
        let same = states.iter_mut().find(|(direction, state)| {
            state.balls == release.balls
                && angle_degrees(*direction, release.direction) <= SAME_STATE_DEGREES
        });
        match same {
            Some((_, state)) => state.releases.push(release.start.clone()),
            None => states.push((
                release.direction,
                FinalState {
                    angle: release.angle,
                    balls: release.balls.clone(),
                    releases: vec![release.start.clone()],
                },
            )),
        }
    }
    states.into_iter().map(|(_, state)| state).collect()
}
