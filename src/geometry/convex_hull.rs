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

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use nalgebra::{Point3, Vector3};

use super::polygon::convex_hull_indices;

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
    /// outside, no three collinear.
    pub corners: Vec<usize>,
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
    let finite: Vec<usize> = (0..points.len())
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

/// A triangle of the hull under construction, counter-clockwise seen from outside.
struct Face {
    corners: [usize; 3],
    /// The face across each edge: `neighbours[k]` shares the edge from `corners[k]` to
    /// `corners[(k + 1) % 3]` (walked the other way).
    neighbours: [usize; 3],
    /// Unit outward normal (zero for a degenerate triangle, which then sees no point).
    normal: Vector3<f64>,
    offset: f64,
    /// The points outside this face that no other face claimed first.
    outside: Vec<usize>,
    alive: bool,
    /// Whether the face is in the queue of faces with outside points.
    queued: bool,
    /// The last point whose visible set this face was found in.
    seen_by: Option<usize>,
}

/// Marks a neighbour not linked yet (only while a cone is being made).
const UNLINKED: usize = usize::MAX;

/// Quickhull's state: triangles, each knowing its three neighbours.
struct Quickhull<'a> {
    points: &'a [Point3<f64>],
    faces: Vec<Face>,
    /// The faces with points outside them, lowest index first, so the next one is found without
    /// a scan over every face ever made (which made the hull quadratic in its vertex count).
    /// A face that died while queued is skipped when it comes up.
    pending: BinaryHeap<Reverse<usize>>,
    /// A point counts as outside a face when farther than this above it.
    epsilon: f64,
    /// Buffers [`Quickhull::add_point`] reuses from one point to the next.
    scratch: Scratch,
}

/// What adding one point works with, kept between points so that a hull of many vertices does
/// not allocate five vectors for each.
#[derive(Default)]
struct Scratch {
    /// The faces the point sees.
    visible: Vec<usize>,
    /// Each edge of the horizon, from `a` to `b` on a visible face, with the face beyond it.
    horizon: Vec<(usize, usize, usize)>,
    /// Each horizon edge's first corner and its index, by corner.
    starts: Vec<(usize, usize)>,
    /// The outside points of the faces that die.
    orphans: Vec<usize>,
    /// The new faces, one per horizon edge.
    cone: Vec<usize>,
}

impl<'a> Quickhull<'a> {
    /// The first tetrahedron, with every other point assigned to a face it is outside of; `None`
    /// when the points span no volume.
    fn start(points: &'a [Point3<f64>], finite: &[usize], epsilon: f64) -> Option<Self> {
        let p = |i: usize| points[i];
        // The two farthest apart among the extreme points along the axes.
        let mut extremes = Vec::with_capacity(6);
        for axis in 0..3 {
            let by = |a: &&usize, b: &&usize| p(**a)[axis].total_cmp(&p(**b)[axis]);
            extremes.push(*finite.iter().min_by(by)?);
            extremes.push(*finite.iter().max_by(by)?);
        }
        let mut pair = (extremes[0], extremes[1]);
        for &a in &extremes {
            for &b in &extremes {
                if (p(a) - p(b)).norm() > (p(pair.0) - p(pair.1)).norm() {
                    pair = (a, b);
                }
            }
        }
        let (a, b) = pair;
        let axis = (p(b) - p(a)).normalize();
        let off_line = |i: &usize| {
            let v = p(*i) - p(a);
            (v - axis * v.dot(&axis)).norm()
        };
        let c = *finite
            .iter()
            .max_by(|x, y| off_line(x).total_cmp(&off_line(y)))?;
        if off_line(&c) <= epsilon {
            return None;
        }
        let normal = (p(b) - p(a)).cross(&(p(c) - p(a))).normalize();
        let off_plane = |i: &usize| normal.dot(&(p(*i) - p(a)));
        let d = *finite
            .iter()
            .max_by(|x, y| off_plane(x).abs().total_cmp(&off_plane(y).abs()))?;
        if off_plane(&d).abs() <= epsilon {
            return None;
        }
        let mut hull = Quickhull {
            points,
            faces: Vec::new(),
            pending: BinaryHeap::new(),
            epsilon,
            scratch: Scratch::default(),
        };
        let centre = Point3::from((p(a).coords + p(b).coords + p(c).coords + p(d).coords) / 4.0);
        for corners in [[a, b, c], [a, b, d], [a, c, d], [b, c, d]] {
            let [x, y, z] = corners;
            let outward = (p(y) - p(x)).cross(&(p(z) - p(x))).dot(&(p(x) - centre)) > 0.0;
            hull.add_face(if outward { [x, y, z] } else { [x, z, y] });
        }
        // Each edge of the tetrahedron to the other face that has it, walked the other way.
        for f in 0..4 {
            for k in 0..3 {
                let corners = hull.faces[f].corners;
                let (from, to) = (corners[k], corners[(k + 1) % 3]);
                hull.faces[f].neighbours[k] = (0..4)
                    .find(|&g| g != f && hull.edge_slot(g, to, from).is_some())
                    .expect("a tetrahedron's faces share every edge");
            }
        }
        let others: Vec<usize> = finite
            .iter()
            .copied()
            .filter(|i| ![a, b, c, d].contains(i))
            .collect();
        hull.assign(&others, &[0, 1, 2, 3]);
        Some(hull)
    }

