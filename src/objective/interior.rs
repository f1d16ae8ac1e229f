//! The hook for eq. 15: capsules inside their component, which needs a distance field.

use nalgebra::{Point3, Vector3};

/// Distance from a point to a component's surface, for the interior constraints of eq. 15
/// (`d(x) ≥ r + wall` at every sample `x` of a capsule's axis).
///
/// The optimizer supplies an implementation backed by per-component distance grids; the
/// objective only calls it.
pub trait InteriorDistance {
    /// Signed distance from `point` (rest frame of `component`) to that component's surface,
    /// project units, positive inside, and its gradient with respect to `point`.
    fn distance(&self, component: usize, point: &Point3<f64>) -> (f64, Vector3<f64>);
}
