//! A signed distance grid over one mesh and its smooth tricubic interpolant.

mod blocks;
mod deferred;
mod fast_winding;
mod sign;
mod tricubic;

use nalgebra::{Point3, Vector3};

use super::mesh::TriMesh;
use super::tree::TriangleTree;
use crate::cancel::Cancel;
use crate::parallel::map_nodes;
use blocks::Blocks;
use deferred::Deferred;
use fast_winding::WindingTree;
use tricubic::catmull_rom;

/// Empty cells added around the mesh's bounding box on every side.
const MARGIN_CELLS: usize = 3;

/// Signed distance to a mesh's surface (negative inside) sampled on a regular grid, with a C¹
/// tricubic interpolant.
///
/// Node `(i, j, k)` sits at `origin + cell · (i, j, k)`. Its value is the exact unsigned distance
/// to the surface (from a [`TriangleTree`], block by block: the triangles near a block of nodes
/// are found once) with the sign of the generalized winding number: nodes within half a cell of
/// the surface evaluate it (hierarchically, Barill et al. 2018, exact
/// for nearby triangles); every other node takes the sign of its connected region of such far
/// nodes, and a region touching the grid boundary is outside. A small hole in the surface
/// therefore does not flip the inside.
///
/// The blocks of nodes that one query at their centre shows to be all farther than half a cell
/// from the surface, and that lie outside (most of the box around a mesh), are left out of the
/// build: a thread of the lowest priority computes them afterwards, on a core nothing else
/// wants, and a read that comes first ([`value`](Self::value), [`node_value`](Self::node_value))
/// computes its block itself. The values are the same bits either way.
///
/// Between nodes, [`value`](Self::value) interpolates with Catmull-Rom cubics along each axis
/// (tensor product over the 4×4×4 neighbouring nodes): it passes through the node values, is C¹,
/// and reproduces linear functions exactly; [`value_and_gradient`](Self::value_and_gradient) gives
/// its exact gradient.
#[derive(Debug, Clone)]
pub struct DistanceGrid {
    origin: Point3<f64>,
    cell: f64,
    dims: [usize; 3],
    /// Each node's signed distance, NaN for a node of a deferred block.
    values: Vec<f64>,
    /// The blocks left for later, when there are any.
    deferred: Option<Deferred>,
}

impl DistanceGrid {
    /// The default node spacing for capsules of radius at least `smallest_radius`: half of it,
    /// so the interpolant resolves the surface finer than the thinnest capsule. Any other
    /// positive spacing may be passed to [`new`](Self::new) instead.
    pub fn cell_for_radius(smallest_radius: f64) -> f64 {
        smallest_radius / 2.0
    }

    /// Samples the signed distance to `mesh` every `cell` (project units) over its bounding box
    /// plus three cells on every side. Deterministic, whatever the number of cores used.
    ///
    /// Memory: one `f64` per node, `(extent / cell + 7)` nodes along each axis, so halving `cell`
    /// multiplies it (and the time) by about eight.
    ///
    /// A mesh without triangles gives an empty grid, whose [`value`](Self::value) is `+∞`
    /// everywhere (nothing is inside) with a zero gradient.
    ///
    /// # Panics
    /// If `cell` is not positive and finite, or a triangle has an index out of range.
    pub fn new(mesh: &TriMesh, cell: f64) -> DistanceGrid {
        DistanceGrid::new_unless(mesh, cell, &Cancel::new())
            .unwrap_or_else(|| unreachable!("a flag nobody holds is never set"))
    }

