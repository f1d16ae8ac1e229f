//! A compilation drawn as a glTF scene model: one scene per pose with its physics markers.

use nalgebra::{Point3, Vector3};

use super::report::PoseReport;
use super::Compilation;
use crate::balance::GoalOutcome;
use crate::emit::{SceneCapsule, SceneComponent, SceneModel, ScenePose};

impl Compilation {
    /// What the glTF file shows: the components, the capsules and, per pose, where everything is
    /// and the pose's report entry as `extras`.
    pub fn scene(&self) -> SceneModel {
        let project = &self.project;
        let components = project
            .components
            .iter()
            .zip(&self.meshes)
            .map(|(component, mesh)| SceneComponent {
                name: component.name.value.clone(),
                positions: mesh.positions.clone(),
                triangles: mesh.triangles.clone(),
            })
            .collect();
        let capsules = self
            .design
            .capsules
            .iter()
            .map(|capsule| SceneCapsule {
                name: capsule.name.clone(),
                component: capsule.component,
                from: capsule.from,
                to: capsule.to,
                radius: capsule.radius,
                ball_radius: capsule.ball_radius,
            })
            .collect();
        let poses = project
            .poses
            .iter()
            .zip(&self.poses)
            .map(|(pose, evaluation)| {
                let extras = serde_json::to_value(PoseReport::new(evaluation))
                    .unwrap_or(serde_json::Value::Null);
                ScenePose {
                    name: pose.name.value.clone(),
                    component_transforms: (0..project.components.len())
                        .map(|i| pose.component_frame(i))
                        .collect(),
                    ball_centres: evaluation
                        .balls
                        .iter()
                        .map(|ball| point(ball.centre))
                        .collect(),
                    centre_of_mass: point(evaluation.centre_of_mass),
                    support_polygon: evaluation
                        .support
                        .polygon
                        .iter()
                        .copied()
                        .map(point)
                        .collect(),
                    suspension_point: evaluation.goals.iter().find_map(|goal| {
                        match &goal.outcome {
                            GoalOutcome::Suspend { point: p, .. } => Some(point(*p)),
                            _ => None,
                        }
                    }),
                    buoyancy_centre: evaluation
                        .goals
                        .iter()
                        .find_map(|goal| match &goal.outcome {
                            GoalOutcome::Immerse {
                                buoyancy_centre, ..
                            } => Some(point(*buoyancy_centre)),
                            _ => None,
                        }),
                    extras,
                }
            })
            .collect();
        SceneModel {
            unit_in_metres: project.units.in_metres(),
            up: project.up.unit_vector(),
            components,
            capsules,
            poses,
        }
    }
}

fn point(coordinates: [f64; 3]) -> Point3<f64> {
    Point3::from(Vector3::from(coordinates))
}
