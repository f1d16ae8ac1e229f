//! A curve skeleton of one closed mesh, as straight segments whose midpoints seed capsules
//! (section 4.5 of Prévost et al. 2016: one capsule per skeleton segment).
//!
//! The paper uses mean curvature skeletons (Tagliasacchi et al. 2012), which contract the
//! surface mesh and need a well-conditioned, remeshed surface. This module uses voxel thinning
//! instead: it needs only inside or outside per grid node, which the [`DistanceGrid`] already
//! provides robustly (winding numbers, tolerant of small holes), it never fails on a bad
//! triangulation, it is exact integer work once the voxels are known (so deterministic), and
//! for seeding capsules a skeleton within a voxel of the medial axis is good enough.
//!
//! 1. **Voxels.** The grid nodes with a negative signed distance. [`Skeleton::new`] builds its
//!    own grid: a probe of [`PROBE_CELLS`] cells across the longest side of the bounding box
//!    finds the thickest part's inscribed radius, then the grid has at least [`COARSE_CELLS`]
//!    cells across and [`MIN_RADIUS_CELLS`] cells in that radius, with at most [`MAX_NODES`]
//!    nodes.
//! 2. **Thinning.** Directional sequential thinning (Lee, Kashyap and Chu 1994): layer by layer
//!    from the six face directions, removing simple voxels that do not end a curve, until one
//!    voxel wide. Topology is kept (26-connected object, 6-connected background).
//! 3. **Graph.** Junctions are 26-connected clusters of voxels with three or more neighbours,
//!    ends have one; the chains between them are branches. Spurs are pruned: an end branch
//!    whose end is closer to its junction than [`SPUR_RATIO`] times the larger inscribed radius
//!    of the two is noise from a corner, a bump or the fork at the end of a flat part. Links
//!    between junctions shorter than [`CONTRACT_RATIO`] times their radius are contracted, and
//!    loops shorter than [`LOOP_RATIO`] times their node's radius removed, one at a time, the
//!    smallest first.
//! 4. **Segments.** Each branch is split by Douglas-Peucker with a tolerance of
//!    [`BEND_RATIO`] times its mean inscribed radius (at least one cell), so a straight limb
//!    is one segment and a bent one a few; a chord whose midpoint is not inside is split too.
//!
//! Every threshold is a ratio to a radius or a cell, so the result does not depend on the units.
//! When thinning leaves nothing usable (a mesh thinner than the grid can resolve), the skeleton
//! falls back to one segment along the principal axis of inertia through the centroid, clipped
//! to the interior.

mod graph;
mod simplify;
mod thinning;

use nalgebra::{Matrix3, Point3, SymmetricEigen, Vector3};

use super::field::DistanceGrid;
use super::mass::mass_properties;
use super::mesh::TriMesh;
use crate::cancel::Cancel;
use graph::{Field, Graph, Pruning};

/// Cells across the longest side of the bounding box in [`Skeleton::new`]'s probe for the
/// thickest part.
pub(crate) const PROBE_CELLS: f64 = 24.0;
/// The fewest cells across the longest side of the bounding box in [`Skeleton::new`]'s grid.
pub(crate) const COARSE_CELLS: f64 = 48.0;
/// The fewest cells [`Skeleton::new`]'s grid puts in the inscribed radius of the thickest part.
pub(crate) const MIN_RADIUS_CELLS: f64 = 4.0;
/// The most nodes [`Skeleton::new`] lets its grid have (it caps the refinement).
pub(crate) const MAX_NODES: usize = 120_000;
/// Spur pruning: an end branch goes when the distance from its junction to its end is below
/// this times the larger inscribed radius of the two (a bump, a corner, or the fork at the end
/// of a flat part).
pub(crate) const SPUR_RATIO: f64 = 1.75;
/// A branch between two junctions shorter than this times the larger of their inscribed radii
/// is contracted to a point.
pub(crate) const CONTRACT_RATIO: f64 = 1.0;
/// A loop shorter than this times its node's inscribed radius is removed.
pub(crate) const LOOP_RATIO: f64 = 2.0 * std::f64::consts::PI;
/// A node is a voxel of the solid when it is deeper than this many cells inside.
pub(crate) const SURFACE_FRACTION: f64 = 1e-3;
/// Thinning removes voxels in order of depth, in layers this many cells deep.
pub(crate) const DEPTH_STEP: f64 = 0.5;
/// Douglas-Peucker tolerance, as a fraction of the branch's mean inscribed radius.
pub(crate) const BEND_RATIO: f64 = 0.5;

/// One straight piece of a [`Skeleton`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SkeletonSegment {
    /// One end, in the mesh's frame and units.
    pub from: Point3<f64>,
    /// The other end.
    pub to: Point3<f64>,
    /// Inscribed radius at the midpoint: the distance from it to the surface (positive inside).
    pub radius: f64,
}

impl SkeletonSegment {
    /// The point halfway between the ends, where a capsule is seeded.
    pub fn midpoint(&self) -> Point3<f64> {
        nalgebra::center(&self.from, &self.to)
    }