    /// [`new`](Self::new), giving up (`None`) soon after `cancel` is set.
    ///
    /// # Panics
    /// As [`new`](Self::new).
    pub fn new_unless(mesh: &TriMesh, cell: f64, cancel: &Cancel) -> Option<DistanceGrid> {
        assert!(
            cell.is_finite() && cell > 0.0,
            "grid cell must be positive, got {cell}"
        );
        let bounds = mesh.bounding_box().filter(|_| !mesh.triangles.is_empty());
        let Some((lo, hi)) = bounds else {
            return Some(DistanceGrid {
                origin: Point3::origin(),
                cell,
                dims: [0; 3],
                values: Vec::new(),
                deferred: None,
            });
        };
        let margin = cell * MARGIN_CELLS as f64;
        let origin = lo - Vector3::repeat(margin);
        let dims = node_dims(lo, hi, cell);
        let tree = TriangleTree::new(mesh);
        let blocks = Blocks::new(origin, cell, dims);
        // Two neighbouring nodes both farther than half a cell from the surface are joined by an
        // edge that cannot cross it.
        let near = cell / 2.0;
        // Every block that may come within `near` of the surface now; the others once their
        // side of it is known.
        let first = map_nodes(blocks.count(), |b| {
            if cancel.is_cancelled() {
                return None;
            }
            let bound = blocks.bound(&tree, b);
            Some((
                bound,
                (bound.floor() <= near).then(|| blocks.distances(&tree, b, bound)),
            ))
        });
        if cancel.is_cancelled() {
            return None;
        }
        let mut distances = vec![f64::NAN; dims.iter().product()];
        let mut far = Vec::new();
        for (b, block) in first.into_iter().enumerate() {
            match block? {
                (_, Some(values)) => {
                    for (node, value) in blocks.nodes(b).zip(values) {
                        distances[node] = value;
                    }
                }
                (bound, None) => far.push((b, bound)),
            }
        }
        let node_at = |index: usize| {
            let [nx, ny, _] = dims;
            let [i, j, k] = [index % nx, (index / nx) % ny, index / (nx * ny)];
            origin + Vector3::new(i as f64, j as f64, k as f64) * cell
        };
        let winding = WindingTree::new(&tree);
        let inside = sign::inside_nodes(dims, node_at, &distances, near, &winding);
        // A far block lies in one region of far nodes, so its first node's side is its own.
        let (far_inside, mut far_outside): (Vec<_>, Vec<_>) = far
            .into_iter()
            .partition(|&(b, _)| blocks.nodes(b).next().is_some_and(|node| inside[node]));
        let computed = map_nodes(far_inside.len(), |n| {
            let (b, bound) = far_inside[n];
            (!cancel.is_cancelled()).then(|| blocks.distances(&tree, b, bound))
        });
        for (&(b, _), values) in far_inside.iter().zip(computed) {
            for (node, value) in blocks.nodes(b).zip(values?) {
                distances[node] = value;
            }
        }
        let values: Vec<f64> = distances
            .iter()
            .zip(&inside)
            .map(|(&d, &inside)| if inside { -d } else { d })
            .collect();
        // Nearest the surface first: a solve's iterates stray outside by a little far more
        // often than by a lot, so its reads more often find their blocks done.
        far_outside.sort_by(|(a, x), (b, y)| x.floor().total_cmp(&y.floor()).then(a.cmp(b)));
        let pending: Vec<usize> = far_outside.into_iter().map(|(b, _)| b).collect();
        let deferred = (!pending.is_empty()).then(|| Deferred::new(blocks, tree, pending));
        let grid = DistanceGrid {
            origin,
            cell,
            dims,
            values,
            deferred,
        };
        (!cancel.is_cancelled()).then_some(grid)
    }

