//! A bounding-volume hierarchy over a mesh's triangles, for many exact distance queries against
//! one mesh (a distance field samples hundreds of thousands of points).
//!
//! Building costs `O(n log n)`; a query then visits the boxes nearest first and skips every box
//! farther than the best distance found, so it touches a few leaves instead of every triangle.
//! Results are exactly those of [`distance_to_point`](super::distance_to_point) and
//! [`distance_to_segment`](super::distance_to_segment).

use nalgebra::{Point3, Vector3};

use super::distance::{point_triangle_distance, segment_triangle_distance};
use super::mesh::TriMesh;

/// Triangles per leaf, at most.
const LEAF_SIZE: usize = 4;

/// An axis-aligned bounding box.
#[derive(Debug, Clone, Copy)]
struct Aabb {
    lo: Point3<f64>,
    hi: Point3<f64>,
}

impl Aabb {
    fn of_triangle(tri: &[Point3<f64>; 3]) -> Aabb {
        Aabb {
            lo: tri[0].inf(&tri[1]).inf(&tri[2]),
            hi: tri[0].sup(&tri[1]).sup(&tri[2]),
        }
    }

    fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            lo: self.lo.inf(&other.lo),
            hi: self.hi.sup(&other.hi),
        }
    }

    /// Distance from `p` to the box (0 inside).
    fn distance_to_point(&self, p: &Point3<f64>) -> f64 {
        self.squared_distance_to_point(p).sqrt()
    }

    /// Squared distance from `p` to the box (0 inside).
    fn squared_distance_to_point(&self, p: &Point3<f64>) -> f64 {
        (self.lo - p)
            .sup(&(p - self.hi))
            .sup(&Vector3::zeros())
            .norm_squared()
    }

    /// A lower bound on the distance from any point of `other` to the box: the gap between the
    /// two boxes.
    fn distance_to_box(&self, other: &Aabb) -> f64 {
        (self.lo - other.hi)
            .sup(&(other.lo - self.hi))
            .sup(&Vector3::zeros())
            .norm()
    }
}

/// A node: a box and either two children or a run of triangles.
#[derive(Debug, Clone)]
struct Node {
    bounds: Aabb,
    /// Children node indices, or `None` for a leaf.
    children: Option<[usize; 2]>,
    /// For a leaf, the range of `order` holding its triangles.
    first: usize,
    count: usize,
}

/// A bounding-volume hierarchy over the triangles of one mesh, for exact distance queries.
///
/// Holds a copy of each triangle's corners, so it does not borrow the mesh.
#[derive(Debug, Clone)]
pub struct TriangleTree {
    triangles: Vec<[Point3<f64>; 3]>,
    nodes: Vec<Node>,
}

impl TriangleTree {
    /// Builds the tree over every triangle of `mesh` (median split along the longest axis of the
    /// triangles' centroids). Deterministic.
    ///
    /// # Panics
    /// If a triangle has an index out of range.
    pub fn new(mesh: &TriMesh) -> TriangleTree {
        let all: Vec<[Point3<f64>; 3]> = (0..mesh.triangles.len())
            .map(|i| mesh.triangle(i))
            .collect();
        let centroids: Vec<Point3<f64>> = all
            .iter()
            .map(|t| Point3::from((t[0].coords + t[1].coords + t[2].coords) / 3.0))
            .collect();
        let mut order: Vec<usize> = (0..all.len()).collect();
        let mut nodes = Vec::new();
        if !all.is_empty() {
            build(&all, &centroids, &mut order, 0, all.len(), &mut nodes);
        }
        // Store the triangles in leaf order so a leaf's triangles are contiguous.
        let triangles = order.iter().map(|&i| all[i]).collect();
        TriangleTree { triangles, nodes }
    }

    /// The triangles, in leaf order: each node's triangles are a contiguous range.
    pub(crate) fn triangles(&self) -> &[[Point3<f64>; 3]] {
        &self.triangles
    }

