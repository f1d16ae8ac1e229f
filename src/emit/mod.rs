//! Back end: glTF scenes, the solution file, and atomic file writes (one file, or a set).

pub mod atomic;
pub mod gltf;
mod number;
pub mod output_set;
pub mod print_files;
pub mod scene;
mod shapes;
pub mod solution;

pub use atomic::write_atomic;
pub use gltf::{write_glb, GltfError};
pub use output_set::{finish_interrupted, manifest_path, replace_set};
pub use scene::{SceneCapsule, SceneComponent, SceneModel, ScenePose};
pub use solution::{write_solution, Solution, SolutionCapsule};