    /// A grid rebuilt from the parts [`new`](Self::new) produced for `mesh` (read back from a
    /// cache): [`stored_values`](Self::stored_values), NaN where a block was deferred, whose
    /// distances are then computed from `mesh` as [`new`](Self::new) does. `None` when they do
    /// not make a grid: `cell` not positive and finite, `origin` not finite, `values` not one per
    /// node (x fastest), a non-empty grid with fewer than four nodes along some axis (the
    /// interpolant needs a 4×4×4 neighbourhood), or deferred nodes and a mesh without triangles.
    pub fn from_parts(
        origin: Point3<f64>,
        cell: f64,
        dims: [usize; 3],
        values: Vec<f64>,
        mesh: &TriMesh,
    ) -> Option<DistanceGrid> {
        let count = dims
            .iter()
            .try_fold(1usize, |count, &n| count.checked_mul(n))?;
        let usable = cell.is_finite()
            && cell > 0.0
            && origin.iter().all(|c| c.is_finite())
            && values.len() == count
            && (count == 0 || dims.iter().all(|&n| n >= 4));
        let deferred = values.iter().any(|v| v.is_nan());
        if !usable || (deferred && mesh.triangles.is_empty()) {
            return None;
        }
        let deferred = deferred.then(|| {
            let blocks = Blocks::new(origin, cell, dims);
            let pending = (0..blocks.count())
                .filter(|&b| blocks.nodes(b).any(|node| values[node].is_nan()))
                .collect();
            Deferred::new(blocks, TriangleTree::new(mesh), pending)
        });
        Some(DistanceGrid {
            origin,
            cell,
            dims,
            values,
            deferred,
        })
    }

    /// Every node's signed distance as computed so far, x fastest (node `(i, j, k)` at
    /// `i + nx · (j + ny · k)`): NaN for a node of a block deferred by [`new`](Self::new), even
    /// once it has been read. What a cache stores; [`node_value`](Self::node_value) gives every
    /// node's value.
    pub fn stored_values(&self) -> &[f64] {
        &self.values
    }

    /// Number of nodes whose distance [`new`](Self::new) left out of the build.
    pub fn deferred_nodes(&self) -> usize {
        self.values.iter().filter(|v| v.is_nan()).count()
    }

    /// Number of nodes [`new`](Self::new) would sample for `mesh` at spacing `cell`, counted in
    /// floating point so that a tiny cell gives a huge count (or infinity) rather than an
    /// overflow: for checking a spacing before building its grid.
    pub fn planned_nodes(mesh: &TriMesh, cell: f64) -> f64 {
        match mesh.bounding_box().filter(|_| !mesh.triangles.is_empty()) {
            Some((lo, hi)) if cell > 0.0 => (0..3)
                .map(|a| ((hi[a] - lo[a]) / cell).ceil() + (2 * MARGIN_CELLS + 1) as f64)
                .product(),
            Some(_) => f64::INFINITY,
            None => 0.0,
        }
    }

    /// Number of nodes [`new`](Self::new) samples for `mesh` at spacing `cell`.
    pub fn node_count(mesh: &TriMesh, cell: f64) -> usize {
        match mesh.bounding_box().filter(|_| !mesh.triangles.is_empty()) {
            Some((lo, hi)) if cell.is_finite() && cell > 0.0 => {
                node_dims(lo, hi, cell).iter().product()
            }
            _ => 0,
        }
    }

    /// Node spacing, project units.
    pub fn cell(&self) -> f64 {
        self.cell
    }

    /// Position of node `(0, 0, 0)`.
    pub fn origin(&self) -> Point3<f64> {
        self.origin
    }

    /// Number of nodes along x, y and z (`[0, 0, 0]` for an empty grid).
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// Position of node `index = [i, j, k]`.
    pub fn node(&self, index: [usize; 3]) -> Point3<f64> {
        self.origin + Vector3::new(index[0] as f64, index[1] as f64, index[2] as f64) * self.cell
    }

    /// Signed distance at node `index`, or `None` outside the grid. A node of a deferred block
    /// has its block computed now.
    pub fn node_value(&self, index: [usize; 3]) -> Option<f64> {
        let [i, j, k] = index;
        let [nx, ny, nz] = self.dims;
        (i < nx && j < ny && k < nz).then(|| self.value_of(i + nx * (j + ny * k)))
    }

