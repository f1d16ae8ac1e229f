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
        (self.lo - p)
            .sup(&(p - self.hi))
            .sup(&Vector3::zeros())
            .norm()
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

    /// [`nearest_to_point`](Self::nearest_to_point) when the distance is known to be below
    /// `bound`, and `hint` is a triangle likely near `p` (a neighbouring point's nearest): both
    /// only prune the search sooner. The same distance, bit for bit, as long as the bound
    /// holds; `(bound, None)` when no triangle is nearer than it.
    pub(crate) fn nearest_to_point_below(
        &self,
        p: &Point3<f64>,
        bound: f64,
        hint: Option<usize>,
    ) -> (f64, Option<usize>) {
        let start = match hint.map(|t| (point_triangle_distance(p, &self.triangles[t]), t)) {
            Some((distance, t)) if distance < bound => (distance, Some(t)),
            _ => (bound, None),
        };
        self.nearest_from(
            start,
            |bounds| bounds.distance_to_point(p),
            |tri| point_triangle_distance(p, tri),
        )
    }

    /// Appends to `out` the index (into [`triangles`](Self::triangles)) of every triangle whose
    /// bounding box lies within `reach` of the box `lo`–`hi`: every triangle that can be nearer
    /// than `reach` to some point of the box. In leaf order.
    pub(crate) fn triangles_near_box(
        &self,
        lo: &Point3<f64>,
        hi: &Point3<f64>,
        reach: f64,
        out: &mut Vec<usize>,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let query = Aabb { lo: *lo, hi: *hi };
        let mut stack = vec![0];
        while let Some(index) = stack.pop() {
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
