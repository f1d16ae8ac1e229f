//! Where the heuristic starts: a small capsule at the midpoint of every skeleton segment (section
//! 4.5 b), plus the capsules written in the project file.

use std::borrow::Borrow;

use nalgebra::Point3;

use super::problem::{Origin, StartCapsule};
use crate::geometry::Skeleton;
use crate::objective::InteriorDistance;

/// A skeleton segment's midpoint and what became of it.
#[derive(Debug, Clone, PartialEq)]
pub struct SeedSite {
    /// The component whose skeleton it comes from, and which must contain it.
    pub component: usize,
    /// The midpoint, rest frame of the component.
    pub midpoint: Point3<f64>,
    /// Distance from the midpoint to the component's surface (positive inside).
    pub depth: f64,
    /// Whether a capsule was seeded there: the midpoint is deep enough inside its component for
    /// the smallest capsule and the wall.
    pub seeded: bool,
}

/// One start capsule of radius `radius` per skeleton segment whose midpoint lies at least
/// `radius + wall` inside its component (checked with `interior`), along the segment, half as long
/// as it (and at least `2 · radius`), centred on the midpoint. `skeletons` is indexed like the
/// components. Returns the capsules and every site, seeded or not, in component then segment order.
pub fn skeleton_seeds(
    skeletons: &[impl Borrow<Skeleton>],
    interior: &dyn InteriorDistance,
    radius: f64,
    wall: f64,
) -> (Vec<StartCapsule>, Vec<SeedSite>) {
    let mut seeds = Vec::new();
    let mut sites = Vec::new();
    for (component, skeleton) in skeletons.iter().enumerate() {
        for segment in &skeleton.borrow().segments {
            let midpoint = segment.midpoint();
            let depth = interior.distance(component, &midpoint).0;
            let seeded = depth >= radius + wall;
            let site = sites.len();
            sites.push(SeedSite {
                component,
                midpoint,
                depth,
                seeded,
            });
            if !seeded {
                continue;
            }
            let axis = segment.to - segment.from;
            let length = axis.norm();
            let direction = if length > 0.0 {
                axis / length
            } else {
                nalgebra::Vector3::z()
            };
            let half = (0.25 * length).max(radius);
            seeds.push(StartCapsule::centred(
                component,
                midpoint,
                direction * half,
                radius,
                Origin::Skeleton(site),
            ));
        }
    }
    (seeds, sites)
}
