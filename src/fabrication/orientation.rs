//! Print orientation: which way up a component is printed, declared in its `print` block or
//! chosen among the flat facets of its convex hull.
//!
//! The print frame has +z up, away from the bed. A facet goes on the bed by the shortest
//! rotation taking its outward normal to −z; the rotation about the vertical, free for the print,
//! then turns the facet's longest edge along +x (its first such edge, counter-clockwise seen from
//! outside, on a tie).
//!
//! Without a declaration, [`choose`] ranks the hull's facets by, in order:
//! 1. the capsules' insertion, when the caller's [`InsertionRank`] hook gives one: more capsules
//!    insertable, then fewer pauses;
//! 2. the facet's area (adhesion to the bed; the largest flat facet of a part is where a slicer
//!    needs no support under it): every facet within [`AREA_TIE`] of the largest counts as
//!    largest;
//! 3. stability: a facet the part stands on by itself (its centroid above the facet,
//!    [`facet_margin`] positive) before one it leans off, held only by the bed's adhesion;
//! 4. the part's height on the bed, lowest first (heights within the hull's tolerance equal);
//! 5. the facet facing most nearly the project's down (the part printed the way it is modelled
//!    standing), then the hull's facet order.

use nalgebra::{Point3, Rotation3, Unit, Vector3};

use super::plan::OrientationChoice;
use crate::balance::facets::{facet_along, facet_margin};
use crate::geometry::{ConvexHull, HullFacet, HullWalk};

/// Facets whose area is within this fraction of the largest candidate's rank as equally large.
pub const AREA_TIE: f64 = 0.01;

/// A facet counts as lying on the bed under a declared rotation when its normal is within this
/// angle of straight down, degrees.
const FLAT_ON_BED: f64 = 0.01;

/// How well an orientation lets the design's balls go in during the print: ranks before the
/// facet's area in [`choose`]. Greater is better: more capsules insertable, then fewer pauses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InsertionRank {
    /// Capsules whose ball can be dropped in at some pause.
    pub insertable: usize,
    /// Pauses the print needs for them.
    pub pauses: usize,
}

impl InsertionRank {
    /// The key compared: more insertable first, then fewer pauses.
    fn key(&self) -> (usize, std::cmp::Reverse<usize>) {
        (self.insertable, std::cmp::Reverse(self.pauses))
    }
}

/// How each candidate rotation (rest frame to print frame) suits the capsules' insertion, for
/// [`choose`].
pub type InsertionHook<'a> = &'a dyn Fn(&Rotation3<f64>) -> InsertionRank;

/// A facet still in the running in [`choose`], with the rotation that puts it on the bed when
/// the insertion rank needed it.
type Ranked = (usize, Option<Rotation3<f64>>);

/// How one component is printed.
#[derive(Debug, Clone, PartialEq)]
pub struct Orientation {
    /// Rest frame to print frame (+z up).
    pub to_print: Rotation3<f64>,
    /// The rest-frame unit direction that points down onto the bed.
    pub down: Vector3<f64>,
    /// Declared, or chosen and why.
    pub choice: OrientationChoice,
    /// Area of the hull facet on the bed, square units of the mesh; `None` when a declared
    /// rotation puts no facet flat on the bed (the part stands on an edge or a corner).
    pub facet_area: Option<f64>,
    /// The part's height on the bed: its extent along the print frame's z.
    pub height: f64,
}

/// The orientation that puts the facet that the ray from `centre` along `down` leaves `hull`
/// through (of the hull of `points`) on the bed; `None` for a zero `down`.
pub fn declared_down(
    hull: &ConvexHull,
    points: &[Point3<f64>],
    centre: &Point3<f64>,
    down: &Vector3<f64>,
) -> Option<Orientation> {
    let index = facet_along(hull, centre, down)?;
    let facet = &hull.facets[index];
    Some(on_facet(facet, points, OrientationChoice::Declared))
}

/// The orientation a declared rotation `to_print` (rest frame to print frame) gives the part of
/// hull `hull` over `points`.
pub fn declared_rotation(
    hull: &ConvexHull,
    points: &[Point3<f64>],
    to_print: Rotation3<f64>,
) -> Orientation {
    let down = to_print.inverse() * -Vector3::z();
    let flat = FLAT_ON_BED.to_radians().cos();
    let facet_area = hull
        .facets
        .iter()
        .find(|facet| facet.normal.dot(&down) >= flat)
        .map(|facet| facet.area);
    Orientation {
        to_print,
        down,
        choice: OrientationChoice::Declared,
        facet_area,
        height: height(points, &to_print),
    }
}

