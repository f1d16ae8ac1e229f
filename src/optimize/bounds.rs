//! Box bounds on the design vector, from the components' bounding boxes.

use super::solver::Bounds;
use crate::geometry::TriMesh;
use crate::objective::{half_narrowest_side, Objective, CAPSULE_STRIDE, P, Q, R};

/// Bounds for `objective`'s design vector: each capsule end inside its component's bounding box
/// (rest frame), each radius between the smallest printable one and half the component's
/// narrowest side, the infill within its range. `meshes` is indexed like the components.
///
/// Positions are scaled by the model's extent (the largest bounding-box diagonal) about their
/// box's centre, radii by the extent, the infill not at all.
pub fn design_bounds(objective: &Objective, meshes: &[TriMesh]) -> Bounds {
    let layout = objective.layout();
    let n = layout.len();
    let boxes: Vec<_> = meshes.iter().map(TriMesh::bounding_box).collect();
    let extent = boxes
        .iter()
        .flatten()
        .map(|(lo, hi)| (hi - lo).norm())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut bounds = Bounds {
        range: vec![(0.0, 0.0); n],
        shift: vec![0.0; n],
        scale: vec![1.0; n],
    };
    let min_radius = objective.parameters().min_radius;
    for (j, &component) in layout.components.iter().enumerate() {
        let base = j * CAPSULE_STRIDE;
        let (lo, hi) = boxes.get(component).copied().flatten().unwrap_or_default();
        for end in [P, Q] {
            for k in 0..3 {
                let i = base + end + k;
                bounds.range[i] = (lo[k], hi[k]);
                bounds.shift[i] = 0.5 * (lo[k] + hi[k]);
                bounds.scale[i] = extent;
            }
        }
        let max_radius = meshes.get(component).map_or(0.0, half_narrowest_side);
        bounds.range[base + R] = (min_radius, max_radius.max(min_radius));
        bounds.scale[base + R] = extent;
    }
    if let (Some(i), Some(range)) = (layout.infill_index(), layout.infill_range) {
        bounds.range[i] = range;
    }
    bounds
}