    /// How many nodes there are; node 0 is the root, and a node comes before its children.
    pub(crate) fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The children of node `index`, or `None` for a leaf.
    pub(crate) fn children(&self, index: usize) -> Option<[usize; 2]> {
        self.nodes[index].children
    }

    /// The range of [`triangles`](Self::triangles) under node `index`.
    pub(crate) fn triangle_range(&self, index: usize) -> std::ops::Range<usize> {
        let node = &self.nodes[index];
        node.first..node.first + node.count
    }

    /// Unsigned distance from `p` to the surface (`+∞` without triangles).
    pub fn distance_to_point(&self, p: &Point3<f64>) -> f64 {
        self.nearest(
            |bounds| bounds.distance_to_point(p),
            |tri| point_triangle_distance(p, tri),
        )
    }

    /// The distance from `p` to the surface and the nearest triangle (an index into
    /// [`triangles`](Self::triangles)), `None` without triangles.
    pub(crate) fn nearest_to_point(&self, p: &Point3<f64>) -> (f64, Option<usize>) {
        self.nearest_from(
            (f64::INFINITY, None),
            |bounds| bounds.distance_to_point(p),
            |tri| point_triangle_distance(p, tri),
        )
    }

    /// Lowers each `best[i]` to the distance from `points[i]` to the surface wherever that is
    /// below it: one walk of the tree for up to 64 points near one another (a block of a
    /// distance grid), each box opened only for the points it may hold a nearer triangle for.
    /// Each lowered value is, bit for bit, [`distance_to_point`](Self::distance_to_point)'s:
    /// the least [`point_triangle_distance`] of any triangle.
    ///
    /// # Panics
    /// If there are more than 64 points or not one `best` per point.
    pub(crate) fn nearest_to_points_below(&self, points: &[Point3<f64>], best: &mut [f64]) {
        assert!(points.len() <= 64 && points.len() == best.len());
        if self.nodes.is_empty() || points.is_empty() {
            return;
        }
        // A box is opened for a point while its squared gap is below the squared best, made a
        // little larger so that rounding never closes a box holding a nearer triangle.
        const GENEROUS: f64 = 1.0 + 1e-9;
        let mut open_below = [0.0; 64];
        for (open, best) in open_below.iter_mut().zip(best.iter()) {
            *open = best * best * GENEROUS;
        }
        let centre = Point3::from(
            points
                .iter()
                .fold(Vector3::zeros(), |sum, p| sum + p.coords)
                / points.len() as f64,
        );
        let everyone = u64::MAX >> (64 - points.len());
        // Each entry a node and the points it may matter to, one bit each; the child nearer the
        // points' centre is visited first, so the bounds fall early.
        let mut stack: Vec<(usize, u64)> = vec![(0, everyone)];
        while let Some((index, asking)) = stack.pop() {
            let node = &self.nodes[index];
            let open = bits_where(asking, |i| {
                node.bounds.squared_distance_to_point(&points[i]) < open_below[i]
            });
            if open == 0 {
                continue;
            }
            match node.children {
                Some([left, right]) => {
                    let to =
                        |child: usize| self.nodes[child].bounds.squared_distance_to_point(&centre);
                    let (near, far) = if to(left) <= to(right) {
                        (left, right)
                    } else {
                        (right, left)
                    };
                    stack.push((far, open));
                    stack.push((near, open));
                }
                None => {
                    for t in node.first..node.first + node.count {
                        let triangle = &self.triangles[t];
                        let bounds = Aabb::of_triangle(triangle);
                        let near = bits_where(open, |i| {
                            bounds.squared_distance_to_point(&points[i]) < open_below[i]
                        });
                        for i in bits(near) {
                            let distance = point_triangle_distance(&points[i], triangle);
                            if distance < best[i] {
                                best[i] = distance;
                                open_below[i] = distance * distance * GENEROUS;
                            }
                        }
                    }
                }
            }
        }
    }