/// The orientation ballast chooses for the part of hull `hull` over `points` with centroid
/// `centre`, `down` the project's down in its rest frame (see the module documentation); `rank`
/// says how each candidate rotation suits the capsules' insertion, `None` when the part has no
/// capsules to rank by. Each facet's rotation and stability are computed only while it is still
/// in the running, so a hull of a million facets costs little more than a scan of their areas.
pub fn choose(
    hull: &ConvexHull,
    points: &[Point3<f64>],
    centre: &Point3<f64>,
    down: &Vector3<f64>,
    rank: Option<InsertionHook>,
) -> Orientation {
    // The facets with the best insertion rank, each with its rotation when the rank needed it.
    let (ranked, best_rank): (Vec<Ranked>, Option<InsertionRank>) = match rank {
        Some(rank) => {
            let placed: Vec<(usize, Rotation3<f64>, InsertionRank)> = (0..hull.facets.len())
                .map(|facet| {
                    let rotation = facet_rotation(&hull.facets[facet], points);
                    (facet, rotation, rank(&rotation))
                })
                .collect();
            let best = placed.iter().map(|(_, _, r)| *r).max_by_key(|r| r.key());
            let ranked = placed
                .into_iter()
                .filter(|(_, _, r)| Some(*r) == best)
                .map(|(facet, rotation, _)| (facet, Some(rotation)))
                .collect();
            (ranked, best)
        }
        None => ((0..hull.facets.len()).map(|f| (f, None)).collect(), None),
    };
    let largest = ranked
        .iter()
        .map(|&(facet, _)| hull.facets[facet].area)
        .fold(0.0, f64::max);
    let large: Vec<Candidate> = ranked
        .into_iter()
        .filter(|&(facet, _)| hull.facets[facet].area >= (1.0 - AREA_TIE) * largest)
        .map(|(facet, rotation)| Candidate {
            facet,
            stable: facet_margin(&hull.facets[facet], points, centre) > 0.0,
            rotation: rotation.unwrap_or_else(|| facet_rotation(&hull.facets[facet], points)),
        })
        .collect();
    let any_stable = large.iter().any(|c| c.stable);
    // The height only of the facets still in the running, each by walks over the hull's edges
    // (a scan of every point per facet made this quadratic): the low end from a corner of the
    // facet itself, which is on the bed, the high end from where the last walk ended, the facets
    // taken in an order that keeps successive directions close, so each walk is short.
    let walk = HullWalk::new(hull);
    let candidates: Vec<&Candidate> = large.iter().filter(|c| c.stable == any_stable).collect();
    let mut heights = vec![0.0; candidates.len()];
    let mut order: Vec<usize> = (0..candidates.len()).collect();
    order.sort_by_key(|&k| direction_key(&hull.facets[candidates[k].facet].normal));
    let mut high = 0;
    for k in order {
        let facet = &hull.facets[candidates[k].facet];
        let along = candidates[k].rotation.matrix().row(2).transpose();
        let low = facet.corners.first().and_then(|&c| walk.vertex(c));
        let mut start = (low.unwrap_or(0), high);
        heights[k] = walk
            .extent(points, &along, &mut start)
            .map_or(0.0, |(low, high)| high - low);
        high = start.1;
    }
    // Each with the part's height on the bed.
    let steady: Vec<(&Candidate, f64)> = candidates.into_iter().zip(heights).collect();
    let lowest = steady
        .iter()
        .map(|(_, height)| *height)
        .fold(f64::INFINITY, f64::min);
    let facing = |c: &Candidate| -hull.facets[c.facet].normal.dot(down);
    let best = steady
        .iter()
        .filter(|(_, height)| *height <= lowest + hull.tolerance)
        .map(|(c, _)| *c)
        .min_by(|a, b| facing(a).total_cmp(&facing(b)))
        .expect("a hull has facets");
    let facet = &hull.facets[best.facet];
    let overall = hull.facets.iter().map(|f| f.area).fold(0.0, f64::max);
    let mut reason = if facet.area >= (1.0 - AREA_TIE) * overall {
        "the largest flat facet".to_string()
    } else {
        "the largest flat facet that lets the capsules in".to_string()
    };
    if steady.len() > 1 {
        reason.push_str(&format!(", one of {} as large", steady.len()));
    }
    if !best.stable {
        reason.push_str(" (the part leans past its edge: the bed holds it)");
    }
    if let Some(rank) = best_rank {
        reason = format!(
            "{} insertable in {}; {reason}",
            counted(rank.insertable, "capsule"),
            counted(rank.pauses, "pause")
        );
    }
    on_facet(
        facet,
        points,
        OrientationChoice::Chosen {
            area: facet.area,
            reason,
        },
    )
}

/// One facet as [`choose`] ranks it.
struct Candidate {
    /// Index into the hull's facets.
    facet: usize,
    /// Whether the part stands on the facet by itself.
    stable: bool,
    /// The rotation that puts the facet on the bed.
    rotation: Rotation3<f64>,
}

