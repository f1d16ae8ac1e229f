//! Mass, centre of mass and centre of buoyancy of a posed model (paper eq. 9-13), with the
//! material where an FDM slicer deposits it (`docs/physics.md`, "The mass of a print").

use nalgebra::{Point3, Vector3};

use super::{BallPlacement, ComponentBody};
use crate::design::{Design, PlacedCapsule};
use crate::geometry::Region;
use crate::spec::model::{MassModel, Pose, Print, Project};

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

/// Sums material and balls over the posed components (eq. 12-13, with the print's shells).
///
/// Component `i` contributes its [`PrintVolumes`](crate::geometry::PrintVolumes): the solid part
/// at the material's density, the sparse part at `design.infill` of it, each at its centroid.
/// Each capsule removes the sparse material of the capsule dilated by [`capsule_shell`], adds
/// that shell back solid, and adds its ball (already placed, in `balls`, one per capsule); shell
/// and void are centred on the axis midpoint. A component whose print is measured
/// ([`ComponentBody::voids_in_print`]) has its voids and shells in it already: only its balls are
/// added. Capsules whose component has no body are left out.
/// When a total cancels to (nearly) zero, its centre is the mean of the components' world
/// centroids, or the origin without components.
pub(crate) fn mass_totals(
    project: &Project,
    bodies: &[ComponentBody],
    design: &Design,
    pose: &Pose,
    balls: &[BallPlacement],
) -> MassTotals {
    let density = project.material.density * project.units.cubic_in_cm3();
    let shell = capsule_shell(&project.print);
    let mut mass = Weighted::default();
    let mut volume = Weighted::default();
    let mut centroids = Vector3::zeros();
    for (i, body) in bodies.iter().enumerate() {
        let frame = pose.component_frame(i);
        let centroid = frame * body.mass.centroid;
        centroids += centroid.coords;
        volume.add(body.mass.volume, &centroid);
        let (solid, sparse) = (&body.print.solid, &body.print.sparse);
        mass.add(density * solid.volume, &(frame * solid.centroid));
        mass.add(
            density * design.infill * sparse.volume,
            &(frame * sparse.centroid),
        );
    }
    for (capsule, ball) in design.capsules.iter().zip(balls) {
        if capsule.component >= bodies.len() {
            continue;
        }
        if !bodies[capsule.component].voids_in_print {
            let middle = pose.component_frame(capsule.component)
                * nalgebra::center(&capsule.from, &capsule.to);
            mass.add(
                density * capsule_material(capsule, shell, design.infill),
                &middle,
            );
        }
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

/// The material of component `index` as the mass model prints it, before its balls go in:
/// its volume at the material's full density (cubic project units) and its centroid, rest frame.
/// The same sum as `mass_totals` makes for one component: the solid part, the sparse part at
/// `design.infill`, and for each of its capsules the sparse material of the dilated capsule
/// taken out and its shell put back solid (nothing for a measured body, whose voids are in it).
pub fn component_material(
    project: &Project,
    body: &ComponentBody,
    design: &Design,
    index: usize,
) -> Region {
    let shell = capsule_shell(&project.print);
    let mut material = Weighted::default();
    material.add(body.print.solid.volume, &body.print.solid.centroid);
    material.add(
        design.infill * body.print.sparse.volume,
        &body.print.sparse.centroid,
    );
    if !body.voids_in_print {
        for capsule in design.capsules.iter().filter(|c| c.component == index) {
            let middle = nalgebra::center(&capsule.from, &capsule.to);
            material.add(capsule_material(capsule, shell, design.infill), &middle);
        }
    }
    Region {
        volume: material.total,
        centroid: material.centre().unwrap_or(body.mass.centroid),
    }
}

/// The material a capsule changes in its component, full-density volume: the sparse fill of the
/// capsule dilated by `shell` taken out at `infill`, the dilated capsule put back solid, the
/// void taken out.
fn capsule_material(capsule: &PlacedCapsule, shell: f64, infill: f64) -> f64 {
    let dilated = capsule_volume(capsule.axis_length(), capsule.radius + shell);
    (1.0 - infill) * dilated - capsule.volume()
}

/// Thickness of the solid shell a slicer prints around a capsule, project units; 0 under the
/// `uniform` mass model.
///
/// Around a hole, each layer gets the perimeters (horizontal thickness `T_h`, see
/// [`Print::perimeter_thickness`]); the layers under the hole's floor and over its ceiling are
/// solid (vertical thickness `T_v`, the mean of the top and bottom solid layers times the layer
/// height), and the slicer grows those surfaces sideways by its surface margin. One thickness
/// all round keeps the shell closed form (a capsule dilated by a sphere is a capsule):
/// `√(T_h² + T_v²)`, 1.47 mm at PrusaSlicer's defaults, where its G-code gives 1.3 mm for a level
/// capsule and 1.7 mm for one tilted 10° (`docs/physics.md`).
pub fn capsule_shell(print: &Print) -> f64 {
    match print.model {
        MassModel::Uniform => 0.0,
        MassModel::Fdm => {
            let horizontal = print.perimeter_thickness();
            let layers = (print.top_solid_layers as f64 + print.bottom_solid_layers as f64) / 2.0;
            horizontal.hypot(layers * print.layer_height)
        }
    }
}

/// Volume of a capsule: `πr²(length + 4/3 r)`.
pub(super) fn capsule_volume(length: f64, radius: f64) -> f64 {
    std::f64::consts::PI * radius * radius * (length + 4.0 / 3.0 * radius)
}

/// A running sum of weights at points.
#[derive(Debug, Default)]
pub(super) struct Weighted {
    /// Σ w.
    pub(super) total: f64,
    /// Σ w·x.
    moment: Vector3<f64>,
    /// Σ |w|, to tell a total that cancelled from one that is merely small.
    magnitude: f64,
}

impl Weighted {
    pub(super) fn add(&mut self, weight: f64, at: &Point3<f64>) {
        self.total += weight;
        self.moment += at.coords * weight;
        self.magnitude += weight.abs();
    }

    /// The weighted mean position, or `None` when the weights cancel or the result is not finite.
    pub(super) fn centre(&self) -> Option<Point3<f64>> {
        if self.total.abs() <= CANCELLATION * self.magnitude || self.total == 0.0 {
            return None;
        }
        let centre = Point3::from(self.moment / self.total);
        centre.iter().all(|x| x.is_finite()).then_some(centre)
    }
}
