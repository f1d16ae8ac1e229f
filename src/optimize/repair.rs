//! Written seeds brought within the rules before the search starts. A seed is only where the
//! optimizer starts, so one that is too thin, too short, too close to the surface, poking out or
//! overlapping another capsule is moved the shortest way to a place where every fabrication check
//! passes (or shrunk to the smallest capsule when it fits nowhere near as it is) rather than
//! rejected. Pinned capsules are never touched: they must be valid as written.

use nalgebra::{Point3, Vector3};

use super::problem::StartCapsule;
use super::stock::smallest_capsule_radius;
use crate::design::{Design, PlacedCapsule};
use crate::fabrication::{check_design, CapsuleIssue, PrintSetup};
use crate::geometry::TriMesh;
use crate::objective::InteriorDistance;
use crate::spec::model::Ball;

/// Steps of the push towards a valid place, per attempt.
const STEPS: usize = 200;
/// Points along the axis where the distance to the surface and to other capsules is measured.
const SAMPLES: usize = 9;

/// What was done to one seed.
#[derive(Debug, Clone, PartialEq)]
pub struct SeedRepair {
    /// The seed's index in the seeds given to [`repair_seeds`].
    pub seed: usize,
    /// What the fabrication checks found wrong with it as written (capsule indices are into the
    /// seeds).
    pub issues: Vec<CapsuleIssue>,
    /// Where it starts instead: `None` when no valid place was found near it and it was left out.
    pub repaired: Option<StartCapsule>,
}

/// What the repair works with: the components, the distance to their surfaces, the balls and the
/// smallest capsule.
pub struct Rules<'a> {
    /// The component meshes, for the exact checks.
    pub meshes: &'a [TriMesh],
    /// The distance to each component's surface and its gradient, to find the way inside.
    pub interior: &'a dyn InteriorDistance,
    /// The balls (clearance and sizes).
    pub ball: &'a Ball,
    /// The smallest radius the optimizer gives a capsule.
    pub min_radius: f64,
    /// Material around every capsule.
    pub wall: f64,
    /// Steps per project unit of the solution file's length grid (stock capsule radii sit on it).
    pub scale: f64,
    /// How each component is printed. A seed is moved for its placement only: whether its ball
    /// can go in at a pause is the optimizer's constraint, which moves it on from there.
    pub print: &'a PrintSetup,
}

/// Brings every unpinned seed within the rules, in order: each is checked exactly against the
/// meshes and against the seeds before it (pinned ones and those already repaired); a seed with
/// an issue is grown to the smallest capsule that holds a ball when it is too thin, lengthened to
/// its radius when too short, then pushed along the distance field into its component and away
/// from the capsules it overlaps, until the exact checks pass; when no push succeeds, it is
/// shrunk to the smallest capsule and pushed again from where it was written; when that fails too,
/// it is left out. Returns one [`SeedRepair`] per seed that had an issue, in seed order;
/// `seeds` holds the repaired seeds after (those left out removed).
pub fn repair_seeds(seeds: &mut Vec<StartCapsule>, rules: &Rules) -> Vec<SeedRepair> {
    let mut repairs = Vec::new();
    // The seeds judged so far that stay, with their indices: pinned ones first, as they do not
    // move, then each repaired or kept seed as it comes.
    let mut placed: Vec<(usize, StartCapsule)> = seeds
        .iter()
        .enumerate()
        .filter(|(_, s)| s.pinned)
        .map(|(i, s)| (i, s.clone()))
        .collect();
    let mut kept = vec![false; seeds.len()];
    for (index, seed) in seeds.iter_mut().enumerate() {
        if seed.pinned {
            kept[index] = true;
            continue;
        }
        let others: Vec<StartCapsule> = placed.iter().map(|(_, s)| s.clone()).collect();
        let issues: Vec<CapsuleIssue> = issues_among(seed, &others, rules)
            .into_iter()
            .map(|issue| issue.renumbered(|i| placed.get(i).map_or(index, |(j, _)| *j)))
            .collect();
        if issues.is_empty() {
            placed.push((index, seed.clone()));
            kept[index] = true;
            continue;
        }
        let repaired = pushed(&shaped(seed, rules), &others, rules)
            .or_else(|| pushed(&smallest(seed, rules), &others, rules));
        if let Some(repaired) = &repaired {
            *seed = repaired.clone();
            placed.push((index, repaired.clone()));
            kept[index] = true;
        }
        repairs.push(SeedRepair {
            seed: index,
            issues,
            repaired,
        });
    }
    let mut index = 0;
    seeds.retain(|_| {
        index += 1;
        kept[index - 1]
    });
    repairs
}