/// `n` and the noun, plural unless `n` is 1.
fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// The orientation with `facet` on the bed.
fn on_facet(facet: &HullFacet, points: &[Point3<f64>], choice: OrientationChoice) -> Orientation {
    let to_print = facet_rotation(facet, points);
    Orientation {
        to_print,
        down: facet.normal,
        choice,
        facet_area: Some(facet.area),
        height: height(points, &to_print),
    }
}

/// The rotation that puts `facet` (of the hull of `points`) on the bed, its longest edge along
/// +x.
fn facet_rotation(facet: &HullFacet, points: &[Point3<f64>]) -> Rotation3<f64> {
    let tilt = Rotation3::rotation_between(&facet.normal, &-Vector3::z()).unwrap_or_else(|| {
        Rotation3::from_axis_angle(&Unit::new_unchecked(Vector3::x()), std::f64::consts::PI)
    });
    let n = facet.corners.len();
    let longest = (0..n)
        .map(|k| points[facet.corners[(k + 1) % n]] - points[facet.corners[k]])
        .fold(Vector3::zeros(), |longest: Vector3<f64>, edge| {
            if edge.norm() > longest.norm() {
                edge
            } else {
                longest
            }
        });
    let edge = tilt * longest;
    let spin = Rotation3::from_axis_angle(&Vector3::z_axis(), -edge.y.atan2(edge.x));
    spin * tilt
}

/// A key that sorts unit vectors along a space-filling curve (Morton order of their components),
/// so that vectors close in the order are mostly close in direction.
fn direction_key(direction: &Vector3<f64>) -> u64 {
    let quantised = direction.map(|x| (((x.clamp(-1.0, 1.0) + 1.0) / 2.0) * 1023.0) as u64);
    let mut key = 0;
    for bit in (0..10).rev() {
        for axis in 0..3 {
            key = (key << 1) | ((quantised[axis] >> bit) & 1);
        }
    }
    key
}

/// The extent of `points` along the print frame's z under `to_print`: the part's height on the
/// bed (0 without points).
pub fn height(points: &[Point3<f64>], to_print: &Rotation3<f64>) -> f64 {
    let (low, high) = points
        .iter()
        .map(|p| (to_print * p).z)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), z| {
            (low.min(z), high.max(z))
        });
    if high >= low {
        high - low
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::convex_hull;

    fn box_points(a: f64, b: f64, c: f64) -> Vec<Point3<f64>> {
        let mut points = Vec::new();
        for &x in &[0.0, a] {
            for &y in &[0.0, b] {
                for &z in &[0.0, c] {
                    points.push(Point3::new(x, y, z));
                }
            }
        }
        points
    }

    #[test]
    fn a_box_lies_on_its_largest_face_longest_edge_along_x() {
        let points = box_points(30.0, 20.0, 5.0);
        let hull = convex_hull(&points).unwrap();
        let centre = Point3::new(15.0, 10.0, 2.5);
        let chosen = choose(&hull, &points, &centre, &-Vector3::z(), None);
        assert!(chosen.down.z.abs() > 0.999_999, "{:?}", chosen.down);
        assert!((chosen.height - 5.0).abs() < 1e-9);
        let x = chosen.to_print * Vector3::x();
        assert!(x.x.abs() > 0.999_999, "the 30 edge along x: {x:?}");
        match chosen.choice {
            OrientationChoice::Chosen { area, ref reason } => {
                assert!((area - 600.0).abs() < 1e-9);
                assert!(reason.starts_with("the largest flat facet"), "{reason}");
            }
            OrientationChoice::Declared => panic!("chosen"),
        }
    }

    #[test]
    fn the_insertion_rank_comes_before_the_area() {
        let points = box_points(30.0, 20.0, 5.0);
        let hull = convex_hull(&points).unwrap();
        let centre = Point3::new(15.0, 10.0, 2.5);
        // Only orientations with the rest frame's x vertical let every capsule in.
        let rank = |r: &Rotation3<f64>| {
            let x_up = (r * Vector3::x()).z.abs() > 0.5;
            InsertionRank {
                insertable: if x_up { 2 } else { 1 },
                pauses: 1,
            }
        };
        let chosen = choose(&hull, &points, &centre, &-Vector3::z(), Some(&rank));
        assert!(chosen.down.x.abs() > 0.999_999, "{:?}", chosen.down);
        assert!((chosen.height - 30.0).abs() < 1e-9);
        let OrientationChoice::Chosen { area, reason } = chosen.choice else {
            panic!("chosen");
        };
        assert!((area - 100.0).abs() < 1e-9);
        assert!(
            reason.starts_with("2 capsules insertable in 1 pause;"),
            "{reason}"
        );
    }
}
