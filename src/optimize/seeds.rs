//! Where the heuristic starts: a small capsule at the midpoint of the skeleton segments (section
//! 4.5 b) with the most leverage, at most [`MAX_SEEDS`], plus the capsules written in the project
//! file.

use std::borrow::Borrow;

use nalgebra::Point3;

use super::problem::{Origin, StartCapsule};

/// The most capsules seeded from skeletons: the first round optimizes them all together, and its
/// time grows faster than their number.
pub const MAX_SEEDS: usize = 12;
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
    /// the smallest capsule and the wall, and the site is among the [`MAX_SEEDS`] with the most
    /// leverage.
    pub seeded: bool,
}

/// One start capsule of radius `radius` per skeleton segment whose midpoint lies at least
/// `radius + wall` inside its component (checked with `interior`), along the segment, half as long
/// as it (and at least `2 · radius`), centred on the midpoint; of more than [`MAX_SEEDS`] such
/// segments, only the [`MAX_SEEDS`] with the most leverage (see `leverage`). `skeletons` is
/// indexed like the components. Returns the capsules and every site, seeded or not, in component
/// then segment order.
pub fn skeleton_seeds(
    skeletons: &[impl Borrow<Skeleton>],
    interior: &dyn InteriorDistance,
    radius: f64,
    wall: f64,
) -> (Vec<StartCapsule>, Vec<SeedSite>) {
    let mut seeds = Vec::new();
    let mut sites = Vec::new();
    let deep_enough = |component: usize, midpoint: &Point3<f64>| {
        let depth = interior.distance(component, midpoint).0;
        (depth, depth >= radius + wall)
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

/// How much a capsule seeded at a skeleton segment can move the centre of mass: the mass of the
/// largest ball that fits at its midpoint (`depth`³) times how far it can roll (the segment's
/// `length`, at least `depth`).
fn leverage(depth: f64, length: f64) -> f64 {
    depth.powi(3) * length.max(depth)
}