/// The fabrication issues of `seed` placed after `placed`: its own, and its overlaps with them.
/// Capsule indices are into `placed` followed by `seed`.
fn issues_among(seed: &StartCapsule, placed: &[StartCapsule], rules: &Rules) -> Vec<CapsuleIssue> {
    let last = placed.len();
    let capsules = placed
        .iter()
        .chain(std::iter::once(seed))
        .map(|s| placed_capsule(s, rules.ball))
        .collect();
    let design = Design {
        capsules,
        infill: 0.0,
    };
    check_design(
        rules.meshes,
        &design,
        rules.wall,
        rules.ball.clearance,
        rules.print,
    )
    .into_iter()
    .filter(|issue| match *issue {
        CapsuleIssue::NoInsertionWindow { .. } => false,
        CapsuleIssue::Overlap { second, .. } => second == last,
        ref other => other.capsule() == last,
    })
    .collect()
}

/// The design capsule a start capsule describes, with the ball that fits it (0 when none does).
fn placed_capsule(seed: &StartCapsule, ball: &Ball) -> PlacedCapsule {
    PlacedCapsule {
        name: seed.name.clone().unwrap_or_default(),
        component: seed.component,
        from: seed.from,
        to: seed.to,
        radius: seed.radius,
        ball_radius: ball.radius_for(seed.radius).unwrap_or(0.0),
    }
}

/// `seed` wide enough to hold a ball (at least the smallest radius) and at least as long as its
/// radius, about the same centre and along the same axis.
fn shaped(seed: &StartCapsule, rules: &Rules) -> StartCapsule {
    let radius = if seed.radius < rules.min_radius || rules.ball.radius_for(seed.radius).is_none() {
        smallest_capsule_radius(rules.ball, rules.min_radius, rules.scale)
    } else {
        seed.radius
    };
    resized(
        seed,
        radius,
        (seed.to - seed.from).norm().max(radius * 1.01),
    )
}

/// `seed` as the smallest capsule, as long as twice its radius, about the same centre.
fn smallest(seed: &StartCapsule, rules: &Rules) -> StartCapsule {
    let radius = smallest_capsule_radius(rules.ball, rules.min_radius, rules.scale);
    resized(seed, radius, 2.0 * radius)
}

/// `seed` with this radius and axis length, about the same centre and along the same axis (`z`
/// for a seed whose ends meet).
fn resized(seed: &StartCapsule, radius: f64, length: f64) -> StartCapsule {
    let centre = nalgebra::center(&seed.from, &seed.to);
    let axis = seed.to - seed.from;
    let direction = axis
        .try_normalize(f64::MIN_POSITIVE)
        .unwrap_or_else(Vector3::z);
    let half = direction * (0.5 * length);
    StartCapsule {
        from: centre - half,
        to: centre + half,
        radius,
        ..seed.clone()
    }
}

/// `seed` translated step by step, each step along the direction that most relieves its worst
/// shortfall (the distance field's gradient at the sample nearest the surface, or away from the
/// nearest overlapped capsule), until the exact checks pass; `None` when they do not within
/// [`STEPS`] steps.
fn pushed(seed: &StartCapsule, placed: &[StartCapsule], rules: &Rules) -> Option<StartCapsule> {
    let mut current = seed.clone();
    for _ in 0..STEPS {
        if issues_among(&current, placed, rules).is_empty() {
            return Some(current);
        }
        let (shortfall, direction) = worst_shortfall(&current, placed, rules);
        // At least a hundredth of the radius: the grid's interpolant may see room where the exact
        // distance does not.
        let step = shortfall.max(0.0) * 1.05 + 0.01 * current.radius;
        if !step.is_finite() || direction == Vector3::zeros() {
            return None;
        }
        current.from += direction * step;
        current.to += direction * step;
    }
    None
}

