//! Quickhull: the hull of points in space as triangles, each knowing its three neighbours, the
//! points outside each face kept in its own list (the face's conflict list), so each added point
//! is tested only against the faces its predecessors' cones made.

use nalgebra::{Point3, Vector3};

/// A triangle of the hull under construction, counter-clockwise seen from outside.
pub(super) struct Face {
    pub(super) corners: [usize; 3],
    /// The face across each edge: `neighbours[k]` shares the edge from `corners[k]` to
    /// `corners[(k + 1) % 3]` (walked the other way).
    pub(super) neighbours: [usize; 3],
    /// Unit outward normal (zero for a degenerate triangle, which then sees no point).
    pub(super) normal: Vector3<f64>,
    pub(super) offset: f64,
    /// The points outside this face that no other face claimed first.
    outside: Vec<usize>,
    pub(super) alive: bool,
    /// The last point whose visible set this face was found in.
    seen_by: Option<usize>,
}

/// Marks a neighbour not linked yet (only while a cone is being made).
const UNLINKED: usize = usize::MAX;

/// Quickhull's state: triangles, each knowing its three neighbours.
pub(super) struct Quickhull<'a> {
    pub(super) points: &'a [Point3<f64>],
    pub(super) faces: Vec<Face>,
    /// Every face before this one is dead or has no point outside it. Points are only ever
    /// given to faces as they are made, which come after every other, so the first face with
    /// outside points never lies behind the cursor, and the cursor passes each face once (a scan
    /// from the first face for each point made the hull quadratic in its vertex count).
    cursor: usize,
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
    pub(super) fn start(points: &'a [Point3<f64>], finite: &[usize], epsilon: f64) -> Option<Self> {
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
            cursor: 0,
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
    pub(super) fn edge_slot(&self, f: usize, from: usize, to: usize) -> Option<usize> {
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
            seen_by: None,
        });
        index
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
            }
        }
    }

    /// Adds outside points until none is left: the farthest outside the first face (in the order
    /// faces were made) that has any. O(n log n) for points spread over the hull: that face is
    /// found by a cursor that only moves forward.
    pub(super) fn run(&mut self) {
        while let Some(f) = self.next_face() {
            let outside = &self.faces[f].outside;
            let (mut k, mut farthest) = (0, self.distance(f, outside[0]));
            for (j, &i) in outside.iter().enumerate().skip(1) {
                let distance = self.distance(f, i);
                if distance > farthest {
                    (k, farthest) = (j, distance);
                }
            }
            let apex = self.faces[f].outside.swap_remove(k);
            self.add_point(f, apex);
        }
    }

    /// The first live face with points outside it, the cursor moved up to it.
    fn next_face(&mut self) -> Option<usize> {
        while let Some(face) = self.faces.get(self.cursor) {
            if face.alive && !face.outside.is_empty() {
                return Some(self.cursor);
            }
            self.cursor += 1;
        }
        None
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
}
