//! Volume, centroid and second moment of the solid bounded by a closed triangle mesh.

use nalgebra::{Matrix3, Point3, Vector3};

use super::mesh::TriMesh;

/// Volume, centroid and inertia of a homogeneous solid bounded by a closed mesh (divergence
/// theorem), in the mesh's units.
///
/// All three are signed: an inside-out mesh gives a negative volume (and negated moments).
/// Multiply by a density to get mass, first moment and the mass second moment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// Signed volume (units³). Negative when the triangles face inwards.
    pub volume: f64,
    /// Centroid of the solid (units). When the volume is exactly zero, the centre of the
    /// mesh's bounding box instead (the origin for a mesh without positions).
    pub centroid: Point3<f64>,
    /// `∫ x xᵀ dV` over the solid, about the origin (units⁵). The inertia tensor about the origin
    /// per unit density is `trace(S)·I − S`.
    pub second_moment: Matrix3<f64>,
}

/// Mass properties of the solid bounded by `mesh`: the sum over triangles of the signed
/// tetrahedra they span with a reference point (Tonon 2004; Eberly, "Polyhedral Mass
/// Properties"). Exact, up to rounding, for any closed polyhedron; for an open mesh the result
/// depends on the reference point and means little.
///
/// The reference point is the bounding-box centre, so large coordinates do not cancel.
///
/// # Panics
/// If a triangle has an index out of range.
pub fn mass_properties(mesh: &TriMesh) -> MassProperties {
    integrate(
        reference_point(mesh),
        (0..mesh.triangles.len()).map(|i| mesh.triangle(i)),
    )
}

/// The centre of the bounding box, or the origin for a mesh without positions.
pub(crate) fn reference_point(mesh: &TriMesh) -> Point3<f64> {
    mesh.bounding_box()
        .map(|(lo, hi)| nalgebra::center(&lo, &hi))
        .unwrap_or_else(Point3::origin)
}

/// Sums the tetrahedra (reference, a, b, c) over the given triangles.
pub(crate) fn integrate(
    reference: Point3<f64>,
    triangles: impl Iterator<Item = [Point3<f64>; 3]>,
) -> MassProperties {
    // Accumulate 6·V, 24·∫x' dV and 120·∫x' x'ᵀ dV with x' = x − reference.
    let mut six_v = 0.0;
    let mut first = Vector3::zeros();
    let mut second = Matrix3::zeros();
    for [a, b, c] in triangles {
        let (a, b, c) = (a - reference, b - reference, c - reference);
        let d = a.dot(&b.cross(&c));
        let s = a + b + c;
        six_v += d;
        first += s * d;
        second +=
            (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose()) * d;
    }
    MassProperties::from_moments(reference, six_v / 6.0, first / 24.0, second / 120.0)
}

impl MassProperties {
    /// The mass properties of a solid of `volume` whose first and second moments about
    /// `reference` are `first` (`∫ (x − r) dV`) and `second` (`∫ (x − r)(x − r)ᵀ dV`).
    pub(crate) fn from_moments(
        reference: Point3<f64>,
        volume: f64,
        first: Vector3<f64>,
        second: Matrix3<f64>,
    ) -> MassProperties {
        let r = reference.coords;
        // Shift ∫x' x'ᵀ to the origin: x = x' + r.
        let second_moment =
            second + first * r.transpose() + r * first.transpose() + r * r.transpose() * volume;
        let centroid = if volume != 0.0 {
            reference + first / volume
        } else {
            reference
        };
        MassProperties {
            volume,
            centroid,
            second_moment,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tetrahedron (0, e1, e2, e3), faces counter-clockwise from outside.
    fn unit_tetrahedron() -> TriMesh {
        TriMesh {
            positions: vec![
                Point3::origin(),
                Point3::new(1.0, 0.0, 0.0),
                Point3::new(0.0, 1.0, 0.0),
                Point3::new(0.0, 0.0, 1.0),
            ],
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        }
    }

    #[test]
    fn unit_tetrahedron_closed_form() {
        let m = mass_properties(&unit_tetrahedron());
        assert!((m.volume - 1.0 / 6.0).abs() < 1e-15);
        assert!((m.centroid - Point3::new(0.25, 0.25, 0.25)).norm() < 1e-15);
        // ∫x² = 1/60, ∫xy = 1/120 over the unit tetrahedron.
        let expected = Matrix3::from_fn(|i, j| if i == j { 1.0 / 60.0 } else { 1.0 / 120.0 });
        assert!((m.second_moment - expected).abs().max() < 1e-15);
    }

    #[test]
    fn empty_mesh_is_zero() {
        let m = mass_properties(&TriMesh {
            positions: vec![],
            triangles: vec![],
        });
        assert_eq!(m.volume, 0.0);
        assert_eq!(m.centroid, Point3::origin());
        assert_eq!(m.second_moment, Matrix3::zeros());
    }
}
