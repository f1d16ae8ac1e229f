//! `immerse` by simulation: the model under water, buoyancy pushing up at its centre of buoyancy,
//! let go from several orientations.

use super::body::{Build, Model, World, GRAVITY};
use super::release::{angle_degrees, run_until_settled, starts, turned_about, Release, TIME_STEP};

/// Linear and angular damping of the model and its balls in the fluid, 1/s.
pub(crate) const FLUID_DAMPING: f64 = 2.0;

/// Puts the model in a fluid of `fluid_density` (kg/m³) and lets it go from every start of
/// [`starts`].
///
/// Buoyancy, `fluid_density × volume × g` up, acts at the centre of buoyancy; gravity acts on
/// the model and on each ball. A holding force at the centre of mass (model and balls) cancels
/// the difference between weight and buoyancy, so the model stays where it is without a torque
/// about its centre of mass: only its orientation matters. Each release's angle is the one
/// between up and the direction from the centre of mass (balls where they ended) to the centre
/// of buoyancy, both in the model's frame: how far the floating model has turned off its pose.
pub(crate) fn float(model: &Model, fluid_density: f64) -> Vec<Release> {
    starts(model)
        .into_iter()
        .map(|(start, rotation)| float_from(model, fluid_density, start, rotation))
        .collect()
}

fn float_from(
    model: &Model,
    fluid_density: f64,
    start: String,
    rotation: rapier3d_f64::prelude::Rotation,
) -> Release {
    let pose = turned_about(model.buoyancy_centre, rotation);
    let mut world = World::new(
        model,
        &Build {
            start: pose,
            colliders: false,
            fused_balls: false,
            damping: (FLUID_DAMPING, FLUID_DAMPING),
            time_step: TIME_STEP,
        },
    );
    let buoyancy = fluid_density * model.volume * GRAVITY;
    let holding = model.mass() * GRAVITY - buoyancy;
    let settled = run_until_settled(&mut world, model, |world| {
        let centre = world.centre_of_mass();
        let handle = world.model;
        let body = &mut world.bodies[handle];
        let buoyancy_centre = body.position() * model.buoyancy_centre;
        body.reset_forces(true);
        body.add_force_at_point(model.up * buoyancy, buoyancy_centre, true);
        body.add_force_at_point(model.up * holding, centre, true);
    });
    let frame = *world.model_body().position();
    let centre = frame.inverse_transform_point(world.centre_of_mass());
    let lift = model.buoyancy_centre - centre;
    Release {
        start,
        angle: angle_degrees(lift, model.up),
        balls: world.ball_ends(model),
        settled,
        direction: lift.normalize_or_zero(),
    }
}