/// The largest shortfall of `seed` (how much farther from the surface, or from another capsule,
/// it must be) and the unit direction that relieves it.
fn worst_shortfall(
    seed: &StartCapsule,
    placed: &[StartCapsule],
    rules: &Rules,
) -> (f64, Vector3<f64>) {
    let mut worst = (f64::NEG_INFINITY, Vector3::zeros());
    for k in 0..SAMPLES {
        let point = sample(seed, k as f64 / (SAMPLES - 1) as f64);
        let (distance, gradient) = rules.interior.distance(seed.component, &point);
        let shortfall = seed.radius + rules.wall - distance;
        if shortfall > worst.0 {
            worst = (shortfall, gradient.try_normalize(1e-12).unwrap_or_default());
        }
        for other in placed.iter().filter(|o| o.component == seed.component) {
            let closest = closest_on_axis(other, &point);
            let away = point - closest;
            let shortfall = seed.radius + other.radius + rules.wall - away.norm();
            if shortfall > worst.0 {
                let direction = away.try_normalize(1e-12).unwrap_or_else(|| {
                    perpendicular(&(seed.to - seed.from)).unwrap_or_else(Vector3::x)
                });
                worst = (shortfall, direction);
            }
        }
    }
    worst
}

/// The point `from + s (to − from)` of a capsule's axis.
fn sample(capsule: &StartCapsule, s: f64) -> Point3<f64> {
    capsule.from + (capsule.to - capsule.from) * s
}

/// The point of `capsule`'s axis nearest `point`.
fn closest_on_axis(capsule: &StartCapsule, point: &Point3<f64>) -> Point3<f64> {
    let axis = capsule.to - capsule.from;
    let length = axis.norm_squared();
    let s = if length > 0.0 {
        ((point - capsule.from).dot(&axis) / length).clamp(0.0, 1.0)
    } else {
        0.0
    };
    sample(capsule, s)
}