    /// Signed distance of point `i` above face `f`.
    fn distance(&self, f: usize, i: usize) -> f64 {
        let face = &self.faces[f];
        face.normal.dot(&self.points[i].coords) - face.offset
    }

    /// The slot `k` of face `f` whose edge runs from `from` to `to`.
    fn edge_slot(&self, f: usize, from: usize, to: usize) -> Option<usize> {
        let corners = self.faces[f].corners;
        (0..3).find(|&k| corners[k] == from && corners[(k + 1) % 3] == to)
    }

    /// A new face with its neighbours not linked yet.
    fn add_face(&mut self, corners: [usize; 3]) -> usize {
        let [a, b, c] = corners.map(|i| self.points[i]);
        let cross = (b - a).cross(&(c - a));
        let length = cross.norm();
        let normal = if length > 0.0 {
            cross / length
        } else {
            Vector3::zeros()
        };
        let index = self.faces.len();
        self.faces.push(Face {
            corners,
            neighbours: [UNLINKED; 3],
            normal,
            offset: normal.dot(&a.coords),
            outside: Vec::new(),
            alive: true,
            queued: false,
            seen_by: None,
        });
        index
    }

    /// Puts face `f` in the queue unless it is there.
    fn enqueue(&mut self, f: usize) {
        if !self.faces[f].queued {
            self.faces[f].queued = true;
            self.pending.push(Reverse(f));
        }
    }

    /// Gives each of `points` to the first of `faces` it is farthest outside of; points outside
    /// none are inside the hull and dropped.
    fn assign(&mut self, points: &[usize], faces: &[usize]) {
        for &i in points {
            let mut best: Option<(usize, f64)> = None;
            for &f in faces {
                let distance = self.distance(f, i);
                if distance > self.epsilon && best.is_none_or(|(_, d)| distance > d) {
                    best = Some((f, distance));
                }
            }
            if let Some((f, _)) = best {
                self.faces[f].outside.push(i);
                self.enqueue(f);
            }
        }
    }

    /// Adds outside points until none is left: the farthest outside the first face (in the order
    /// faces were made) that has any. O(n log n) for points spread over the hull: each step finds
    /// that face in the queue, not by a scan.
    fn run(&mut self) {
        while let Some(Reverse(f)) = self.pending.pop() {
            self.faces[f].queued = false;
            if !self.faces[f].alive || self.faces[f].outside.is_empty() {
                continue;
            }
            let outside = &self.faces[f].outside;
            let (mut k, mut farthest) = (0, self.distance(f, outside[0]));
            for (j, &i) in outside.iter().enumerate().skip(1) {
                let distance = self.distance(f, i);
                if distance > farthest {
                    (k, farthest) = (j, distance);
                }
            }
            let apex = self.faces[f].outside.swap_remove(k);
            if !self.faces[f].outside.is_empty() {
                self.enqueue(f);
            }
            self.add_point(f, apex);
        }
    }

    /// Replaces the faces `apex` sees (starting from `first`) with a cone from their horizon to
    /// `apex`. When the visible faces' boundary is not one loop (possible only for points within
    /// rounding of several faces' planes), the point is dropped instead.
    fn add_point(&mut self, first: usize, apex: usize) {
        let mut scratch = std::mem::take(&mut self.scratch);
        self.add_point_with(first, apex, &mut scratch);
        self.scratch = scratch;
    }

    /// [`Quickhull::add_point`] with its buffers.
    fn add_point_with(&mut self, first: usize, apex: usize, scratch: &mut Scratch) {
        let Scratch {
            visible,
            horizon,
            starts,
            orphans,
            cone,
        } = scratch;
        visible.clear();
        horizon.clear();
        visible.push(first);
        self.faces[first].seen_by = Some(apex);
        let mut k = 0;
        while k < visible.len() {
            let face = &self.faces[visible[k]];
            let (corners, neighbours) = (face.corners, face.neighbours);
            k += 1;
            for e in 0..3 {
                let (a, b) = (corners[e], corners[(e + 1) % 3]);
                let neighbour = neighbours[e];
                if self.distance(neighbour, apex) > self.epsilon {
                    if self.faces[neighbour].seen_by != Some(apex) {
                        self.faces[neighbour].seen_by = Some(apex);
                        visible.push(neighbour);
                    }
                } else {
                    horizon.push((a, b, neighbour));
                }
            }
        }
        starts.clear();
        starts.extend(horizon.iter().enumerate().map(|(k, &(a, _, _))| (a, k)));
        starts.sort_unstable();
        starts.dedup_by_key(|&mut (a, _)| a);
        if starts.len() != horizon.len() || horizon.len() < 3 {
            return;
        }
        orphans.clear();
        for &f in visible.iter() {
            let face = &mut self.faces[f];
            face.alive = false;
            // Taken, not drained: a dead face keeps no buffer.
            orphans.extend_from_slice(&std::mem::take(&mut face.outside));
        }
        cone.clear();
        for &(a, b, _) in horizon.iter() {
            let face = self.add_face([a, b, apex]);
            cone.push(face);
        }
        // Link each cone face to the face beyond its horizon edge, and to the cone faces on
        // either side: the one starting where it ends, and the one ending where it starts.
        let next = |b: usize| {
            let at = starts
                .binary_search_by_key(&b, |&(a, _)| a)
                .expect("the horizon is one loop");
            starts[at].1
        };
        for (k, &(a, b, beyond)) in horizon.iter().enumerate() {
            let after = cone[next(b)];
            self.faces[cone[k]].neighbours[0] = beyond;
            self.faces[cone[k]].neighbours[1] = after;
            self.faces[after].neighbours[2] = cone[k];
            let slot = self
                .edge_slot(beyond, b, a)
                .expect("the face beyond the horizon has its edge");
            self.faces[beyond].neighbours[slot] = cone[k];
        }
        self.assign(orphans, cone);
    }

