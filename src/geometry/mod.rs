//! Geometry: triangle meshes, loading, validation, mass properties and distance queries.
//!
//! - [`TriMesh`]: positions and counter-clockwise (seen from outside) triangles in one frame.
//! - [`load_mesh`]: `.obj`, `.gltf` and `.glb` files, whole or one named part.
//! - [`check_mesh`]: holes, non-manifold and misoriented edges, degenerate triangles, inversion.
//! - [`mass_properties`]: volume, centroid and second moment of the enclosed solid.

mod load;
mod load_gltf;
mod load_obj;
mod mass;
mod mesh;
mod validate;

pub use load::{load_mesh, LoadError, MeshSelector};
pub use mass::{mass_properties, MassProperties};
pub use mesh::TriMesh;
pub use validate::{check_mesh, MeshCheck};
