//! Mass, centre of mass and centre of buoyancy of a posed model (paper eq. 9-13).

use nalgebra::{Point3, Vector3};

use super::{BallPlacement, ComponentBody};
use crate::design::Design;
use crate::spec::model::{Pose, Project};

/// The mass-related quantities of a posed model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MassTotals {
    /// Grams: material plus balls.
    pub mass: f64,
    /// Outer volume of all components, cubic project units.
    pub volume: f64,
    /// World.
    pub centre_of_mass: Point3<f64>,
    /// Centroid of the outer volume, world: where buoyancy acts on the fully submerged model.
    pub buoyancy_centre: Point3<f64>,
}

/// Below this fraction of the sum of the magnitudes that went into it, a total mass (or volume)
/// counts as zero: dividing by it would only amplify rounding.
const CANCELLATION: f64 = 1e-12;

/// Sums material and balls over the posed components (eq. 12-13).
///
/// Component `i` contributes material of density `material.density × design.infill` over its
/// mesh volume at its centroid; each capsule removes that material over its void at the axis
/// midpoint and adds its ball (already placed, in `balls`, one per capsule). Capsules whose
/// component has no body are left out. When a total cancels to (nearly) zero, its centre is the
/// mean of the components' world centroids, or the origin without components.
pub(crate) fn mass_totals(
    project: &Project,
    bodies: &[ComponentBody],
    design: &Design,
    pose: &Pose,
    balls: &[BallPlacement],
) -> MassTotals {
    let density = project.material.density * design.infill * project.units.cubic_in_cm3();
    let mut mass = Weighted::default();
    let mut volume = Weighted::default();
    let mut centroids = Vector3::zeros();
    for (i, body) in bodies.iter().enumerate() {
        let centroid = pose.component_frame(i) * body.mass.centroid;
        centroids += centroid.coords;
        volume.add(body.mass.volume, &centroid);
        mass.add(density * body.mass.volume, &centroid);
    }
    for (capsule, ball) in design.capsules.iter().zip(balls) {
        if capsule.component >= bodies.len() {
            continue;
        }
        let middle =
            pose.component_frame(capsule.component) * nalgebra::center(&capsule.from, &capsule.to);
        mass.add(-density * capsule.volume(), &middle);
        mass.add(ball.mass, &Point3::from(ball.centre_world));
    }
    let fallback = if bodies.is_empty() {
        Point3::origin()
    } else {
        Point3::from(centroids / bodies.len() as f64)
    };
    MassTotals {
        mass: mass.total,
        volume: volume.total,
        centre_of_mass: mass.centre().unwrap_or(fallback),
        buoyancy_centre: volume.centre().unwrap_or(fallback),
    }
}

/// A running sum of weights at points.
#[derive(Debug, Default)]
struct Weighted {
    /// Σ w.
    total: f64,
    /// Σ w·x.
    moment: Vector3<f64>,
    /// Σ |w|, to tell a total that cancelled from one that is merely small.
    magnitude: f64,
}

impl Weighted {
    fn add(&mut self, weight: f64, at: &Point3<f64>) {
        self.total += weight;
        self.moment += at.coords * weight;
        self.magnitude += weight.abs();
    }

    /// The weighted mean position, or `None` when the weights cancel or the result is not finite.
    fn centre(&self) -> Option<Point3<f64>> {
        if self.total.abs() <= CANCELLATION * self.magnitude || self.total == 0.0 {
            return None;
        }
        let centre = Point3::from(self.moment / self.total);
        centre.iter().all(|x| x.is_finite()).then_some(centre)
    }
}
