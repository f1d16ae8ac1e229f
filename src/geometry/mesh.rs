//! The triangle mesh type shared by every geometry query.

use nalgebra::{Isometry3, Point3};

/// A triangle mesh in one rigid frame.
///
/// - `positions`: #V points, in the units of the file they came from.
/// - `triangles`: #F index triples into `positions`, counter-clockwise seen from outside
///   (so the right-hand normal points out of the solid).
///
/// Invariant expected by the queries in this module: every index is `< positions.len()`.
/// Meshes returned by [`load_mesh`](super::load_mesh) always satisfy it;
/// [`check_mesh`](super::check_mesh) reports triangles that do not.
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh {
    /// Vertex positions: #V points.
    pub positions: Vec<Point3<f64>>,
    /// Triangles: #F index triples into `positions`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// The mesh with every position mapped by the rigid transform `iso` (rotation then
    /// translation). Triangles are unchanged: a rigid motion keeps their orientation.
    pub fn transformed(&self, iso: &Isometry3<f64>) -> TriMesh {
        TriMesh {
            positions: self.positions.iter().map(|p| iso * p).collect(),
            triangles: self.triangles.clone(),
        }
    }

    /// Axis-aligned bounding box `(min, max)` of all positions (referenced or not),
    /// or `None` when the mesh has no positions.
    pub fn bounding_box(&self) -> Option<(Point3<f64>, Point3<f64>)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p))),
        )
    }

    /// The three corners of triangle `i`, in the triangle's (counter-clockwise) order.
    ///
    /// # Panics
    /// If `i >= triangles.len()` or the triangle has an index out of range.
    pub fn triangle(&self, i: usize) -> [Point3<f64>; 3] {
        let [a, b, c] = self.triangles[i];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }
}
