//! The convex hull of points in space (quickhull), its coplanar triangles merged into facets.
//!
//! # Tolerances
//!
//! Both are fractions of the points' extent `L` (the diagonal of their bounding box), so a hull
//! means the same whatever unit its points are written in:
//!
//! - quickhull adds a point to the hull only when it lies more than `1e-10 L` outside it, far
//!   above the rounding of the coordinates (about `1e-16 L`) and far below anything a print shows;
//! - hull triangles whose corners all lie within [`COPLANAR`]` × L` (`1e-6 L`) of one plane are
//!   one facet. That is 0.1 µm on a 100 mm model, a thousandth of a printer's finest layer, yet
//!   ten times the rounding of coordinates stored as 32-bit floats (`6e-8` relative), so a face
//!   exported from a modeller stays one facet while the smallest real bump does not.

mod facets;
mod quickhull;

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Vector3};

use quickhull::Quickhull;

/// Hull triangles within this fraction of the points' extent of one plane form one facet.
pub const COPLANAR: f64 = 1e-6;

/// A point joins the hull when more than this fraction of the extent outside it.
const OUTSIDE: f64 = 1e-10;

/// One flat side of a [`ConvexHull`]: a convex polygon.
#[derive(Debug, Clone, PartialEq)]
pub struct HullFacet {
    /// Outward unit normal (the area-weighted mean of its triangles' normals).
    pub normal: Vector3<f64>,
    /// `normal · p` of the facet's plane: the largest over its corners, so every point given to
    /// [`convex_hull`] is at most the coplanarity tolerance above it.
    pub offset: f64,
    /// The corners, indices into the points given to [`convex_hull`], counter-clockwise seen from
    /// outside, no three collinear. Shared, not copied, by the hull [`ConvexHull::moved`] makes
    /// (a hull of a million facets is moved once for every pose).
    pub corners: Arc<[usize]>,
    /// Area of the polygon, square units of the points.
    pub area: f64,
}

/// The convex hull of a point set as facets.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexHull {
    /// The facets, largest first (ties in the order quickhull made them).
    pub facets: Vec<HullFacet>,
    /// Every corner of every facet, ascending, indices into the points.
    pub vertices: Vec<usize>,
    /// The coplanarity tolerance used, a length: [`COPLANAR`] times the points' extent.
    pub tolerance: f64,
}

/// The convex hull of the finite points among `points`, or `None` when they span no volume
/// (all within `1e-10` of their extent of one plane, or fewer than four). Deterministic: the same
/// points in the same order give the same facets in the same order.
pub fn convex_hull(points: &[Point3<f64>]) -> Option<ConvexHull> {
    let all: Vec<usize> = (0..points.len()).collect();
    convex_hull_among(points, &all)
}

/// [`convex_hull`] of the points `points[i]` for `i` in `candidates` (ascending), its corners
/// indices into `points`: the hull of a model from the hull vertices of its parts, without
/// the points inside them. The extent, and so both tolerances, are the candidates'.
pub fn convex_hull_among(points: &[Point3<f64>], candidates: &[usize]) -> Option<ConvexHull> {
    let finite: Vec<usize> = candidates
        .iter()
        .copied()
        .filter(|&i| points[i].iter().all(|x| x.is_finite()))
        .collect();
    let extent = extent(points, &finite);
    if extent.is_nan() || extent <= 0.0 {
        return None;
    }
    let mut hull = Quickhull::start(points, &finite, OUTSIDE * extent)?;
    hull.run();
    Some(hull.facets(COPLANAR * extent))
}

impl ConvexHull {
    /// This hull with its points moved by the rigid motion `motion`: every facet's normal turned,
    /// its offset moved along it; corners, areas, order and tolerance kept (the same points,
    /// placed elsewhere). What [`convex_hull`] of the moved points gives, up to rounding, without
    /// computing it again.
    pub fn moved(&self, motion: &Isometry3<f64>) -> ConvexHull {
        let facets = self
            .facets
            .iter()
            .map(|facet| {
                let normal = motion.rotation * facet.normal;
                HullFacet {
                    normal,
                    offset: facet.offset + normal.dot(&motion.translation.vector),
                    corners: facet.corners.clone(),
                    area: facet.area,
                }
            })
            .collect();
        ConvexHull {
            facets,
            vertices: self.vertices.clone(),
            tolerance: self.tolerance,
        }
    }
}

