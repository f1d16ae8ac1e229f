//! `stand` and `imbalance` by simulation: the model set down on a ground that then tilts slowly
//! until the model topples. The ground stays still and gravity turns instead: seen from the
//! ground, the two are the same, but a ground that moves pushes the model as it turns (with the
//! engine's contact recycling on, a model on a ground turning at 1°/s stood up to 1.8° past the
//! tilt at which it toppled when the tilt was held).

use rapier3d_f64::prelude::*;
use serde::Serialize;

use super::body::{Build, Model, World, FRICTION, GRAVITY, RESTITUTION};

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
    /// `MAX_TILT`.
    pub topples_at: Option<f64>,
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
        let down = world.model_body().rotation().inverse() * world.gravity().normalize();
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
/// settle. Returns the world, the balls, and how far the model turned while settling, degrees.
fn set_down(model: &Model) -> (World, Balls, f64) {
    set_down_on_slope(model, model.up, 0.0)
}

/// Gravity, seen from a ground tilted by `tilt` (radians) so that `direction` (horizontal,
/// world) points downhill: `g (−cos θ·up + sin θ·direction)`.
fn slope_gravity(model: &Model, direction: Vector, tilt: f64) -> Vector {
    (direction * tilt.sin() - model.up * tilt.cos()) * GRAVITY
}

/// [`set_down`] on a ground already tilted by `tilt` (radians) so that `direction` points
/// downhill: the balls start at the ends that tilted gravity sends them to.
fn set_down_on_slope(model: &Model, direction: Vector, tilt: f64) -> (World, Balls, f64) {
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
    let handle = world.bodies.insert(RigidBodyBuilder::fixed().pose(base));
    let cuboid = ColliderBuilder::cuboid(extent, extent, model.size)
        .friction(FRICTION)
        .restitution(RESTITUTION);
    world
        .colliders
        .insert_with_parent(cuboid, handle, &mut world.bodies);
    world.set_gravity(slope_gravity(model, direction, tilt));
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
    (world, balls, turned)
}

/// Whether the model, set down in its pose, topples over by itself.
pub(crate) fn topples_when_set_down(model: &Model) -> bool {
    let (_, _, turned) = set_down(model);
    turned > TOPPLE_DEGREES
}

/// Sets the model down, then tilts the ground slowly so that `direction` (horizontal, world)
/// points downhill, until the model topples. `None` when it topples as it is set down.
pub(crate) fn tilt(model: &Model, direction: Vector) -> Option<TiltRun> {
    let (mut world, mut balls, turned) = set_down(model);
    if turned > TOPPLE_DEGREES {
        return None;
    }
    // Tilting the ground turns gravity, seen from the ground ([`slope_gravity`]).
    let settled = *world.model_body().rotation();
    let step = TILT_RATE.to_radians() * world.time_step();
    let mut tilt: f64 = 0.0;
    let mut onset = 0.0;
    let topples_at = loop {
        if tilt.to_degrees() > MAX_TILT {
            break None;
        }
        tilt += step;
        world.set_gravity(slope_gravity(model, direction, tilt));
        world.step();
        balls.roll(model, &mut world);
        // Turning about the ground's normal is no toppling: only how far the model's up has
        // moved counts.
        let relative = *world.model_body().rotation() * settled.inverse();
        let turned = (relative * model.up).angle_between(model.up).to_degrees();
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

/// Steps of the search for the gentlest slope a toppling model stands on, degrees: slopes this
/// far apart are tried from level up, then the first step that stands is halved
/// [`SLOPE_HALVINGS`] times.
pub(crate) const SLOPE_STEP: f64 = 1.0;
/// Halvings of the slope step once a standing slope is found: `1° / 2⁶`, about 0.016°.
const SLOPE_HALVINGS: usize = 6;

/// One search for the gentlest slope, in one direction, that a model which topples on level
/// ground stands on.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlopeRun {
    /// The horizontal unit vector pointing downhill, world.
    pub direction: [f64; 3],
    /// The gentlest slope the model, set down on it, stood on, degrees; `None` when it toppled on
    /// every slope tried (up to `MAX_TILT` in the first direction, up to the gentlest slope
    /// found so far in the others).
    pub stands_from: Option<f64>,
}

/// Whether the model, set down on a ground tilted by `tilt` degrees so that `direction` points
/// downhill, stays standing.
fn stands_on_slope(model: &Model, direction: Vector, tilt: f64) -> bool {
    let (_, _, turned) = set_down_on_slope(model, direction, tilt.to_radians());
    turned <= TOPPLE_DEGREES
}

/// The gentlest slope, with `direction` downhill, that the model stands on when set down on it:
/// slopes [`SLOPE_STEP`] apart from level up to `limit` degrees (at most [`MAX_TILT`]), then
/// bisection between the last that toppled and the first that stood. The balls start at the ends the slope's gravity sends
/// them to, as they would after a slow tilt. Independent of ballast's formulas: only the engine's
/// contacts decide.
pub(crate) fn gentlest_standing_slope(model: &Model, direction: Vector, limit: f64) -> SlopeRun {
    let mut toppled = 0.0;
    let mut stood = None;
    let mut tilt = SLOPE_STEP;
    while tilt <= limit.min(MAX_TILT) {
        if stands_on_slope(model, direction, tilt) {
            stood = Some(tilt);
            break;
        }
        toppled = tilt;
        tilt += SLOPE_STEP;
    }
    let stands_from = stood.map(|mut stood| {
        for _ in 0..SLOPE_HALVINGS {
            let middle = 0.5 * (toppled + stood);
            if stands_on_slope(model, direction, middle) {
                stood = middle;
            } else {
                toppled = middle;
            }
        }
        stood
    });
    SlopeRun {
        direction: direction.to_array(),
        stands_from,
    }
}