    /// Distance between the ends.
    pub fn length(&self) -> f64 {
        (self.to - self.from).norm()
    }
}

/// A curve skeleton of one closed mesh as straight segments, longest first (see the module
/// documentation for the method).
#[derive(Debug, Clone, PartialEq)]
pub struct Skeleton {
    /// The segments, longest first. Empty only for a mesh with no inside at all.
    pub segments: Vec<SkeletonSegment>,
    /// Whether thinning gave nothing and the segment is the principal-axis fallback.
    pub fallback: bool,
}

impl Skeleton {
    /// The skeleton of `mesh` on a grid of its own: a 24-cell probe finds the thickest part, then
    /// the grid has at least 48 cells across and 4 cells in that part's inscribed radius, with at
    /// most 120,000 nodes. Deterministic, whatever the number of cores. A mesh without triangles,
    /// with an index out of range or a non-finite coordinate, or flat, gives an empty skeleton.
    pub fn new(mesh: &TriMesh) -> Skeleton {
        let empty = Skeleton {
            segments: Vec::new(),
            fallback: false,
        };
        let Some((lo, hi)) = usable_bounds(mesh) else {
            return empty;
        };
        let extent = hi - lo;
        let nodes = |cell: f64| -> f64 {
            extent
                .iter()
                .map(|e| (e / cell).ceil() + 7.0)
                .product::<f64>()
        };
        // The smallest cell, in steps of 1.25, that keeps the node count within MAX_NODES.
        let mut finest = extent.max() / COARSE_CELLS;
        while nodes(finest) > MAX_NODES as f64 {
            finest *= 1.25;
        }
        while nodes(finest / 1.25) <= MAX_NODES as f64 {
            finest /= 1.25;
        }
        // A cheap probe for the thickest part; with nothing inside it, the finest grid.
        let probe = DistanceGrid::new(mesh, (extent.max() / PROBE_CELLS).max(finest));
        let deepest = deepest_radius(&probe);
        let cell = (extent.max() / COARSE_CELLS)
            .min(deepest / MIN_RADIUS_CELLS)
            .max(finest);
        Skeleton::from_grid(mesh, &DistanceGrid::new(mesh, cell))
    }

    /// The skeleton of `mesh` with the nodes of `grid` (built from the same mesh) as voxels:
    /// its cell sets the resolution, and the time grows with the number of inside nodes.
    pub fn from_grid(mesh: &TriMesh, grid: &DistanceGrid) -> Skeleton {
        Skeleton::from_grid_unless(mesh, grid, &Cancel::new())
            .expect("a flag nobody else holds is never set")
    }

    /// [`from_grid`](Self::from_grid), giving up (`None`) soon after `cancel` is set.
    pub fn from_grid_unless(
        mesh: &TriMesh,
        grid: &DistanceGrid,
        cancel: &Cancel,
    ) -> Option<Skeleton> {
        let dims = grid.dims();
        let [nx, ny, nz] = dims;
        // Nodes on the surface, up to rounding, are not inside.
        let depth = SURFACE_FRACTION * grid.cell();
        let mut occupied = Vec::with_capacity(nx * ny * nz);
        let mut depths = Vec::with_capacity(nx * ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let value = grid.node_value_or_far([i, j, k]).unwrap_or(f64::INFINITY);
                    occupied.push(value < -depth);
                    depths.push(-value);
                }
            }
        }
        if !thinning::thin(
            dims,
            &mut occupied,
            &depths,
            DEPTH_STEP * grid.cell(),
            cancel,
        ) {
            return None;
        }
        let field = GridField { grid, dims };
        let mut graph = Graph::new(dims, &occupied, &field);
        graph.prune(&Pruning {
            spur: SPUR_RATIO,
            contract: CONTRACT_RATIO,
            loop_length: LOOP_RATIO,
        });
        let inside = |p: &Point3<f64>| grid.value(p) < 0.0;
        let mut segments = Vec::new();
        for branch in graph.branches() {
            let points = &branch.points;
            let mean_radius =
                points.iter().map(|p| field.radius(p)).sum::<f64>() / points.len() as f64;
            let tolerance = (BEND_RATIO * mean_radius).max(grid.cell());
            let kept = simplify::douglas_peucker(points, tolerance, inside);
            for pair in kept.windows(2) {
                let (from, to) = (points[pair[0]], points[pair[1]]);
                let radius = -grid.value(&nalgebra::center(&from, &to));
                if from != to && radius > 0.0 {
                    segments.push(SkeletonSegment { from, to, radius });
                }
            }
        }
        if segments.is_empty() {
            return Some(Skeleton {
                segments: principal_axis(mesh, grid).into_iter().collect(),
                fallback: true,
            });
        }
        segments.sort_by(|a, b| {
            b.length()
                .total_cmp(&a.length())
                .then_with(|| order_points(&a.from, &b.from))
                .then_with(|| order_points(&a.to, &b.to))
        });
        Some(Skeleton {
            segments,
            fallback: false,
        })
    }
}

