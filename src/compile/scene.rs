//! A compilation drawn as a glTF scene model: one group per pose with its physics markers, and its
//! numbers as `extras`, structured and flat.

use nalgebra::{Point3, Vector3};
use serde_json::{Map, Value};

use super::report::PoseReport;
use super::Compilation;
use crate::balance::{GoalOutcome, PoseEvaluation};
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
                let extras = pose_extras(evaluation, project.units.keyword());
                ScenePose {
                    name: pose.name.value.clone(),
                    component_transforms: evaluation.component_frames.clone(),
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
                    ground: stands(evaluation).then_some(evaluation.support.ground_height),
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

/// Whether the pose stands on the ground: it has a `stand` or `imbalance` goal, or no goal that
/// hangs or floats it.
fn stands(evaluation: &PoseEvaluation) -> bool {
    let on_ground = |outcome: &GoalOutcome| {
        matches!(
            outcome,
            GoalOutcome::Stand { .. } | GoalOutcome::Imbalance { .. }
        )
    };
    let off_ground = |outcome: &GoalOutcome| {
        matches!(
            outcome,
            GoalOutcome::Suspend { .. } | GoalOutcome::Immerse { .. }
        )
    };
    evaluation.goals.iter().any(|goal| on_ground(&goal.outcome))
        || !evaluation
            .goals
            .iter()
            .any(|goal| off_ground(&goal.outcome))
}

/// The pose's report entry (structured), with flat scalar keys beside it that viewers show as
/// plain properties: `mass_g`; when the pose stands, `centre_height_<units>`, `tilt_margin_deg`
/// and `fixed_ball_margin_deg`; and per goal `goal.<kind>.<field>` for each of its scalar fields
/// (`goal.<kind>.<n>.<field>` for the n-th goal of a kind, from 2).
fn pose_extras(evaluation: &PoseEvaluation, units: &str) -> Value {
    let Ok(Value::Object(mut extras)) = serde_json::to_value(PoseReport::new(evaluation)) else {
        return Value::Null;
    };
    let mut flat = Map::new();
    let number = |x: f64| serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number);
    flat.insert("mass_g".to_owned(), number(evaluation.mass));
    for (key, value) in [
        (
            format!("centre_height_{units}"),
            evaluation.support.centre_height,
        ),
        ("tilt_margin_deg".to_owned(), evaluation.support.tilt_margin),
        (
            "fixed_ball_margin_deg".to_owned(),
            evaluation.support.fixed_ball_margin,
        ),
    ] {
        if stands(evaluation) {
            flat.insert(key, number(value));
        }
    }
    let mut seen: Vec<String> = Vec::new();
    for goal in &evaluation.goals {
        let Ok(Value::Object(fields)) = serde_json::to_value(goal) else {
            continue;
        };
        let kind = fields
            .get("kind")
            .and_then(Value::as_str)
            .unwrap_or("goal")
            .to_owned();
        let n = seen.iter().filter(|k| **k == kind).count() + 1;
        let prefix = if n == 1 {
            format!("goal.{kind}")
        } else {
            format!("goal.{kind}.{n}")
        };
        seen.push(kind);
        for (field, value) in fields {
            let scalar = matches!(value, Value::Bool(_) | Value::Number(_) | Value::String(_));
            if scalar && field != "kind" {
                flat.insert(format!("{prefix}.{field}"), value);
            }
        }
    }
    extras.extend(flat);
    Value::Object(extras)
}
