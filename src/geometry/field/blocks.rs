//! The unsigned distance at the grid's nodes, block by block: one tree query at each block's
//! centre bounds the distance of all its nodes, so a block near a few triangles takes them alone,
//! the nodes of every other block walk the tree together from that bound and from their
//! distances to the centre's nearest triangle, and a block whose bound keeps it far from the
//! surface can be left for later.

use nalgebra::{Point3, Vector3};

use super::super::distance::point_triangle_distance;
use super::super::tree::TriangleTree;

/// Nodes along each side of a block.
const SIDE: usize = 4;

/// Above this many nearby triangles, a block's nodes search the tree together (from the block's
/// bound) rather than every nearby triangle.
const MAX_NEARBY: usize = 24;

/// The grid `dims` (node `(i, j, k)` at `origin + cell · (i, j, k)`, x fastest) cut into blocks
/// of up to 4×4×4 nodes, numbered x fastest.
#[derive(Debug, Clone, Copy)]
pub(super) struct Blocks {
    origin: Point3<f64>,
    cell: f64,
    dims: [usize; 3],
    /// Blocks along each axis.
    per_axis: [usize; 3],
}

/// What one tree query at a block's centre says of all its nodes.
#[derive(Debug, Clone, Copy)]
pub(super) struct Bound {
    /// Strictly above every node's distance (a distance is 1-Lipschitz): the centre's distance
    /// plus the block's half-diagonal and a rounding slack.
    reach: f64,
    /// At most every node's distance: the centre's distance less the same.
    floor: f64,
    /// The centre's nearest triangle.
    nearest: Option<usize>,
}

impl Bound {
    /// A distance no node of the block is nearer the surface than.
    pub(super) fn floor(&self) -> f64 {
        self.floor
    }
}

impl Blocks {
    /// The blocks of the grid `dims` at `origin`, spacing `cell`.
    pub(super) fn new(origin: Point3<f64>, cell: f64, dims: [usize; 3]) -> Blocks {
        Blocks {
            origin,
            cell,
            dims,
            per_axis: dims.map(|n| n.div_ceil(SIDE)),
        }
    }

    /// Number of blocks.
    pub(super) fn count(&self) -> usize {
        self.per_axis.iter().product()
    }

    /// The block holding the node of flat index `node`.
    pub(super) fn of_node(&self, node: usize) -> usize {
        let [nx, ny, _] = self.dims;
        let (i, j, k) = (node % nx, (node / nx) % ny, node / (nx * ny));
        i / SIDE + self.per_axis[0] * (j / SIDE + self.per_axis[1] * (k / SIDE))
    }

    /// The flat indices of block `b`'s nodes, x fastest within the block.
    pub(super) fn nodes(&self, b: usize) -> impl Iterator<Item = usize> {
        let (start, end) = self.range(b);
        let [nx, ny, _] = self.dims;
        (start[2]..end[2]).flat_map(move |k| {
            (start[1]..end[1])
                .flat_map(move |j| (start[0]..end[0]).map(move |i| i + nx * (j + ny * k)))
        })
    }

    /// Position in block `b`'s node order (that of [`nodes`](Self::nodes)) of the node of flat
    /// index `node`, which must lie in it.
    pub(super) fn position_in_block(&self, b: usize, node: usize) -> usize {
        let (start, end) = self.range(b);
        let [nx, ny, _] = self.dims;
        let (i, j, k) = (node % nx, (node / nx) % ny, node / (nx * ny));
        let [sx, sy, _] = [0, 1, 2].map(|a| end[a] - start[a]);
        (i - start[0]) + sx * ((j - start[1]) + sy * (k - start[2]))
    }

    /// The one tree query at block `b`'s centre.
    pub(super) fn bound(&self, tree: &TriangleTree, b: usize) -> Bound {
        let (lo, hi) = self.corners(b);
        let centre = Point3::from((lo.coords + hi.coords) / 2.0);
        // Rounding slack, so the bound is strictly above every node's distance.
        let half_diagonal = (hi - lo).norm() / 2.0;
        let slack = 1e-9 * (half_diagonal + self.cell);
        let (centre_distance, nearest) = tree.nearest_to_point(&centre);
        Bound {
            reach: centre_distance + half_diagonal + slack,
            floor: centre_distance - half_diagonal - slack,
            nearest,
        }
    }

    /// The exact distance from each node of block `b` to the triangles of `tree`, in the order of
    /// [`nodes`](Self::nodes): the same values, bit for bit, as one
    /// [`TriangleTree::distance_to_point`] per node. `bound` is [`bound`](Self::bound)'s.
    ///
    /// Every node is within `bound.reach` of the surface, so its nearest triangle is one whose
    /// bounding box lies within that of the block's box: with few such, each node takes them
    /// all; otherwise the nodes walk the tree together, each starting from its distance to the
    /// centre's nearest triangle.
    pub(super) fn distances(&self, tree: &TriangleTree, b: usize, bound: Bound) -> Vec<f64> {
        let (lo, hi) = self.corners(b);
        let mut nearby = Vec::new();
        // More than `MAX_NEARBY` is all it needs to know of a block far out.
        tree.triangles_near_box(&lo, &hi, bound.reach, MAX_NEARBY, &mut nearby);
        let triangles = tree.triangles();
        let (start, end) = self.range(b);
        let mut points = Vec::with_capacity(SIDE * SIDE * SIDE);
        for k in start[2]..end[2] {
            for j in start[1]..end[1] {
                for i in start[0]..end[0] {
                    points.push(self.node(i, j, k));
                }
            }
        }
        if nearby.len() <= MAX_NEARBY {
            return points
                .iter()
                .map(|p| {
                    nearby
                        .iter()
                        .map(|&t| point_triangle_distance(p, &triangles[t]))
                        .fold(f64::INFINITY, f64::min)
                })
                .collect();
        }
        let mut best: Vec<f64> = points
            .iter()
            .map(|p| match bound.nearest {
                Some(t) => point_triangle_distance(p, &triangles[t]).min(bound.reach),
                None => bound.reach,
            })
            .collect();
        tree.nearest_to_points_below(&points, &mut best);
        best
    }

    /// The first and one-past-the-last node index of block `b` along each axis.
    fn range(&self, b: usize) -> ([usize; 3], [usize; 3]) {
        let [bx, by, _] = self.per_axis;
        let block = [b % bx, (b / bx) % by, b / (bx * by)];
        let start = block.map(|n| n * SIDE);
        let end = [0, 1, 2].map(|a| (start[a] + SIDE).min(self.dims[a]));
        (start, end)
    }

    /// The positions of block `b`'s first and last node.
    fn corners(&self, b: usize) -> (Point3<f64>, Point3<f64>) {
        let (start, end) = self.range(b);
        (
            self.node(start[0], start[1], start[2]),
            self.node(end[0] - 1, end[1] - 1, end[2] - 1),
        )
    }

    fn node(&self, i: usize, j: usize, k: usize) -> Point3<f64> {
        self.origin + Vector3::new(i as f64, j as f64, k as f64) * self.cell
    }
}
