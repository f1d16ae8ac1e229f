//! The driver of the pipeline: project text in; the evaluated design, its report and its glTF
//! scene out.
//!
//! [`compile`] runs the stages in order (parse, load meshes, hand-placed design, fabrication
//! checks, per-pose physics) and stops before the physics when any stage found an error, so every
//! error of the earlier stages is reported together.

mod design;
mod meshes;
mod report;
mod scene;

use std::path::Path;

pub use design::hand_placed_design;
pub use meshes::load_components;
pub use report::{Report, REPORT_FORMAT};

use crate::balance::{evaluate_pose, BallRest, ComponentBody, PoseEvaluation};
use crate::design::Design;
use crate::diagnostic::Problem;
use crate::geometry::{MassProperties, TriMesh};
use crate::spec::model::Project;
use crate::spec::parse_project;

/// A valid project and what its design does in every pose.
#[derive(Debug, Clone)]
pub struct Compilation {
    /// The project as parsed.
    pub project: Project,
    /// Each component's mesh, rest frame, in project order.
    pub meshes: Vec<TriMesh>,
    /// Each component's volume, centroid and second moment, in project order.
    pub mass: Vec<MassProperties>,
    /// The capsules evaluated.
    pub design: Design,
    /// One per pose, in project order.
    pub poses: Vec<PoseEvaluation>,
    /// Warnings: the project is valid but something deserves a look.
    pub warnings: Vec<Problem>,
}

impl Compilation {
    /// Whether every goal of every pose is met.
    pub fn all_goals_met(&self) -> bool {
        self.poses
            .iter()
            .all(|pose| pose.goals.iter().all(|goal| goal.met))
    }
}

/// Compiles the project file text `source`, read from `project_path` (mesh and output paths are
/// relative to its folder). On an invalid project, returns every problem found, warnings included.
pub fn compile(source: &str, project_path: &Path) -> Result<Compilation, Vec<Problem>> {
    let parsed = parse_project(source, project_path);
    let mut problems = parsed.problems;
    let Some(project) = parsed.project else {
        return Err(problems);
    };
    let (meshes, mesh_problems) = load_components(&project);
    problems.extend(mesh_problems);
    let (design, design_problems) = hand_placed_design(&project);
    problems.extend(design_problems);
    if let Some(meshes) = &meshes {
        problems.extend(design::fabrication_problems(&project, meshes, &design));
    }
    let meshes = match meshes {
        Some(meshes) if !problems.iter().any(Problem::is_error) => meshes,
        _ => return Err(problems),
    };
    let bodies: Vec<ComponentBody> = meshes.iter().map(ComponentBody::new).collect();
    let mass = bodies.iter().map(|body| body.mass).collect();
    let poses: Vec<PoseEvaluation> = project
        .poses
        .iter()
        .map(|pose| evaluate_pose(&project, &bodies, &design, pose))
        .collect();
    problems.extend(undetermined_balls(&project, &poses));
    Ok(Compilation {
        project,
        meshes,
        mass,
        design,
        poses,
        warnings: problems,
    })
}

/// A warning for every ball whose rest end cannot be trusted in a pose.
fn undetermined_balls(project: &Project, poses: &[PoseEvaluation]) -> Vec<Problem> {
    let mut warnings = Vec::new();
    for (pose, evaluation) in project.poses.iter().zip(poses) {
        for (capsule, ball) in project.capsules.iter().zip(&evaluation.balls) {
            if ball.rest != BallRest::Undetermined {
                continue;
            }
            warnings.push(
                Problem::warning(
                    "ballast::capsule::undetermined",
                    format!(
                        "in pose `{}`, capsule `{}` is {:.1}° from horizontal, less than the ball's min-angle of {}°: its ball may rest anywhere along it",
                        pose.name.value, capsule.name.value, ball.elevation, project.ball.min_angle
                    ),
                )
                .with_label(capsule.span, "this capsule")
                .with_label(pose.name.span, "in this pose")
                .with_help("tilt the capsule's axis, or the result in this pose assumes the ball in the middle"),
            );
        }
    }
    warnings
}
