//! `stand` and `imbalance` by simulation: the model set down on a ground that then tilts slowly
//! until the model topples.

use rapier3d_f64::prelude::*;
use serde::Serialize;

use super::body::{Build, Model, World, FRICTION, RESTITUTION};

/// Time step of the ground simulations, seconds.
pub(crate) const TIME_STEP: f64 = 1.0 / 120.0;
/// How long the model settles after it is set down, seconds.
pub(crate) const SETTLE_TIME: f64 = 1.5;
/// How fast the ground tilts, degrees per second.
pub(crate) const TILT_RATE: f64 = 1.0;
/// The steepest ground tried, degrees.
pub(crate) const MAX_TILT: f64 = 75.0;
/// The model has toppled once it has turned this far relative to the ground, degrees.
pub(crate) const TOPPLE_DEGREES: f64 = 3.0;
/// The toppling angle is the ground's tilt when the model last sat within this many degrees of
/// its settled orientation on the ground, before it toppled.
pub(crate) const ONSET_DEGREES: f64 = 0.05;
/// How far above the ground the model's lowest point is set down, as a fraction of its size.
const DROP: f64 = 1e-4;

/// One tilt of the ground in one direction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TiltRun {
    /// The horizontal unit vector pointing downhill, world.
    pub direction: [f64; 3],
    /// The ground's tilt at which the model toppled, degrees; `None` when it still stood at
    /// [`MAX_TILT`].
    pub topples_at: Option<f64>,
}

/// A ground (kinematic, so it can be tilted) under a model set down on it.
struct Ground {
    handle: RigidBodyHandle,
    base: Pose3,
}

/// The end of its capsule each ball is at, while the balls are part of the model's body: a ball
/// rolls to the other end as soon as gravity, in the model's frame, points along its axis the
/// other way (a frictionless ball on a quasi-statically tilting ground; the time it takes to roll
/// is not simulated).
struct Balls {
    ends: Vec<bool>,
}

impl Balls {
    /// Each ball at the lower end of its capsule in the model's orientation now.
    fn new(model: &Model, world: &mut World) -> Balls {
        let mut balls = Balls { ends: Vec::new() };
        balls.ends = balls.lower_ends(model, world);
        world.place_balls(model, &balls.ends);
        balls
    }

    /// The lower end of each capsule (`true`: `to`); the current end where the axis is level.
    fn lower_ends(&self, model: &Model, world: &World) -> Vec<bool> {
        let down = world.model_body().rotation().inverse() * -model.up;
        model
            .balls
            .iter()
            .enumerate()
            .map(|(i, ball)| {
                let slope = (ball.to - ball.from).dot(down);
                if slope == 0.0 {
                    self.ends.get(i).copied().unwrap_or(false)
                } else {
                    slope > 0.0
                }
            })
            .collect()
    }

    /// Moves every ball whose end is no longer the lower one, and the model's mass with it.
    fn roll(&mut self, model: &Model, world: &mut World) {
        let ends = self.lower_ends(model, world);
        if ends != self.ends {
            self.ends = ends;
            world.place_balls(model, &self.ends);
        }
    }
}

/// The model set down at its pose orientation with its lowest point on a horizontal ground, let
/// settle. Returns the world, the ground, and how far the model turned while settling, degrees.
fn set_down(model: &Model) -> (World, Ground, Balls, f64) {
    let lowest = model
        .hulls
        .iter()
        .flatten()
        .map(|point| point.dot(model.up))
        .fold(f64::INFINITY, f64::min);
    let lowest = if lowest.is_finite() { lowest } else { 0.0 };
    let start = Pose3::from_translation(model.up * (DROP * model.size - lowest));
    let mut world = World::new(
        model,
        &Build {
            start,
            colliders: true,
            fused_balls: true,
            damping: (0.0, 0.0),
            time_step: TIME_STEP,
        },
    );
    let extent = 20.0 * model.size;
    let base = Pose3::from_parts(
        -model.up * model.size,
        Rotation::from_rotation_arc(Vector::Z, model.up),
    );
    let handle = world
        .bodies
        .insert(RigidBodyBuilder::kinematic_position_based().pose(base));
    let cuboid = ColliderBuilder::cuboid(extent, extent, model.size)
        .friction(FRICTION)
        .restitution(RESTITUTION);
    world
        .colliders
        .insert_with_parent(cuboid, handle, &mut world.bodies);
    let steps = (SETTLE_TIME / world.time_step()).ceil() as usize;
    let mut balls = Balls::new(model, &mut world);
    for _ in 0..steps {
        world.step();
        balls.roll(model, &mut world);
    }
    // How far the model has tilted: the angle its pose's up has turned through (turning about
    // up is no toppling).
    let turned = (*world.model_body().rotation() * model.up)
        .angle_between(start.rotation * model.up)
        .to_degrees();
    (world, Ground { handle, base }, balls, turned)
}

/// Whether the model, set down in its pose, topples over by itself.
pub(crate) fn topples_when_set_down(model: &Model) -> bool {
    let (_, _, _, turned) = set_down(model);
    turned > TOPPLE_DEGREES
}

/// Sets the model down, then tilts the ground slowly so that `direction` (horizontal, world)
/// points downhill, until the model topples. `None` when it topples as it is set down.
pub(crate) fn tilt(model: &Model, direction: Vector) -> Option<TiltRun> {
    let (mut world, ground, mut balls, turned) = set_down(model);
    if turned > TOPPLE_DEGREES {
        return None;
    }
    // Rotating the ground's normal towards `direction` makes `direction` point downhill. The
    // ground turns about the point under the model's centre of mass, so the support barely moves.
    let axis = model.up.cross(direction).normalize();
    let centre = world.centre_of_mass();
    let pivot = centre - model.up * centre.dot(model.up);
    let settled = ground_rotation(&world, &ground).inverse() * *world.model_body().rotation();
    let step = TILT_RATE.to_radians() * world.time_step();
    let mut tilt: f64 = 0.0;
    let mut onset = 0.0;
    let topples_at = loop {
        if tilt.to_degrees() > MAX_TILT {
            break None;
        }
        tilt += step;
        let turn = Pose3::from_rotation(Rotation::from_axis_angle(axis, tilt));
        let pose =
            Pose3::from_translation(pivot) * turn * Pose3::from_translation(-pivot) * ground.base;
        if let Some(body) = world.bodies.get_mut(ground.handle) {
            body.set_next_kinematic_position(pose);
        }
        world.step();
        balls.roll(model, &mut world);
        let relative = ground_rotation(&world, &ground).inverse() * *world.model_body().rotation();
        // Turning about the ground's normal is no toppling: only how far the ground's normal
        // (the ground body's z axis) has moved in the model's frame counts.
        let turned = (relative.inverse() * Vector::Z)
            .angle_between(settled.inverse() * Vector::Z)
            .to_degrees();
        if turned <= ONSET_DEGREES {
            onset = tilt.to_degrees();
        } else if turned > TOPPLE_DEGREES {
            break Some(onset);
        }
    };
    Some(TiltRun {
        direction: direction.to_array(),
        topples_at,
    })
}

/// The ground's orientation now.
fn ground_rotation(world: &World, ground: &Ground) -> Rotation {
    world
        .bodies
        .get(ground.handle)
        .map_or(ground.base.rotation, |body| *body.rotation())
}
