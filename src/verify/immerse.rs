//! `immerse` by simulation: the model under water, held at its centre of buoyancy, let go from
//! several orientations.
//!
//! Buoyancy, `fluid density × outer volume × g` up, acts at the centre of buoyancy, so it has no
//! torque about that point; gravity acts on the model and on each ball. Only the orientation
//! matters to the goal, so the model is held still at its centre of buoyancy by a spherical
//! joint, which carries the buoyancy and whatever weight it does not balance: the torque about
//! that point, and so every equilibrium orientation, is that of the free floating model (when
//! the model's weight equals the buoyancy; a model that sinks or rises also has its drag).

use super::body::Model;
use super::release::Release;
use super::suspend::hang;

/// Linear and angular damping of the model and its balls in the fluid, 1/s.
pub(crate) const FLUID_DAMPING: f64 = 2.0;

/// Puts the model in a fluid, held at its centre of buoyancy, and lets it go from every
/// starting orientation. Each release's angle is the one between up and the direction from the
/// centre of mass (balls where they ended) to the centre of buoyancy, both in the model's frame:
/// how far the floating model has turned off its pose.
pub(crate) fn float(model: &Model) -> Vec<Release> {
    // The angle between gravity and the direction from the held point to the centre of mass is
    // the one between up and the direction from the centre of mass to the centre of buoyancy.
    hang(model, model.buoyancy_centre, (FLUID_DAMPING, FLUID_DAMPING))
}
