//! What can stop a model from being written, and the structural checks made before writing.

use nalgebra::Vector3;

use crate::emit::scene::SceneModel;

/// What can stop a model from being written as glTF.
#[derive(Debug, thiserror::Error)]
pub enum GltfError {
    #[error("the unit length must be a positive number of metres, got {0}")]
    InvalidUnit(f64),
    #[error("the up axis must be a finite non-zero vector, got ({}, {}, {})", .0.x, .0.y, .0.z)]
    InvalidUp(Vector3<f64>),
    #[error("capsule `{capsule}` belongs to component #{component}, but there are only {count} components")]
    ComponentOutOfRange {
        capsule: String,
        component: usize,
        count: usize,
    },
    #[error("capsule `{capsule}` needs a positive radius and ball radius, got {radius} and {ball_radius}")]
    InvalidCapsule {
        capsule: String,
        radius: f64,
        ball_radius: f64,
    },
    #[error(
        "component `{component}` has a triangle using vertex {index}, but only {vertices} vertices"
    )]
    TriangleOutOfRange {
        component: String,
        index: u32,
        vertices: usize,
    },
    #[error("component `{component}` has {vertices} vertices, more than glTF indices can address")]
    TooManyVertices { component: String, vertices: usize },
    #[error("pose `{pose}` places {found} components, but the model has {expected}")]
    TransformCount {
        pose: String,
        expected: usize,
        found: usize,
    },
    #[error("pose `{pose}` has {found} ball centres, but the model has {expected} capsules")]
    BallCount {
        pose: String,
        expected: usize,
        found: usize,
    },
    #[error("{0} is not finite in single precision")]
    NonFinite(String),
    #[error("the glTF file would be {bytes} bytes, over the 4 GiB limit of binary glTF")]
    TooLarge { bytes: u64 },
    #[error("could not encode the glTF JSON: {0}")]
    Json(#[from] serde_json::Error),
    #[error("could not encode the binary glTF container: {0}")]
    Container(#[source] gltf::Error),
}

/// Structural checks that do not depend on the numbers being drawable.
pub(super) fn check(model: &SceneModel) -> Result<(), GltfError> {
    if !(model.unit_in_metres.is_finite() && model.unit_in_metres > 0.0) {
        return Err(GltfError::InvalidUnit(model.unit_in_metres));
    }
    if !(model.up.iter().all(|c| c.is_finite()) && model.up.norm() > 0.0) {
        return Err(GltfError::InvalidUp(model.up));
    }
    for component in &model.components {
        let vertices = component.positions.len();
        if u32::try_from(vertices).is_err() {
            return Err(GltfError::TooManyVertices {
                component: component.name.clone(),
                vertices,
            });
        }
        if let Some(&index) = component
            .triangles
            .iter()
            .flatten()
            .find(|&&i| i as usize >= vertices)
        {
            return Err(GltfError::TriangleOutOfRange {
                component: component.name.clone(),
                index,
                vertices,
            });
        }
    }
    for capsule in &model.capsules {
        if capsule.component >= model.components.len() {
            return Err(GltfError::ComponentOutOfRange {
                capsule: capsule.name.clone(),
                component: capsule.component,
                count: model.components.len(),
            });
        }
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !(positive(capsule.radius) && positive(capsule.ball_radius)) {
            return Err(GltfError::InvalidCapsule {
                capsule: capsule.name.clone(),
                radius: capsule.radius,
                ball_radius: capsule.ball_radius,
            });
        }
    }
    for pose in &model.poses {
        if pose.component_transforms.len() != model.components.len() {
            return Err(GltfError::TransformCount {
                pose: pose.name.clone(),
                expected: model.components.len(),
                found: pose.component_transforms.len(),
            });
        }
        if pose.ball_centres.len() != model.capsules.len() {
            return Err(GltfError::BallCount {
                pose: pose.name.clone(),
                expected: model.capsules.len(),
                found: pose.ball_centres.len(),
            });
        }
    }
    Ok(())
}