/// A unit vector perpendicular to `axis`, when it has a length.
fn perpendicular(axis: &Vector3<f64>) -> Option<Vector3<f64>> {
    let unit = axis.try_normalize(1e-12)?;
    let helper = if unit.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    unit.cross(&helper).try_normalize(1e-12)
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::fabrication::LayerGrid;
    use crate::geometry::DistanceGrid;
    use crate::objective::GridInterior;
    use crate::optimize::test_meshes::cube;
    use crate::optimize::Origin;
    use nalgebra::Rotation3;

    fn ball() -> Ball {
        Ball {
            density: 7.85,
            clearance: 0.2,
            pause_clearance: 0.2,
            min_angle: 3.0,
            diameters: Vec::new(),
        }
    }

    fn seed(from: [f64; 3], to: [f64; 3], radius: f64, pinned: bool) -> StartCapsule {
        StartCapsule {
            component: 0,
            from: from.into(),
            to: to.into(),
            radius,
            pinned,
            name: Some("seed".to_string()),
            origin: Origin::Written,
        }
    }

    /// Repairs `seeds` in a 40 mm cube; returns the repairs, the seeds after and whether the
    /// exact checks pass on them all.
    fn repair(seeds: Vec<StartCapsule>) -> (Vec<SeedRepair>, Vec<StartCapsule>, bool) {
        repair_in(40.0, seeds)
    }

    /// [`repair`] in a cube of edge `side`.
    fn repair_in(
        side: f64,
        mut seeds: Vec<StartCapsule>,
    ) -> (Vec<SeedRepair>, Vec<StartCapsule>, bool) {
        let meshes = vec![cube(side, 0.0)];
        let interior = GridInterior {
            grids: vec![Arc::new(DistanceGrid::new(&meshes[0], side / 40.0))],
        };
        let ball = ball();
        let rules = Rules {
            meshes: &meshes,
            interior: &interior,
            ball: &ball,
            min_radius: 1.2,
            wall: 1.2,
            scale: 100.0,
            print: &PrintSetup::from_rotations(
                &[Rotation3::identity()],
                LayerGrid {
                    first_layer_height: 0.2,
                    layer_height: 0.2,
                    pause_clearance: 0.2,
                },
            ),
        };
        let repairs = repair_seeds(&mut seeds, &rules);
        let design = Design {
            capsules: seeds.iter().map(|s| placed_capsule(s, &ball)).collect(),
            infill: 0.0,
        };
        let valid = check_design(&meshes, &design, rules.wall, ball.clearance, rules.print)
            .iter()
            .all(|issue| matches!(issue, CapsuleIssue::NoInsertionWindow { .. }));
        (repairs, seeds, valid)
    }

    #[test]
    fn a_valid_seed_is_left_alone() {
        let written = vec![seed([10.0, 20.0, 20.0], [30.0, 20.0, 20.0], 3.0, false)];
        let (repairs, seeds, valid) = repair(written.clone());
        assert!(repairs.is_empty());
        assert_eq!(seeds, written);
        assert!(valid);
    }

    #[test]
    fn a_seed_poking_out_is_moved_inside_the_shortest_way() {
        // 1 mm below the top face: it needs radius + wall = 4.2 mm.
        let written = seed([10.0, 20.0, 39.0], [30.0, 20.0, 39.0], 3.0, false);
        let (repairs, seeds, valid) = repair(vec![written.clone()]);
        assert!(valid, "{seeds:?}");
        assert_eq!(repairs.len(), 1);
        assert!(matches!(
            repairs[0].issues[..],
            [CapsuleIssue::TooCloseToSurface { .. }]
        ));
        let moved = &seeds[0];
        assert_eq!(moved.radius, 3.0);
        let shift = moved.from - written.from;
        // Straight down, by the deficit (3.2 mm) and a little more, not to the middle.
        assert!(shift.x.abs() < 1e-6 && shift.y.abs() < 1e-6, "{shift:?}");
        assert!(shift.z < -3.2 && shift.z > -4.0, "{shift:?}");
        assert_eq!(moved.to - moved.from, written.to - written.from);
    }

    #[test]
    fn a_thin_short_seed_is_grown_and_a_crowding_one_moved_off_a_pinned_capsule() {
        let pinned = seed([10.0, 20.0, 20.0], [30.0, 20.0, 20.0], 3.0, true);
        let crowding = seed([10.0, 20.0, 22.0], [30.0, 20.0, 22.0], 3.0, false);
        let thin = seed([20.0, 10.0, 10.0], [20.0, 10.0, 10.05], 0.1, false);
        let (repairs, seeds, valid) = repair(vec![pinned.clone(), crowding, thin]);
        assert!(valid, "{seeds:?}");
        assert_eq!(seeds.len(), 3);
        assert_eq!(seeds[0], pinned, "a pinned capsule never moves");
        assert_eq!(repairs.iter().map(|r| r.seed).collect::<Vec<_>>(), [1, 2]);
        assert!(matches!(
            repairs[0].issues[..],
            [CapsuleIssue::Overlap {
                first: 0,
                second: 1,
                ..
            }]
        ));
        assert!(seeds[2].radius >= 1.2);
        assert!((seeds[2].to - seeds[2].from).norm() >= seeds[2].radius);
    }

    #[test]
    fn a_seed_outside_is_brought_in() {
        let outside = seed([50.0, 20.0, 20.0], [60.0, 20.0, 20.0], 3.0, false);
        let (repairs, seeds, valid) = repair(vec![outside]);
        assert!(valid, "{seeds:?}");
        assert!(matches!(
            repairs[0].issues[..],
            [CapsuleIssue::Outside { .. }]
        ));
        assert!(seeds[0].to.x <= 40.0 - 4.2 + 1e-9, "{seeds:?}");
    }

    #[test]
    fn a_seed_with_no_valid_place_near_it_is_left_out() {
        // A 4 mm cube has no room for the smallest capsule (1.2 mm) with its wall (1.2 mm).
        let cramped = seed([1.0, 2.0, 2.0], [3.0, 2.0, 2.0], 1.2, false);
        let (repairs, seeds, _) = repair_in(4.0, vec![cramped]);
        assert_eq!(repairs.len(), 1);
        assert!(repairs[0].repaired.is_none());
        assert!(seeds.is_empty());
    }
}