    /// The live triangles merged into facets: from the largest triangle down, each facet takes
    /// the triangles reachable across edges whose corners are within `tolerance` of its first
    /// triangle's plane.
    fn facets(&self, tolerance: f64) -> ConvexHull {
        let area = |f: usize| {
            let [a, b, c] = self.faces[f].corners.map(|i| self.points[i]);
            (b - a).cross(&(c - a)).norm() / 2.0
        };
        let mut order: Vec<(f64, usize)> = (0..self.faces.len())
            .filter(|&f| self.faces[f].alive)
            .map(|f| (area(f), f))
            .collect();
        order.sort_unstable_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
        let mut taken = vec![false; self.faces.len()];
        let mut facets = Vec::new();
        for &(_, seed) in &order {
            if taken[seed] {
                continue;
            }
            taken[seed] = true;
            let (normal, offset) = (self.faces[seed].normal, self.faces[seed].offset);
            let on_plane = |f: usize| {
                let face = &self.faces[f];
                face.normal.dot(&normal) > 0.0
                    && face
                        .corners
                        .iter()
                        .all(|&i| (normal.dot(&self.points[i].coords) - offset).abs() <= tolerance)
            };
            let mut group = vec![seed];
            let mut k = 0;
            while k < group.len() {
                let neighbours = self.faces[group[k]].neighbours;
                k += 1;
                for neighbour in neighbours {
                    if !taken[neighbour] && on_plane(neighbour) {
                        taken[neighbour] = true;
                        group.push(neighbour);
                    }
                }
            }
            if let Some(facet) = self.facet(&group) {
                facets.push(facet);
            }
        }
        facets.sort_by(|a, b| b.area.total_cmp(&a.area));
        let mut vertices: Vec<usize> = facets
            .iter()
            .flat_map(|f| f.corners.iter().copied())
            .collect();
        vertices.sort_unstable();
        vertices.dedup();
        ConvexHull {
            facets,
            vertices,
            tolerance,
        }
    }

    /// One facet of the triangles `group`: their corners' convex polygon in the plane of their
    /// mean normal. `None` when that polygon has no area.
    fn facet(&self, group: &[usize]) -> Option<HullFacet> {
        let sum: Vector3<f64> = group
            .iter()
            .map(|&f| {
                let [a, b, c] = self.faces[f].corners.map(|i| self.points[i]);
                (b - a).cross(&(c - a))
            })
            .sum();
        let normal = sum.try_normalize(0.0)?;
        let mut corners: Vec<usize> = group.iter().flat_map(|&f| self.faces[f].corners).collect();
        corners.sort_unstable();
        corners.dedup();
        // (u, w, normal) is right-handed, so counter-clockwise in (u, w) is counter-clockwise
        // seen from outside.
        let u = normal.cross(&least_aligned_axis(&normal)).normalize();
        let w = normal.cross(&u);
        let flat: Vec<[f64; 2]> = corners
            .iter()
            .map(|&i| {
                let p = self.points[i].coords;
                [u.dot(&p), w.dot(&p)]
            })
            .collect();
        let polygon: Vec<usize> = convex_hull_indices(&flat);
        if polygon.len() < 3 {
            return None;
        }
        let area = (0..polygon.len())
            .map(|k| {
                let (a, b) = (flat[polygon[k]], flat[polygon[(k + 1) % polygon.len()]]);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum::<f64>()
            / 2.0;
        let corners: Vec<usize> = polygon.iter().map(|&k| corners[k]).collect();
        let offset = corners
            .iter()
            .map(|&i| normal.dot(&self.points[i].coords))
            .fold(f64::NEG_INFINITY, f64::max);
        Some(HullFacet {
            normal,
            offset,
            corners,
            area,
        })
    }
}

/// The coordinate axis most nearly perpendicular to `v`.
fn least_aligned_axis(v: &Vector3<f64>) -> Vector3<f64> {
    let a = v.abs();
    if a.x <= a.y && a.x <= a.z {
        Vector3::x()
    } else if a.y <= a.z {
        Vector3::y()
    } else {
        Vector3::z()
    }
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