fn order_points(a: &Point3<f64>, b: &Point3<f64>) -> std::cmp::Ordering {
    (0..3).fold(std::cmp::Ordering::Equal, |o, i| {
        o.then_with(|| a[i].total_cmp(&b[i]))
    })
}

/// The bounding box, when the mesh has triangles, valid indices, finite coordinates and a
/// positive extent along every axis.
fn usable_bounds(mesh: &TriMesh) -> Option<(Point3<f64>, Point3<f64>)> {
    let count = mesh.positions.len();
    let valid = !mesh.triangles.is_empty()
        && mesh
            .triangles
            .iter()
            .flatten()
            .all(|&i| (i as usize) < count)
        && mesh
            .positions
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite()));
    let (lo, hi) = mesh.bounding_box().filter(|_| valid)?;
    let extent = hi - lo;
    (extent.min() > 0.0 && extent.max().is_finite()).then_some((lo, hi))
}

/// The largest inscribed radius at a node of `grid` (0 when nothing is inside).
fn deepest_radius(grid: &DistanceGrid) -> f64 {
    let [nx, ny, nz] = grid.dims();
    let mut deepest = 0.0f64;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                deepest = deepest.max(-grid.node_value_or_far([i, j, k]).unwrap_or(0.0));
            }
        }
    }
    deepest
}

/// Voxel positions and radii from a distance grid.
struct GridField<'a> {
    grid: &'a DistanceGrid,
    dims: [usize; 3],
}

impl Field for GridField<'_> {
    fn position(&self, index: usize) -> Point3<f64> {
        let [nx, ny, _] = self.dims;
        self.grid
            .node([index % nx, (index / nx) % ny, index / (nx * ny)])
    }

    fn radius(&self, p: &Point3<f64>) -> f64 {
        (-self.grid.value(p)).max(0.0)
    }
}

/// Samples along the fallback axis.
const AXIS_SAMPLES: usize = 513;

/// The fallback: the longest-extent principal axis of inertia through the centroid (of the
/// vertices when the mesh encloses no volume), clipped to the run of inside samples through the
/// centroid, or else the longest run. `None` when no sample is inside.
fn principal_axis(mesh: &TriMesh, grid: &DistanceGrid) -> Option<SkeletonSegment> {
    let (lo, hi) = usable_bounds(mesh)?;
    let mass = mass_properties(mesh);
    let (centre, spread) = if mass.volume > 0.0 && mass.volume.is_finite() {
        let c = mass.centroid.coords;
        (
            mass.centroid,
            mass.second_moment - c * c.transpose() * mass.volume,
        )
    } else {
        let n = mesh.positions.len() as f64;
        let mean = mesh
            .positions
            .iter()
            .fold(Vector3::zeros(), |s, p| s + p.coords)
            / n;
        let spread = mesh.positions.iter().fold(Matrix3::zeros(), |s, p| {
            let d = p.coords - mean;
            s + d * d.transpose()
        });
        (Point3::from(mean), spread)
    };
    if !spread.iter().all(|v| v.is_finite()) {
        return None;
    }
    let eigen = SymmetricEigen::new(spread);
    let mut largest = 0;
    for i in 1..3 {
        if eigen.eigenvalues[i] > eigen.eigenvalues[largest] {
            largest = i;
        }
    }
    let mut axis: Vector3<f64> = eigen.eigenvectors.column(largest).into_owned();
    let norm = axis.norm();
    if !(norm > 0.0 && norm.is_finite()) {
        return None;
    }
    axis /= norm;
    let dominant = axis.iamax();
    if axis[dominant] < 0.0 {
        axis = -axis;
    }
    let reach = (hi - lo).norm() / 2.0 + (centre - nalgebra::center(&lo, &hi)).norm();
    let step = 2.0 * reach / (AXIS_SAMPLES - 1) as f64;
    let at = |s: usize| centre + axis * (-reach + step * s as f64);
    let inside: Vec<bool> = (0..AXIS_SAMPLES)
        .map(|s| grid.value(&at(s)) < 0.0)
        .collect();
    // Runs of inside samples as (first, last).
    let mut runs = Vec::new();
    let mut s = 0;
    while s < AXIS_SAMPLES {
        if inside[s] {
            let first = s;
            while s + 1 < AXIS_SAMPLES && inside[s + 1] {
                s += 1;
            }
            runs.push((first, s));
        }
        s += 1;
    }
    let middle = AXIS_SAMPLES / 2;
    let (first, last) = runs
        .iter()
        .copied()
        .find(|&(a, b)| a <= middle && middle <= b)
        .or_else(|| {
            runs.iter()
                .copied()
                .fold(None, |best: Option<(usize, usize)>, r| match best {
                    Some(b) if b.1 - b.0 >= r.1 - r.0 => Some(b),
                    _ => Some(r),
                })
        })?;
    let (from, to) = (at(first), at(last));
    let radius = (-grid.value(&nalgebra::center(&from, &to))).max(0.0);
    Some(SkeletonSegment { from, to, radius })
}
