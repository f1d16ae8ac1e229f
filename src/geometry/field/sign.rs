//! Signs of the grid nodes: winding numbers near the surface, flood-filled regions elsewhere.

use super::fast_winding::WindingTree;
use crate::parallel::map_nodes;

/// `true` for every node inside the surface, in the grid's node order (x fastest).
///
/// A node within `near` of the surface (`distances` holds the unsigned distances, NaN for a node
/// known to be farther than `near` without its distance) is inside when its winding number
/// exceeds ½. The other nodes form 6-connected regions that cannot cross the surface (with
/// `near` at least half the spacing, the edge between two neighbours both farther than `near`
/// from it would need a point of the surface within `near` of one of them); a region touching
/// the grid boundary is outside, any other takes the sign of the winding number at its first node
/// in node order.
pub(super) fn inside_nodes(
    dims: [usize; 3],
    node: impl Fn(usize) -> nalgebra::Point3<f64> + Sync,
    distances: &[f64],
    near: f64,
    winding: &WindingTree,
) -> Vec<bool> {
    let count = distances.len();
    let near_inside = map_nodes(count, |i| {
        distances[i] <= near && winding.winding_number(&node(i)) > 0.5
    });
    let mut inside = near_inside;
    let mut visited: Vec<bool> = distances.iter().map(|&d| d <= near).collect();
    let mut region = Vec::new();
    for seed in 0..count {
        if visited[seed] {
            continue;
        }
        visited[seed] = true;
        region.clear();
        region.push(seed);
        let mut touches_boundary = false;
        let mut next = 0;
        while next < region.len() {
            let index = region[next];
            next += 1;
            let (x, y, z) = split(index, dims);
            if [x, y, z].contains(&0) || x + 1 == dims[0] || y + 1 == dims[1] || z + 1 == dims[2] {
                touches_boundary = true;
            }
            for neighbour in neighbours(x, y, z, dims) {
                if !visited[neighbour] {
                    visited[neighbour] = true;
                    region.push(neighbour);
                }
            }
        }
        let region_inside = !touches_boundary && winding.winding_number(&node(seed)) > 0.5;
        for &index in &region {
            inside[index] = region_inside;
        }
    }
    inside
}

/// Node index to `(x, y, z)`, x fastest.
fn split(index: usize, dims: [usize; 3]) -> (usize, usize, usize) {
    (
        index % dims[0],
        (index / dims[0]) % dims[1],
        index / (dims[0] * dims[1]),
    )
}

/// Indices of the up to six face neighbours of node `(x, y, z)`.
fn neighbours(x: usize, y: usize, z: usize, dims: [usize; 3]) -> impl Iterator<Item = usize> {
    let index = move |x: usize, y: usize, z: usize| x + dims[0] * (y + dims[1] * z);
    [
        (x > 0).then(|| index(x - 1, y, z)),
        (x + 1 < dims[0]).then(|| index(x + 1, y, z)),
        (y > 0).then(|| index(x, y - 1, z)),
        (y + 1 < dims[1]).then(|| index(x, y + 1, z)),
        (z > 0).then(|| index(x, y, z - 1)),
        (z + 1 < dims[2]).then(|| index(x, y, z + 1)),
    ]
    .into_iter()
    .flatten()
}