    /// Appends to `out` the index (into [`triangles`](Self::triangles)) of every triangle whose
    /// bounding box lies within `reach` of the box `lo`–`hi`: every triangle that can be nearer
    /// than `reach` to some point of the box. In leaf order. Stops as soon as `out` holds more
    /// than `most`: then it holds more than `most` such triangles, not every one.
    pub(crate) fn triangles_near_box(
        &self,
        lo: &Point3<f64>,
        hi: &Point3<f64>,
        reach: f64,
        most: usize,
        out: &mut Vec<usize>,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let query = Aabb { lo: *lo, hi: *hi };
        let mut stack = vec![0];
        while let Some(index) = stack.pop() {
            if out.len() > most {
                return;
            }
            let node = &self.nodes[index];
            if node.bounds.distance_to_box(&query) > reach {
                continue;
            }
            match node.children {
                Some([left, right]) => {
                    stack.push(right);
                    stack.push(left);
                }
                None => out.extend((node.first..node.first + node.count).filter(|&t| {
                    Aabb::of_triangle(&self.triangles[t]).distance_to_box(&query) <= reach
                })),
            }
        }
    }

    /// Distance from the segment `a`–`b` to the surface: 0 when it crosses the surface (`+∞`
    /// without triangles).
    pub fn distance_to_segment(&self, a: &Point3<f64>, b: &Point3<f64>) -> f64 {
        let segment = Aabb {
            lo: a.inf(b),
            hi: a.sup(b),
        };
        self.nearest(
            |bounds| bounds.distance_to_box(&segment),
            |tri| segment_triangle_distance(a, b, tri),
        )
    }

    /// The minimum of `exact` over all triangles, visiting nodes nearest first by `lower_bound`
    /// (never more than `exact` of any triangle inside the box) and skipping those that cannot
    /// beat the best so far.
    fn nearest(
        &self,
        lower_bound: impl Fn(&Aabb) -> f64,
        exact: impl Fn(&[Point3<f64>; 3]) -> f64,
    ) -> f64 {
        self.nearest_from((f64::INFINITY, None), lower_bound, exact)
            .0
    }

    /// [`nearest`](Self::nearest), starting from `start` as the best so far (a value and the
    /// triangle that reached it, if any), and the triangle reaching the minimum (the first
    /// visited among equals; `start`'s when none beats it).
    fn nearest_from(
        &self,
        start: (f64, Option<usize>),
        lower_bound: impl Fn(&Aabb) -> f64,
        exact: impl Fn(&[Point3<f64>; 3]) -> f64,
    ) -> (f64, Option<usize>) {
        let (mut best, mut nearest) = start;
        if self.nodes.is_empty() {
            return (best, nearest);
        }
        // A depth-first stack that pushes the farther child first, so the nearer is visited next.
        let mut stack = vec![(lower_bound(&self.nodes[0].bounds), 0)];
        while let Some((bound, index)) = stack.pop() {
            if bound >= best {
                continue;
            }
            let node = &self.nodes[index];
            match node.children {
                Some([left, right]) => {
                    let left_bound = lower_bound(&self.nodes[left].bounds);
                    let right_bound = lower_bound(&self.nodes[right].bounds);
                    if left_bound <= right_bound {
                        stack.push((right_bound, right));
                        stack.push((left_bound, left));
                    } else {
                        stack.push((left_bound, left));
                        stack.push((right_bound, right));
                    }
                }
                None => {
                    for t in node.first..node.first + node.count {
                        let distance = exact(&self.triangles[t]);
                        if distance < best {
                            (best, nearest) = (distance, Some(t));
                        }
                    }
                    if best == 0.0 {
                        return (best, nearest);
                    }
                }
            }
        }
        (best, nearest)
    }
}

/// The set bits of `set` (point indices) for which `keep` holds.
fn bits_where(set: u64, keep: impl Fn(usize) -> bool) -> u64 {
    bits(set)
        .filter(|&i| keep(i))
        .fold(0, |kept, i| kept | 1 << i)
}

