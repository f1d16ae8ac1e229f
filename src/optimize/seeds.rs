//! Where the heuristic starts: a small capsule at the midpoint of the skeleton segments (section
//! 4.5 b) with the most leverage, at most [`MAX_SEEDS`], plus the capsules written in the project
//! file.

use std::borrow::Borrow;

use nalgebra::Point3;

use super::problem::{Origin, StartCapsule};

/// The most capsules seeded from skeletons: the first round optimizes them all together, and its
/// time grows faster than their number.
pub const MAX_SEEDS: usize = 6;
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
    /// the smallest capsule and the wall, the component has room along its print direction for
    /// an insertable capsule (see [`skeleton_seeds`]), and the site is among the `MAX_SEEDS`
    /// with the most leverage.
    pub seeded: bool,
}

/// One start capsule of radius `radius` per skeleton segment whose midpoint lies at least
/// `radius + wall` inside its component (checked with `interior`) in a component with `room`,
/// along the segment, half as long as it (and at least `2 · radius`), centred on the midpoint;
/// of more than `MAX_SEEDS` such segments, only the `MAX_SEEDS` with the most leverage (see
/// `leverage`). `skeletons` and `room` are indexed like the components: `room[c]` is whether
/// component `c` can hold any capsule the fabrication rules allow ([`has_room`]; a component past
/// its end has room). Returns the capsules and every site, seeded or not, in component then
/// segment order.
pub fn skeleton_seeds(
    skeletons: &[impl Borrow<Skeleton>],
    interior: &dyn InteriorDistance,
    room: &[bool],
    radius: f64,
    wall: f64,
) -> (Vec<StartCapsule>, Vec<SeedSite>) {
    let mut seeds = Vec::new();
    let mut sites = Vec::new();
    let deep_enough = |component: usize, midpoint: &Point3<f64>| {
        let depth = interior.distance(component, midpoint).0;
        let roomy = room.get(component).copied().unwrap_or(true);
        (depth, roomy && depth >= radius + wall)
    };
    // The deep enough sites, most leverage first (ties in site order), cut to MAX_SEEDS.
    let mut ranked: Vec<(f64, usize)> = skeletons
        .iter()
        .enumerate()
        .flat_map(|(component, skeleton)| {
            skeleton
                .borrow()
                .segments
                .iter()
                .map(move |segment| (component, segment))
        })
        .enumerate()
        .filter_map(|(site, (component, segment))| {
            let (depth, deep) = deep_enough(component, &segment.midpoint());
            let length = (segment.to - segment.from).norm();
            deep.then(|| (leverage(depth, length), site))
        })
        .collect();
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    ranked.truncate(MAX_SEEDS);
    let kept: Vec<usize> = ranked.iter().map(|&(_, site)| site).collect();
    for (component, skeleton) in skeletons.iter().enumerate() {
        for segment in &skeleton.borrow().segments {
            let midpoint = segment.midpoint();
            let site = sites.len();
            let (depth, deep) = deep_enough(component, &midpoint);
            let seeded = deep && kept.contains(&site);
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

/// Whether a component whose vertices are `positions` (rest frame), printed along the unit
/// direction `up`, has room for a capsule of radius `radius` whose ball can be dropped in at a
/// pause: every point of the axis lies at least `radius + wall` from the surface, so within the
/// component's height along `up` less that on each side, and the axis rises at least
/// `radius − 3 · clearance + layer_height` along `up` (the insertion rule, docs/fabrication.md).
/// Necessary, not sufficient: a component without room can hold no such capsule of this radius
/// or more, and a seed there would only cost solves.
pub fn has_room(
    positions: &[Point3<f64>],
    up: &nalgebra::Vector3<f64>,
    radius: f64,
    wall: f64,
    clearance: f64,
    layer_height: f64,
) -> bool {
    let heights = positions.iter().map(|p| p.coords.dot(up));
    let (low, high) = heights.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), h| {
        (lo.min(h), hi.max(h))
    });
    let rise = (radius - 3.0 * clearance + layer_height).max(0.0);
    high - low >= 2.0 * (radius + wall) + rise
}

/// How much a capsule seeded at a skeleton segment can move the centre of mass: the mass of the
/// largest ball that fits at its midpoint (`depth`³) times how far it can roll (the segment's
/// `length`, at least `depth`).
fn leverage(depth: f64, length: f64) -> f64 {
    depth.powi(3) * length.max(depth)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    /// The corners of a box from the origin to `size`.
    fn corners(size: [f64; 3]) -> Vec<Point3<f64>> {
        (0..8)
            .map(|k| {
                let pick = |axis: usize| if k >> axis & 1 == 1 { size[axis] } else { 0.0 };
                Point3::new(pick(0), pick(1), pick(2))
            })
            .collect()
    }

    #[test]
    fn a_part_too_low_for_an_insertable_capsule_has_no_room() {
        // A 10 × 10 × 36 mm arm and the smallest capsule of a 6 mm ball with 0.2 mm clearance
        // (radius 3.2), 1.2 mm walls, 0.2 mm layers: the axis needs 2 · 4.4 mm of wall and a
        // rise of 3.2 − 0.6 + 0.2 = 2.8 mm, 11.6 mm in all.
        let arm = corners([10.0, 10.0, 36.0]);
        let room = |part: &[Point3<f64>], up: Vector3<f64>| has_room(part, &up, 3.2, 1.2, 0.2, 0.2);
        assert!(!room(&arm, Vector3::x()), "printed lying down, 10 mm high");
        assert!(room(&arm, Vector3::z()), "printed standing, 36 mm high");
        assert!(room(&corners([10.0, 10.0, 11.61]), Vector3::z()));
        assert!(!room(&corners([10.0, 10.0, 11.5]), Vector3::z()));
        assert!(!room(&[], Vector3::z()));
    }
}