/// Bounding-box diagonal of `points[i]` for `i` in `indices`.
fn extent(points: &[Point3<f64>], indices: &[usize]) -> f64 {
    let Some(&first) = indices.first() else {
        return 0.0;
    };
    let (lo, hi) = indices
        .iter()
        .fold((points[first], points[first]), |(lo, hi), &i| {
            (lo.inf(&points[i]), hi.sup(&points[i]))
        });
    (hi - lo).norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube's corners, the centres of its faces and edges, and points inside it.
    fn cube_points() -> Vec<Point3<f64>> {
        let mut points = Vec::new();
        for i in 0..3 {
            for j in 0..3 {
                for k in 0..3 {
                    points.push(Point3::new(
                        f64::from(i) / 2.0,
                        f64::from(j) / 2.0,
                        f64::from(k) / 2.0,
                    ));
                }
            }
        }
        points
    }

    /// Every point is under every facet's plane and every facet is convex and outward.
    fn assert_valid(hull: &ConvexHull, points: &[Point3<f64>]) {
        for facet in &hull.facets {
            for p in points {
                assert!(facet.normal.dot(&p.coords) - facet.offset <= hull.tolerance);
            }
            let n = facet.corners.len();
            for k in 0..n {
                let [a, b, c] = [k, (k + 1) % n, (k + 2) % n].map(|j| points[facet.corners[j]]);
                assert!((b - a).cross(&(c - b)).dot(&facet.normal) > 0.0);
            }
        }
        // Euler: V − E + F = 2, each edge shared by two facets.
        let edges: usize = hull.facets.iter().map(|f| f.corners.len()).sum();
        assert_eq!(edges % 2, 0);
        assert_eq!(
            hull.vertices.len() as i64 - (edges / 2) as i64 + hull.facets.len() as i64,
            2
        );
    }

    #[test]
    fn cube_with_points_on_faces_and_inside_has_six_square_facets() {
        let points = cube_points();
        let hull = convex_hull(&points).unwrap();
        assert_valid(&hull, &points);
        assert_eq!(hull.facets.len(), 6);
        assert_eq!(hull.vertices.len(), 8);
        for facet in &hull.facets {
            assert_eq!(facet.corners.len(), 4);
            assert!((facet.area - 1.0).abs() < 1e-12);
            let largest = facet.normal.abs().max();
            assert!((largest - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn bumps_below_the_tolerance_merge_and_above_it_do_not() {
        let mut points = cube_points();
        // The centre of the top face, raised by a fraction of the extent (√3).
        let top = points
            .iter()
            .position(|p| *p == Point3::new(0.5, 0.5, 1.0))
            .unwrap();
        points[top].z = 1.0 + 0.5 * COPLANAR;
        let hull = convex_hull(&points).unwrap();
        assert_eq!(hull.facets.len(), 6);
        points[top].z = 1.0 + 1e-4;
        let hull = convex_hull(&points).unwrap();
        assert_valid(&hull, &points);
        // The top face becomes a flat pyramid of four triangles.
        assert_eq!(hull.facets.len(), 9);
    }

    #[test]
    fn tetrahedron() {
        let points = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(2.0, 0.0, 0.0),
            Point3::new(0.0, 3.0, 0.0),
            Point3::new(0.0, 0.0, 4.0),
            Point3::new(0.1, 0.1, 0.1),
        ];
        let hull = convex_hull(&points).unwrap();
        assert_valid(&hull, &points);
        assert_eq!(hull.facets.len(), 4);
        assert_eq!(hull.vertices, vec![0, 1, 2, 3]);
        // The largest facet is the slanted one, normal along (1/2, 1/3, 1/4).
        let expected = Vector3::new(6.0, 4.0, 3.0).normalize();
        assert!((hull.facets[0].normal - expected).norm() < 1e-12);
    }

    /// `n` points spread over the unit sphere by the golden angle, deterministically.
    fn spiral(n: u32) -> impl Iterator<Item = Point3<f64>> {
        (0..n).map(move |i| {
            let z = 1.0 - 2.0 * (f64::from(i) + 0.5) / f64::from(n);
            let r = (1.0 - z * z).sqrt();
            let phi = f64::from(i) * 2.399_963_229_728_653;
            Point3::new(r * phi.cos(), r * phi.sin(), z)
        })
    }

    #[test]
    fn points_on_a_sphere_are_all_vertices() {
        let points: Vec<Point3<f64>> = spiral(400)
            .map(|p| Point3::new(p.x + 10.0, p.y, p.z))
            .collect();
        let hull = convex_hull(&points).unwrap();
        assert_valid(&hull, &points);
        assert_eq!(hull.vertices.len(), 400);
        assert_eq!(convex_hull(&points), Some(hull));
    }

    #[test]
    fn every_live_face_and_its_neighbours_share_their_edges() {
        let points: Vec<Point3<f64>> = spiral(300)
            .map(|p| Point3::new(p.x, 2.0 * p.y, p.z))
            // And points inside, which are no corners.
            .chain(cube_points().into_iter().map(|p| p * 0.2))
            .collect();
        let finite: Vec<usize> = (0..points.len()).collect();
        let mut hull = Quickhull::start(&points, &finite, 1e-12).unwrap();
        hull.run();
        let live: Vec<usize> = (0..hull.faces.len())
            .filter(|&f| hull.faces[f].alive)
            .collect();
        // A closed triangulated surface of V vertices has 2V − 4 triangles.
        assert_eq!(live.len(), 2 * 300 - 4);
        for &f in &live {
            let face = &hull.faces[f];
            for k in 0..3 {
                let g = face.neighbours[k];
                assert!(hull.faces[g].alive, "face {f} links a dead face");
                let (from, to) = (face.corners[k], face.corners[(k + 1) % 3]);
                let slot = hull.edge_slot(g, to, from).expect("the shared edge");
                assert_eq!(hull.faces[g].neighbours[slot], f);
            }
        }
    }

    /// `a` and `b` have the same facets (matched by their corners) within `tolerance`.
    fn assert_same_facets(a: &ConvexHull, b: &ConvexHull, tolerance: f64) {
        assert_eq!(a.vertices, b.vertices);
        assert_eq!(a.facets.len(), b.facets.len());
        let key = |facet: &HullFacet| {
            let mut corners = facet.corners.to_vec();
            corners.sort_unstable();
            corners
        };
        for facet in &a.facets {
            let twin = b
                .facets
                .iter()
                .find(|other| key(other) == key(facet))
                .expect("a facet with the same corners");
            assert!((facet.normal - twin.normal).norm() < tolerance);
            assert!((facet.offset - twin.offset).abs() < tolerance);
            assert!((facet.area - twin.area).abs() < tolerance);
        }
    }

    #[test]
    fn a_moved_hull_is_the_hull_of_the_moved_points() {
        let points: Vec<Point3<f64>> = spiral(200)
            .map(|p| Point3::new(3.0 * p.x, p.y, 2.0 * p.z))
            .chain(cube_points())
            .collect();
        let motion = Isometry3::new(Vector3::new(4.0, -2.0, 7.5), Vector3::new(0.3, -1.1, 0.7));
        let moved: Vec<Point3<f64>> = points.iter().map(|p| motion * p).collect();
        let hull = convex_hull(&points).unwrap();
        let carried = hull.moved(&motion);
        assert_valid(&carried, &moved);
        assert_same_facets(&carried, &convex_hull(&moved).unwrap(), 1e-9);
        assert_eq!(carried.tolerance, hull.tolerance);
    }

    #[test]
    fn the_hull_among_candidates_is_the_hull_of_those_points_alone() {
        let inside = cube_points().into_iter().map(|p| p * 0.2);
        let points: Vec<Point3<f64>> = spiral(120).chain(inside).collect();
        // Every other point of the sphere, and the cube (inside the sphere: no corner).
        let candidates: Vec<usize> = (0..points.len())
            .filter(|&i| i % 2 == 0 || i >= 120)
            .collect();
        let among = convex_hull_among(&points, &candidates).unwrap();
        let subset: Vec<Point3<f64>> = candidates.iter().map(|&i| points[i]).collect();
        let alone = convex_hull(&subset).unwrap();
        let renumbered = ConvexHull {
            facets: alone
                .facets
                .iter()
                .map(|facet| HullFacet {
                    corners: facet.corners.iter().map(|&k| candidates[k]).collect(),
                    ..facet.clone()
                })
                .collect(),
            vertices: alone.vertices.iter().map(|&k| candidates[k]).collect(),
            tolerance: alone.tolerance,
        };
        assert_eq!(among, renumbered);
        assert!(among.vertices.iter().all(|i| i % 2 == 0 && *i < 120));
    }

    #[test]
    fn flat_and_empty_point_sets_have_no_hull() {
        let square = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ];
        assert_eq!(convex_hull(&square), None);
        assert_eq!(convex_hull(&[]), None);
        assert_eq!(convex_hull(&[Point3::new(f64::NAN, 0.0, 0.0)]), None);
    }
}