/// The indices of the set bits of `set`, lowest first.
fn bits(mut set: u64) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (set != 0).then(|| {
            let i = set.trailing_zeros() as usize;
            set &= set - 1;
            i
        })
    })
}

/// Builds the subtree over `order[first..first + count]`, returns its node index.
fn build(
    triangles: &[[Point3<f64>; 3]],
    centroids: &[Point3<f64>],
    order: &mut [usize],
    first: usize,
    count: usize,
    nodes: &mut Vec<Node>,
) -> usize {
    let slice = &mut order[first..first + count];
    let bounds = slice
        .iter()
        .map(|&i| Aabb::of_triangle(&triangles[i]))
        .reduce(|a, b| a.union(&b))
        .expect("a node has at least one triangle");
    let index = nodes.len();
    nodes.push(Node {
        bounds,
        children: None,
        first,
        count,
    });
    if count <= LEAF_SIZE {
        return index;
    }
    let (lo, hi) = slice.iter().fold(
        (
            Point3::from([f64::INFINITY; 3]),
            Point3::from([f64::NEG_INFINITY; 3]),
        ),
        |(lo, hi), &i| (lo.inf(&centroids[i]), hi.sup(&centroids[i])),
    );
    let extent = hi - lo;
    let axis = extent.imax();
    let half = count / 2;
    // Ties broken by triangle index, so the tree does not depend on the sort's stability.
    slice.select_nth_unstable_by(half, |&a, &b| {
        centroids[a][axis]
            .total_cmp(&centroids[b][axis])
            .then(a.cmp(&b))
    });
    let left = build(triangles, centroids, order, first, half, nodes);
    let right = build(
        triangles,
        centroids,
        order,
        first + half,
        count - half,
        nodes,
    );
    nodes[index].children = Some([left, right]);
    index
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix64;

    /// A vector with coordinates in [−1, 1).
    fn spread(random: &mut SplitMix64) -> Vector3<f64> {
        random.vector() * 2.0 - Vector3::repeat(1.0)
    }

    /// 300 scattered triangles of assorted sizes, some long and thin.
    fn scattered() -> TriMesh {
        let mut random = SplitMix64::new(7);
        let mut mesh = TriMesh {
            positions: Vec::new(),
            triangles: Vec::new(),
        };
        for t in 0..300u32 {
            let corner = Point3::from(spread(&mut random) * 10.0);
            let size = random.uniform(0.05, 3.0);
            for _ in 0..3 {
                mesh.positions.push(corner + spread(&mut random) * size);
            }
            mesh.triangles.push([3 * t, 3 * t + 1, 3 * t + 2]);
        }
        mesh
    }

    #[test]
    fn points_walking_together_get_each_one_s_distance_bit_for_bit() {
        let tree = TriangleTree::new(&scattered());
        let mut random = SplitMix64::new(11);
        for round in 0..40 {
            // A clump of points (a grid block), near the triangles or far out.
            let centre =
                Point3::from(spread(&mut random) * if round % 2 == 0 { 8.0 } else { 40.0 });
            let count = 1 + random.below(64);
            let points: Vec<Point3<f64>> = (0..count)
                .map(|_| centre + spread(&mut random) * random.uniform(0.0, 2.0))
                .collect();
            let exact: Vec<f64> = points.iter().map(|p| tree.distance_to_point(p)).collect();
            // From no bound, from bounds just above the distances, and from a bound below some
            // of them, which those keep.
            let starts: [Vec<f64>; 3] = [
                vec![f64::INFINITY; count],
                exact.iter().map(|d| d * 1.01 + 1e-3).collect(),
                exact.iter().map(|_| exact[0]).collect(),
            ];
            for start in starts {
                let mut best = start.clone();
                tree.nearest_to_points_below(&points, &mut best);
                for i in 0..count {
                    let expected = exact[i].min(start[i]);
                    assert_eq!(best[i].to_bits(), expected.to_bits(), "point {i}");
                }
            }
        }
    }
}
