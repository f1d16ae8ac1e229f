//! Back end: glTF scenes, the JSON report, and atomic file writes.

pub mod atomic;
pub mod gltf;
pub mod scene;
mod shapes;

pub use atomic::write_atomic;
pub use gltf::{write_glb, GltfError};
pub use scene::{SceneCapsule, SceneComponent, SceneModel, ScenePose};
