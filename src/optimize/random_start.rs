//! Random starts: capsules of the smallest radius at random points inside the components, for
//! the exhaustive ranking and the search's second chance.

use nalgebra::{Point3, Vector3};

use super::problem::{Origin, Problem, StartCapsule};
use crate::objective::InteriorDistance;
use crate::random::SplitMix64;

/// `pinned` and `free` random capsules after them ([`random_capsule`]), drawn from `random`.
pub(super) fn random_start(
    problem: &Problem,
    interior: &dyn InteriorDistance,
    pinned: &[StartCapsule],
    free: usize,
    random: &mut SplitMix64,
) -> Vec<StartCapsule> {
    let mut start = pinned.to_vec();
    start.extend((0..free).map(|_| random_capsule(problem, interior, random)));
    start
}

/// A capsule of the smallest radius at a random point inside a random component (up to 64 tries
/// for a point with room for it), along a random direction, up to a sixth of the component's
/// bounding-box diagonal long.
fn random_capsule(
    problem: &Problem,
    interior: &dyn InteriorDistance,
    random: &mut SplitMix64,
) -> StartCapsule {
    let meshes = problem.meshes();
    let component = random.below(meshes.len().max(1));
    let radius = problem.parameters().min_radius;
    let room = radius + problem.project().wall;
    let (lo, hi) = meshes
        .get(component)
        .and_then(|m| m.bounding_box())
        .unwrap_or_default();
    let mut centre = nalgebra::center(&lo, &hi);
    for _ in 0..64 {
        let point = Point3::from(lo.coords + (hi - lo).component_mul(&random.vector()));
        if interior.distance(component, &point).0 > room {
            centre = point;
            break;
        }
    }
    let direction = loop {
        let v = random.vector() * 2.0 - Vector3::repeat(1.0);
        let norm = v.norm();
        if norm > 1e-3 && norm <= 1.0 {
            break v / norm;
        }
    };
    let half = radius.max((hi - lo).norm() / 12.0 * random.unit());
    StartCapsule::centred(component, centre, direction * half, radius, Origin::Random)
}
