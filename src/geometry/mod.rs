//! Geometry: triangle meshes, loading, validation, mass properties and distance queries.
//!
//! - [`TriMesh`]: positions and counter-clockwise (seen from outside) triangles in one frame.
//! - [`load_mesh`]: `.obj`, `.gltf` and `.glb` files, whole or one named part.

mod load;
mod load_gltf;
mod load_obj;
mod mesh;

pub use load::{load_mesh, LoadError, MeshSelector};
pub use mesh::TriMesh;
