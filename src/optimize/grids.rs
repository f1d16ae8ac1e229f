//! The signed distance grids that keep capsules inside their components (eq. 15): their
//! resolution, and the content hash that names a mesh in the [`PrecomputeCache`].
//!
//! [`PrecomputeCache`]: super::PrecomputeCache

use std::hash::{Hash, Hasher};

use crate::geometry::{DistanceGrid, TriMesh};

/// The most nodes a grid gets from the default resolution (about 2 MB of `f64`).
const MAX_DEFAULT_NODES: f64 = 262_144.0;

/// The default node spacing of `mesh`'s grid for capsules at least `smallest_radius` wide:
/// [`DistanceGrid::cell_for_radius`] (half the radius), coarsened when that would give more than
/// 2¹⁸ nodes over the mesh's bounding box, so a large model does not take minutes.
pub fn default_cell(mesh: &TriMesh, smallest_radius: f64) -> f64 {
    let fine = DistanceGrid::cell_for_radius(smallest_radius);
    let Some((lo, hi)) = mesh.bounding_box() else {
        return fine;
    };
    let extent = hi - lo;
    let volume = extent.iter().map(|side| side.max(fine)).product::<f64>();
    let coarse = (volume / MAX_DEFAULT_NODES).cbrt();
    if fine.is_finite() && fine > 0.0 {
        fine.max(coarse)
    } else {
        coarse.max(f64::MIN_POSITIVE)
    }
}

/// A hash of the mesh's exact content: every coordinate's bits and every index.
pub fn content_hash(mesh: &TriMesh) -> u64 {
    let mut hasher = Fnv64::default();
    mesh.positions.len().hash(&mut hasher);
    for p in &mesh.positions {
        for c in p.iter() {
            c.to_bits().hash(&mut hasher);
        }
    }
    mesh.triangles.hash(&mut hasher);
    hasher.finish()
}

/// 64-bit FNV-1a: stable across runs and Rust versions, unlike the standard library's hasher.
struct Fnv64(u64);

impl Default for Fnv64 {
    fn default() -> Self {
        Fnv64(0xcbf2_9ce4_8422_2325)
    }
}

impl Hasher for Fnv64 {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.0 ^= u64::from(byte);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
}
