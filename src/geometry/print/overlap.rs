//! How much of a mesh's solid its shells cover twice or more, measured on its slices.

use nalgebra::{Matrix3, Rotation3, Vector3};

use super::layout::Layout;
use super::Slicing;
use crate::geometry::mesh::TriMesh;
use crate::parallel::map_each;

/// How much of a mesh's solid its shells cover twice or more: where the mesh crosses itself or
/// two shells overlap, the sum of their volumes (what the divergence theorem gives) exceeds the
/// volume of their union (what a slicer prints) by the overlap's volume, and their moments by
/// its moments.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overlap {
    /// What the winding number `w` counts beyond the union, `∫ (w − [w > 0]) dV` (units³): the
    /// overlap, each point weighted by how far `w` is past 1, less what an inward surface with
    /// nothing around it takes away (where `w` is negative).
    pub volume: f64,
    /// Its first moment about the origin, `∫ (w − [w > 0]) x dV` (units⁴).
    pub first_moment: Vector3<f64>,
    /// Its second moment about the origin, `∫ (w − [w > 0]) x xᵀ dV` (units⁵).
    pub second_moment: Matrix3<f64>,
    /// The union's volume, `∫ [w > 0] dV` (units³).
    pub union: f64,
}

impl Overlap {
    /// The same overlap turned by `rotation` about the origin, then scaled by `factor` (> 0).
    pub fn turned_and_scaled(&self, rotation: &Rotation3<f64>, factor: f64) -> Overlap {
        let r = rotation.matrix();
        Overlap {
            volume: self.volume * factor.powi(3),
            first_moment: rotation * self.first_moment * factor.powi(4),
            second_moment: r * self.second_moment * r.transpose() * factor.powi(5),
            union: self.union * factor.powi(3),
        }
    }
}

/// Layers (and rows per layer, about) the overlap of a mesh is measured on.
const OVERLAP_STEPS: f64 = 256.0;

/// The [`Overlap`] of `mesh`'s shells, measured on 256 slices and rows across its largest
/// extent, exactly along each row; `None` for a mesh without extent.
pub fn overlap(mesh: &TriMesh) -> Option<Overlap> {
    let (low, high) = mesh.bounding_box()?;
    let step = (high - low).max() / OVERLAP_STEPS;
    if !(step > 0.0 && step.is_finite()) {
        return None;
    }
    let slicing = Slicing {
        to_print: Rotation3::identity(),
        perimeter_thickness: 4.0 * step,
        layer_height: step,
        first_layer_height: step,
        top_layers: 0,
        bottom_layers: 0,
        min_sparse_area: 0.0,
        surface_margin: 0.0,
        shell_widening: 0.0,
        fill_boundary: 0.0,
        infill_spacing: 0.0,
    };
    let layout = Layout::new(mesh, &slicing)?;
    let reference = nalgebra::center(&low, &high);
    let segments = layout.slice(mesh);
    let slices = map_each(layout.layers, |k| {
        layout.winding_areas(&segments[k], (reference.x, reference.y))
    });
    // Each slice stands for a layer one step thick around its plane.
    let layer = step * step / 12.0;
    let (mut union, mut volume) = (0.0, 0.0);
    let (mut first, mut second) = (Vector3::zeros(), Matrix3::zeros());
    for (k, (area, [m, mu, mv, muu, mvv, muv])) in slices.iter().enumerate() {
        let z = layout.slice_height(k) - reference.z;
        union += area * step;
        volume += m * step;
        first += Vector3::new(*mu, *mv, z * m) * step;
        second += Matrix3::new(
            *muu,
            *muv,
            z * mu,
            *muv,
            *mvv,
            z * mv,
            z * mu,
            z * mv,
            (z * z + layer) * m,
        ) * step;
    }
    let r = reference.coords;
    Some(Overlap {
        volume,
        first_moment: first + r * volume,
        second_moment: second
            + first * r.transpose()
            + r * first.transpose()
            + r * r.transpose() * volume,
        union,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::box_at;

    #[test]
    fn the_overlap_of_two_boxes_is_their_common_box() {
        let mut two = box_at([0.0; 3], [40.0, 30.0, 20.0], 0);
        let other = box_at([20.0, 12.0, 0.0], [60.0, 42.0, 20.0], 8);
        two.positions.extend(other.positions);
        two.triangles.extend(other.triangles);
        let measured = overlap(&two).unwrap();
        // Closed forms: 20 × 18 × 20 in common, 2 × 24,000 less that in all. The measure is
        // exact along u and sampled every step (60 / 256 mm) along v and z: each face facing
        // ±v or ±z may be off by half a step.
        let half_step = 60.0 / 256.0 / 2.0;
        let common_faces = 2.0 * 20.0 * 20.0 + 2.0 * 20.0 * 18.0;
        assert!(
            (measured.volume - 7200.0).abs() <= half_step * common_faces,
            "{measured:?}"
        );
        let union_faces = (40.0 + 20.0 + 40.0 + 20.0) * 20.0 + 2.0 * 2040.0;
        assert!(
            (measured.union - 40800.0).abs() <= half_step * union_faces,
            "{measured:?}"
        );
        let one = overlap(&box_at([0.0; 3], [40.0, 30.0, 20.0], 0)).unwrap();
        assert_eq!(one.volume, 0.0);
        let box_faces = 2.0 * 40.0 * 20.0 + 2.0 * 40.0 * 30.0;
        assert!(
            (one.union - 24000.0).abs() <= 40.0 / 256.0 / 2.0 * box_faces,
            "{one:?}"
        );
    }
}
