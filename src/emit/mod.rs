//! Back end: glTF scenes, the JSON report, and atomic file writes.

pub mod atomic;
pub mod scene;
#[allow(dead_code)] // drawn by the glTF writer
mod shapes;

pub use atomic::write_atomic;
pub use scene::{SceneCapsule, SceneComponent, SceneModel, ScenePose};