    /// As [`node_value`](Self::node_value), but `+∞` for a node of a deferred block, which lies
    /// outside farther than half a cell from the surface: for a pass over every node that needs
    /// only the inside, without computing what was deferred.
    pub fn node_value_or_far(&self, index: [usize; 3]) -> Option<f64> {
        let [i, j, k] = index;
        let [nx, ny, nz] = self.dims;
        (i < nx && j < ny && k < nz).then(|| {
            let value = self.values[i + nx * (j + ny * k)];
            if value.is_nan() {
                f64::INFINITY
            } else {
                value
            }
        })
    }

    /// The interpolated signed distance at `p` (negative inside).
    pub fn value(&self, p: &Point3<f64>) -> f64 {
        self.value_and_gradient(p).0
    }

    /// The interpolated signed distance at `p` and its exact gradient.
    ///
    /// Inside the box of nodes that have a full 4×4×4 neighbourhood (one cell in from the grid's
    /// faces, still at least two cells outside the mesh), this is the Catmull-Rom interpolant.
    /// Farther out, `p` is clamped to that box at `q` and the result is `value(q) + |p − q|`,
    /// continuous, growing at unit rate away from the box as a distance does, with its exact
    /// gradient.
    pub fn value_and_gradient(&self, p: &Point3<f64>) -> (f64, Vector3<f64>) {
        if self.values.is_empty() {
            return (f64::INFINITY, Vector3::zeros());
        }
        let lo = self.origin + Vector3::repeat(self.cell);
        let hi = self.node(self.dims.map(|n| n - 2));
        let q = p.sup(&lo).inf(&hi);
        let (value, mut gradient) = self.interpolate(&q);
        let outside = p - q;
        let reach = outside.norm();
        if reach == 0.0 {
            return (value, gradient);
        }
        for axis in 0..3 {
            if outside[axis] != 0.0 {
                gradient[axis] = 0.0;
            }
        }
        (value + reach, gradient + outside / reach)
    }

    /// Catmull-Rom interpolation at `q`, which must lie in the box of full neighbourhoods.
    fn interpolate(&self, q: &Point3<f64>) -> (f64, Vector3<f64>) {
        let local = (q - self.origin) / self.cell;
        let mut base = [0usize; 3];
        let mut weights = [[0.0; 4]; 3];
        let mut derivatives = [[0.0; 4]; 3];
        for axis in 0..3 {
            // Cell [base, base + 1] with nodes base − 1 ..= base + 2 all in the grid.
            let cell_index = (local[axis].floor().max(1.0) as usize).min(self.dims[axis] - 3);
            base[axis] = cell_index - 1;
            let t = local[axis] - cell_index as f64;
            (weights[axis], derivatives[axis]) = catmull_rom(t);
        }
        let [nx, ny, _] = self.dims;
        let mut value = 0.0;
        let mut gradient = Vector3::zeros();
        for k in 0..4 {
            for j in 0..4 {
                let row = base[0] + nx * (base[1] + j + ny * (base[2] + k));
                for i in 0..4 {
                    let v = self.value_of(row + i);
                    let (wx, wy, wz) = (weights[0][i], weights[1][j], weights[2][k]);
                    value += wx * wy * wz * v;
                    gradient += Vector3::new(
                        derivatives[0][i] * wy * wz,
                        wx * derivatives[1][j] * wz,
                        wx * wy * derivatives[2][k],
                    ) * v;
                }
            }
        }
        (value, gradient / self.cell)
    }

    /// The signed distance of the node of flat index `index`, computing its block if it was
    /// deferred (deferred blocks lie outside, so the distance is the value).
    fn value_of(&self, index: usize) -> f64 {
        let value = self.values[index];
        match &self.deferred {
            Some(deferred) if value.is_nan() => deferred.distance(index),
            _ => value,
        }
    }
}

/// Nodes along each axis for the box `lo`–`hi`: the box plus [`MARGIN_CELLS`] on every side.
fn node_dims(lo: Point3<f64>, hi: Point3<f64>, cell: f64) -> [usize; 3] {
    let extent = hi - lo;
    [0, 1, 2].map(|a| (extent[a] / cell).ceil() as usize + 2 * MARGIN_CELLS + 1)
}
