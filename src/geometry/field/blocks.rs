//! The unsigned distance at every grid node, block by block: one tree query at each block's
//! centre bounds the distance of all its nodes, so a block near a few triangles takes them alone
//! and every other node's search starts from that bound and from the nearest triangle of the
//! node before it.

use nalgebra::{Point3, Vector3};

use super::super::distance::point_triangle_distance;
use super::super::tree::TriangleTree;
use crate::cancel::Cancel;
use crate::parallel::map_nodes;

/// Nodes along each side of a block.
const SIDE: usize = 4;

/// Above this many nearby triangles, a block's nodes each search the tree (from the block's
/// bound) rather than every nearby triangle.
const MAX_NEARBY: usize = 24;

/// The exact distance from every node of the grid `dims` (node `(i, j, k)` at
/// `origin + cell · (i, j, k)`) to the triangles of `tree`, x fastest: the same values, bit for
/// bit, as one [`TriangleTree::distance_to_point`] per node. `None` once `cancel` is set.
///
/// For a block of nodes with centre `c` and half-diagonal `h`, every node is within
/// `reach = d(c) + h` of the surface (a distance is 1-Lipschitz), so its nearest triangle is one
/// whose bounding box lies within `reach` of the block's box.
pub(super) fn node_distances(
    tree: &TriangleTree,
    origin: Point3<f64>,
    cell: f64,
    dims: [usize; 3],
    cancel: &Cancel,
) -> Option<Vec<f64>> {
    let blocks = dims.map(|n| n.div_ceil(SIDE));
    let count = blocks.iter().product();
    let node =
        |i: usize, j: usize, k: usize| origin + Vector3::new(i as f64, j as f64, k as f64) * cell;
    let per_block = map_nodes(count, |b| {
        if cancel.is_cancelled() {
            return Vec::new();
        }
        let (bi, bj, bk) = (
            b % blocks[0],
            (b / blocks[0]) % blocks[1],
            b / (blocks[0] * blocks[1]),
        );
        let start = [bi * SIDE, bj * SIDE, bk * SIDE];
        let end = [0, 1, 2].map(|a| (start[a] + SIDE).min(dims[a]));
        let lo = node(start[0], start[1], start[2]);
        let hi = node(end[0] - 1, end[1] - 1, end[2] - 1);
        let centre = Point3::from((lo.coords + hi.coords) / 2.0);
        // Rounding slack, so the bound is strictly above every node's distance.
        let half_diagonal = (hi - lo).norm() / 2.0;
        let slack = 1e-9 * (half_diagonal + cell);
        let (centre_distance, mut hint) = tree.nearest_to_point(&centre);
        let reach = centre_distance + half_diagonal + slack;
        let mut nearby = Vec::new();
        tree.triangles_near_box(&lo, &hi, reach, &mut nearby);
        let few = nearby.len() <= MAX_NEARBY;
        let triangles = tree.triangles();
        let mut values = Vec::with_capacity(SIDE * SIDE * SIDE);
        for k in start[2]..end[2] {
            for j in start[1]..end[1] {
                for i in start[0]..end[0] {
                    let p = node(i, j, k);
                    let d = if few {
                        nearby
                            .iter()
                            .map(|&t| point_triangle_distance(&p, &triangles[t]))
                            .fold(f64::INFINITY, f64::min)
                    } else {
                        // The last node's nearest triangle starts the search: a neighbour's
                        // is often this node's too, and then only boxes nearer than it are
                        // opened.
                        let (distance, nearest) = tree.nearest_to_point_below(&p, reach, hint);
                        hint = nearest.or(hint);
                        distance
                    };
                    values.push(d);
                }
            }
        }
        values
    });
    if cancel.is_cancelled() {
        return None;
    }
    let mut distances = vec![0.0; dims.iter().product()];
    for (b, values) in per_block.into_iter().enumerate() {
        let (bi, bj, bk) = (
            b % blocks[0],
            (b / blocks[0]) % blocks[1],
            b / (blocks[0] * blocks[1]),
        );
        let start = [bi * SIDE, bj * SIDE, bk * SIDE];
        let end = [0, 1, 2].map(|a| (start[a] + SIDE).min(dims[a]));
        let mut values = values.into_iter();
        for k in start[2]..end[2] {
            for j in start[1]..end[1] {
                for i in start[0]..end[0] {
                    distances[i + dims[0] * (j + dims[1] * k)] = values.next()?;
                }
            }
        }
    }
    Some(distances)
}
