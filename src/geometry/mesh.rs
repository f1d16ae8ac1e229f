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

#[cfg(test)]
/// An axis-aligned box from `low` to `high`, outward, its vertices from `first` on.
pub(crate) fn box_at(low: [f64; 3], high: [f64; 3], first: u32) -> TriMesh {
    let positions = (0..8)
        .map(|i| {
            let pick = |bit: usize, axis: usize| {
                if i & bit != 0 {
                    high[axis]
                } else {
                    low[axis]
                }
            };
            Point3::new(pick(1, 0), pick(2, 1), pick(4, 2))
        })
        .collect();
    let faces: [[u32; 3]; 12] = [
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    TriMesh {
        positions,
        triangles: faces.iter().map(|f| f.map(|v| v + first)).collect(),
    }
}
