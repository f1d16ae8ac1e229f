//! The driver of the pipeline: project text in; the evaluated design, its report and its glTF
//! scene out.
//!
//! [`compile_with`] runs the stages in order (parse, load meshes, the design, fabrication
//! checks, per-pose physics) and stops before the physics when any stage found an error, so every
//! error of the earlier stages is reported together.
//!
//! The design is the project's written capsules, unless the project has an `optimize` node: then
//! `build` runs the optimizer ([`OptimizeOptions`]) and `check` reads the solution file the last
//! build wrote ([`read_solution`]).
//!
//! A [`Workspace`] carries what builds in one process share: the mesh and precompute caches that
//! let watch mode skip work for unchanged meshes, the flag that cancels a build in flight, and
//! where progress goes.

mod calibration;
mod design;
mod down;
mod insertion;
mod limits;
mod mesh_cache;
mod meshes;
mod optimization;
mod optimize;
mod orientation;
mod output_paths;
mod outputs;
mod print_cache;
mod print_files;
mod report;
mod sanity;
mod scene;
mod solution;
mod workspace;

use limits::optimizer_limits;

use std::path::{Path, PathBuf};

pub use calibration::{
    calibration_path, calibration_text, CALIBRATION_REFUSED, CALIBRATION_STALE,
    CALIBRATION_UNKNOWN, CALIBRATION_UNREADABLE,
};
pub use design::hand_placed_design;
pub use insertion::{direction_words, plan_insertions_into, BRIDGE_LIMIT_MM};
pub use mesh_cache::MeshCache;
pub use meshes::load_components;
pub use optimization::{
    CandidateReport, CapsuleOrigin, GoalName, Optimization, SeedReport, Starts, Timings,
};
pub use optimize::{
    length_decimals, optimize_design, prepare, OptimizeOptions, Preparation, WarmStart,
};
pub use orientation::{
    insertion_rank, layer_grid, print_orientations, print_plan, print_setup, BED_CENTRE_MM,
    BED_GAP_MM,
};
pub(crate) use output_paths::lexical;
pub use output_paths::{
    check_output_paths, input_files, output_targets, OutputTarget, WriteOptions, DUPLICATE_OUTPUT,
    OUTSIDE_PROJECT, OVERWRITES_INPUT,
};
pub use outputs::{
    finish_interrupted_outputs, journal_path, write_outputs, write_outputs_with, PrintFileCache,
    WrittenOutputs,
};
pub use print_cache::PrintCache;
pub use print_files::{bed_parts, print_settings};
pub use report::{Report, REPORT_FORMAT};
pub use solution::{interrupted_solution_text, read_solution, solution_text};
pub use workspace::{Failure, Stage, Workspace};

use crate::balance::{
    cut_bodies, evaluate_pose, BallRest, ComponentBody, GoalOutcome, PartPrints, PoseEvaluation,
    MAX_ENUMERATED_BALLS, SNAP_WARNING,
};
use crate::design::Design;
use crate::diagnostic::Problem;
use crate::fabrication::{Orientation, PrintPlan};
use crate::geometry::{
    MassProperties, MeshLimits, PrintCorrection, PrintVolumes, ReadPolicy, TriMesh,
};
use crate::spec::model::Project;
use crate::spec::parse_project_with;

/// Where the evaluated design came from.
#[derive(Debug, Clone, PartialEq)]
pub enum DesignSource {
    /// The capsules written in the project file.
    Written,
    /// The solution file at this path, written by an earlier build.
    SolutionFile(PathBuf),
    /// The optimizer, just now.
    Optimized,
    /// The design of the last build, judged again as it is with the project as it now is
    /// (watch mode's first answer to an edit, before a search).
    Earlier,
}

/// How to compile, beyond what the project file says.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CompileOptions {
    /// Outputs go into this folder instead of the paths the project names; the solution file is
    /// read from there too.
    pub out_dir: Option<PathBuf>,
    /// Run the optimizer (for a project with `optimize`) with these options; `None` reads the
    /// solution file instead.
    pub optimize: Option<OptimizeOptions>,
    /// The outputs will be written, as these options allow: their paths are checked before
    /// anything is computed ([`check_output_paths`]). `None`: the command writes nothing.
    pub writes: Option<WriteOptions>,
    /// Let mesh files and glTF buffer files be read from any folder, not only from inside the
    /// project's folder (`--read-outside`).
    pub read_outside: bool,
    /// How large each mesh may be (`--max-mesh-mb`, `--max-triangles`).
    pub mesh_limits: MeshLimits,
}

impl CompileOptions {
    /// Which files the meshes of the project at `project_path` may be read from, and how much:
    /// inside the project's folder (symbolic links followed) unless [`Self::read_outside`].
    pub fn read_policy(&self, project_path: &Path) -> ReadPolicy {
        let folder = match project_path.parent() {
            Some(folder) if !folder.as_os_str().is_empty() => folder,
            _ => Path::new("."),
        };
        ReadPolicy {
            within: (!self.read_outside).then(|| folder.to_path_buf()),
            limits: self.mesh_limits,
        }
    }
}

/// A valid project and what its design does in every pose.
#[derive(Debug, Clone)]
pub struct Compilation {
    /// The project as parsed.
    pub project: Project,
    /// Each component's mesh, rest frame, in project order.
    pub meshes: Vec<TriMesh>,
    /// Each component's volume, centroid and second moment, in project order.
    pub mass: Vec<MassProperties>,
    /// Per component, where it is printed solid and where sparse (the project's mass model, plus
    /// the calibration file's correction), in its print orientation.
    pub prints: Vec<PrintVolumes>,
    /// Per component, its material with the design's voids cut from it (and the correction
    /// added): what every pose weighs ([`PartPrints::cut`]).
    pub printed: Vec<PrintVolumes>,
    /// Per component, the calibration file's correction added to `prints` (zero without one).
    pub corrections: Vec<PrintCorrection>,
    /// Per component, how it is printed: declared or chosen, and why.
    pub orientations: Vec<Orientation>,
    /// How the design is printed: every component on the bed.
    pub print_plan: PrintPlan,
    /// The capsules evaluated.
    pub design: Design,
    /// One per pose, in project order.
    pub poses: Vec<PoseEvaluation>,
    /// Warnings: the project is valid but something deserves a look.
    pub warnings: Vec<Problem>,
    /// Where the design came from.
    pub source: DesignSource,
    /// What the optimizer did, when it ran.
    pub optimization: Option<Optimization>,
    /// The goals the model without capsules (same infill) meets and this design does not, in
    /// pose and goal order.
    pub solid_goals_lost: Vec<GoalName>,
}

impl Compilation {
    /// The components' bodies with the design's voids cut from their material (`printed`): what
    /// every pose of the design weighs.
    pub fn bodies(&self) -> Vec<ComponentBody<'_>> {
        cut_bodies(&self.meshes, &self.printed)
    }

    /// What it takes to print each component's material for any design (for the optimizer).
    pub fn part_prints(&self) -> PartPrints {
        part_prints(
            &self.project,
            self.prints.clone(),
            &self.orientations,
            &self.corrections,
        )
    }

    /// The components' bodies before any capsule is cut (`prints`).
    pub fn bare_bodies(&self) -> Vec<ComponentBody<'_>> {
        self.meshes
            .iter()
            .zip(&self.prints)
            .map(|(mesh, print)| ComponentBody::with_print(mesh, *print))
            .collect()
    }

    /// Whether every goal of every pose is met.
    pub fn all_goals_met(&self) -> bool {
        self.poses
            .iter()
            .all(|pose| pose.goals.iter().all(|goal| goal.met))
    }
}

/// Compiles the project file text `source`, read from `project_path`, without optimizing: the
/// design is the written capsules, or the solution file for a project with `optimize`.
pub fn compile(source: &str, project_path: &Path) -> Result<Compilation, Vec<Problem>> {
    let options = CompileOptions::default();
    match compile_with(source, project_path, &options, &mut Workspace::new()) {
        Ok(compilation) => Ok(compilation),
        Err(Failure::Invalid(problems)) => Err(problems),
        Err(Failure::Cancelled) => unreachable!("nobody holds the fresh workspace's cancel flag"),
    }
}

/// Compiles the project file text `source`, read from `project_path` (mesh and output paths are
/// relative to its folder), as `options` say; grids and skeletons come from the workspace's cache
/// when it has them. On an invalid project, fails with every problem found, warnings included;
/// when the workspace's cancel flag is set before the build is done, fails as cancelled.
pub fn compile_with(
    source: &str,
    project_path: &Path,
    options: &CompileOptions,
    workspace: &mut Workspace,
) -> Result<Compilation, Failure> {
    let policy = options.read_policy(project_path);
    let parsed = parse_project_with(source, project_path, &policy);
    let mut problems = parsed.problems;
    let Some(mut project) = parsed.project else {
        return Err(Failure::Invalid(problems));
    };
    if let Some(writes) = options.writes {
        problems.extend(check_output_paths(
            &project,
            source,
            project_path,
            options.out_dir.as_deref(),
            writes,
            &policy,
        ));
    }
    let (meshes, mesh_problems) = load_components(&project, &mut workspace.meshes, &policy);
    problems.extend(mesh_problems);
    // The written capsules as they stand, for the ball-gap warnings and the capsules the print
    // orientation is chosen for; their problems come with the fabrication checks below, and the
    // ball-gap warnings after them, since a gap matters only for a capsule that is valid.
    let (written, _) = hand_placed_design(&project);
    let ball_gaps = design::ball_gap_warnings(&project, &written);
    let known = design::fixed_capsules(&project, &written);
    let orientations = meshes.as_ref().map(|meshes| {
        let (orientations, orientation_problems) = print_orientations(&project, meshes, &known);
        problems.extend(orientation_problems);
        orientations
    });
    let corrections = match (&meshes, &orientations) {
        (Some(meshes), Some(orientations)) => {
            let (corrections, calibration_problems) = calibration::read_calibration(
                &project,
                &calibration_path(project_path),
                meshes,
                orientations,
            );
            problems.extend(calibration_problems);
            corrections
        }
        _ => Vec::new(),
    };
    // The print volumes, computed once: here for the `down` poses, which rest on the print-true
    // body, or else below, once the project is known to be valid.
    let mut corrected: Option<calibration::Corrected> = None;
    if let (Some(meshes), Some(orientations)) = (
        meshes
            .as_ref()
            .filter(|_| project.poses.iter().any(|pose| pose.down.is_some())),
        &orientations,
    ) {
        let prints = &corrected
            .insert(corrected_volumes(
                &project,
                meshes,
                orientations,
                &corrections,
                workspace,
            ))
            .prints;
        let bodies: Vec<ComponentBody> = meshes
            .iter()
            .zip(prints.iter())
            .map(|(mesh, print)| ComponentBody::with_print(mesh, *print))
            .collect();
        problems.extend(down::place_down_poses(&mut project, &bodies));
    }
    let optimizing = project.optimize.is_some() && options.optimize.is_some();
    let checked = meshes
        .as_deref()
        .zip(orientations.as_ref())
        .map(|(meshes, orientations)| (meshes, print_setup(&project, orientations)));
    let (written, design_problems) = design::written_design(
        &project,
        checked.as_ref().map(|(meshes, print)| (*meshes, print)),
        optimizing,
    );
    problems.extend(design_problems);
    problems.extend(ball_gaps);
    let (meshes, orientations) = match (meshes, orientations) {
        (Some(meshes), Some(orientations)) if !problems.iter().any(Problem::is_error) => {
            (meshes, orientations)
        }
        _ => return Err(Failure::Invalid(problems)),
    };
    let corrected = corrected.unwrap_or_else(|| {
        corrected_volumes(&project, &meshes, &orientations, &corrections, workspace)
    });
    problems.extend(corrected.refused);
    // A refused correction is in no material: neither in the bare prints nor in any cut.
    let (prints, corrections) = (corrected.prints, corrected.applied);
    // Each part as the cache sliced it for its volumes, for cutting every design's voids.
    let rasters = meshes
        .iter()
        .zip(&orientations)
        .map(|(mesh, o)| workspace.prints.raster(&project, mesh, o.to_print))
        .collect();
    let parts = part_prints(&project, prints, &orientations, &corrections).with_rasters(rasters);
    let print = print_setup(&project, &orientations);
    let (design, source, optimization) = match (&project.optimize, &options.optimize) {
        (None, _) => (written, DesignSource::Written, None),
        (Some(settings), Some(run)) => {
            let limits = optimizer_limits(&project, settings, &meshes, run);
            if !limits.is_empty() {
                problems.extend(limits);
                return Err(Failure::Invalid(problems));
            }
            let earlier = run
                .warm_start
                .as_ref()
                .filter(|warm| run.judge_warm_start && warm.fits(&meshes));
            if let Some(earlier) = earlier {
                (earlier.design.clone(), DesignSource::Earlier, None)
            } else {
                let (design, mut optimization) =
                    optimize_design(&project, settings, &meshes, &parts, &print, run, workspace)
                        .ok_or(Failure::Cancelled)?;
                problems.append(&mut optimization.warnings);
                (design, DesignSource::Optimized, Some(optimization))
            }
        }
        (Some(_), None) => {
            let path = output_path(&project.output.solution, options.out_dir.as_deref());
            match read_solution(&project, &path, &meshes, &print) {
                Ok(Some(design)) => (design, DesignSource::SolutionFile(path), None),
                Ok(None) => {
                    problems.push(solution::missing(&path));
                    (written, DesignSource::Written, None)
                }
                Err(solution_problems) => {
                    problems.extend(solution_problems);
                    return Err(Failure::Invalid(problems));
                }
            }
        }
    };
    let printed = parts.cut(&meshes, &design);
    let bodies = cut_bodies(&meshes, &printed);
    let mass = bodies.iter().map(|body| body.mass).collect();
    let poses: Vec<PoseEvaluation> = project
        .poses
        .iter()
        .map(|pose| evaluate_pose(&project, &bodies, &design, pose))
        .collect();
    problems.extend(undetermined_balls(&project, &design, &poses));
    problems.extend(settled_poses(&project, &poses));
    problems.extend(other_states(&project, &poses));
    problems.extend(sanity::warnings(&project, &meshes, &poses));
    let solid_goals_lost = solid_goals_lost(&project, &parts.bare_bodies(&meshes), &design, &poses);
    problems.extend(lost_goal_warnings(
        &project,
        &solid_goals_lost,
        optimization.as_ref(),
    ));
    let mut print_plan = print_plan(&project, &meshes, &orientations);
    plan_insertions_into(&project, &meshes, &design, &mut print_plan);
    problems.extend(insertion::window_warnings(
        &project,
        &meshes,
        &design,
        &print_plan,
    ));
    problems.extend(insertion::ceiling_warnings(&project, &design, &print_plan));
    Ok(Compilation {
        project,
        meshes,
        mass,
        prints: parts.bare,
        printed,
        corrections,
        orientations,
        print_plan,
        design,
        poses,
        warnings: problems,
        source,
        optimization,
        solid_goals_lost,
    })
}

/// What it takes to print each component's material for any design: its `bare` print volumes
/// (corrected), its print rotation and its calibration correction.
fn part_prints(
    project: &Project,
    bare: Vec<PrintVolumes>,
    orientations: &[Orientation],
    corrections: &[PrintCorrection],
) -> PartPrints {
    PartPrints::new(
        bare,
        orientations.iter().map(|o| o.to_print).collect(),
        corrections.to_vec(),
        project.print,
    )
}

/// Each component's print volumes in its print orientation (from `workspace`'s cache), with the
/// calibration's corrections added, the corrections applied and the problems of those refused.
fn corrected_volumes(
    project: &Project,
    meshes: &[TriMesh],
    orientations: &[Orientation],
    corrections: &[PrintCorrection],
    workspace: &mut Workspace,
) -> calibration::Corrected {
    let prints: Vec<PrintVolumes> = meshes
        .iter()
        .zip(orientations)
        .map(|(mesh, o)| workspace.prints.volumes(project, mesh, o.to_print))
        .collect();
    calibration::corrected_prints(project, &prints, corrections)
}

/// The goals the model without capsules, at `design`'s infill, meets in `poses` and `design`
/// does not (none when the design has no capsules).
fn solid_goals_lost(
    project: &Project,
    bodies: &[ComponentBody],
    design: &Design,
    poses: &[PoseEvaluation],
) -> Vec<GoalName> {
    if design.capsules.is_empty() {
        return Vec::new();
    }
    let solid = Design {
        capsules: Vec::new(),
        infill: design.infill,
    };
    let mut lost = Vec::new();
    for (pose, evaluation) in project.poses.iter().zip(poses) {
        if evaluation.goals.iter().all(|goal| goal.met) {
            continue;
        }
        let solid_evaluation = evaluate_pose(project, bodies, &solid, pose);
        for (index, (with, without)) in evaluation
            .goals
            .iter()
            .zip(&solid_evaluation.goals)
            .enumerate()
        {
            if without.met && !with.met {
                lost.push(GoalName {
                    pose: pose.name.value.clone(),
                    goal: index,
                    kind: pose.goals[index].value.keyword(),
                });
            }
        }
    }
    lost
}

/// A warning per goal the design breaks that the model without capsules meets, saying, for an
/// optimized design that misses some goal, that no design the optimizer tried met them all.
fn lost_goal_warnings(
    project: &Project,
    lost: &[GoalName],
    optimization: Option<&Optimization>,
) -> Vec<Problem> {
    let help = match optimization {
        Some(optimization) if !optimization.meets_goals => {
            "no design the optimizer tried meets every goal, and the one chosen (the lowest objective) gives this goal up: the build names the goals that conflict; remove or loosen one of them"
        }
        _ => "move or remove capsules, or let the optimizer place them (`optimize`)",
    };
    lost.iter()
        .filter_map(|name| {
            let pose = project.poses.iter().find(|p| p.name.value == name.pose)?;
            let goal = pose.goals.get(name.goal)?;
            Some(
                Problem::warning(
                    "ballast::design::loses_goal",
                    format!(
                        "in pose `{}`, the design does not meet the `{}` goal, which the model without capsules meets",
                        name.pose, name.kind
                    ),
                )
                .with_label(goal.span, "met without capsules")
                .with_help(help),
            )
        })
        .collect()
}

/// Where an output goes: its own path, or its file name inside `out_dir`.
pub fn output_path(path: &Path, out_dir: Option<&Path>) -> PathBuf {
    match (out_dir, path.file_name()) {
        (Some(folder), Some(name)) => folder.join(name),
        _ => path.to_path_buf(),
    }
}

/// A warning for every pose that settling on the hull turned by more than [`SNAP_WARNING`]: the
/// written rotation puts no facet on the ground.
fn settled_poses(project: &Project, poses: &[PoseEvaluation]) -> Vec<Problem> {
    let mut warnings = Vec::new();
    for (pose, evaluation) in project.poses.iter().zip(poses) {
        let Some(resting) = &evaluation.resting else {
            continue;
        };
        if resting.correction <= SNAP_WARNING {
            continue;
        }
        let [x, y, z] = resting.down;
        warnings.push(
            Problem::warning(
                "ballast::pose::settles",
                format!(
                    "pose `{}` puts no facet of the model's hull on the ground: it settles {:.2}° away, onto the facet facing {x:.6} {y:.6} {z:.6} ({} corners, area {:.4})",
                    pose.name.value, resting.correction, resting.corners, resting.area
                ),
            )
            .with_label(pose.name.span, "this pose is evaluated as it settles")
            .with_help(format!("to rest on that facet exactly, write `down {x:.6} {y:.6} {z:.6}` instead of the rotation; `ballast poses` lists the facets")),
        );
    }
    warnings
}

/// A warning for every ball whose rest end cannot be trusted in a pose, pointing at the capsule's
/// node when the project file has it.
fn undetermined_balls(
    project: &Project,
    design: &Design,
    poses: &[PoseEvaluation],
) -> Vec<Problem> {
    let mut warnings = Vec::new();
    for (pose, evaluation) in project.poses.iter().zip(poses) {
        for (capsule, ball) in design.capsules.iter().zip(&evaluation.balls) {
            if ball.rest != BallRest::Undetermined {
                continue;
            }
            let mut warning = Problem::warning(
                "ballast::capsule::undetermined",
                format!(
                    "in pose `{}`, capsule `{}` is {:.1}° from horizontal, less than the ball's min-angle of {}°: its ball may rest anywhere along it",
                    pose.name.value, capsule.name, ball.elevation, project.ball.min_angle
                ),
            );
            if let Some(written) = project
                .capsules
                .iter()
                .find(|c| c.name.value == capsule.name)
            {
                warning = warning.with_label(written.span, "this capsule");
            }
            warnings.push(
                warning
                    .with_label(pose.name.span, "in this pose")
                    .with_help("tilt the capsule's axis, or the result in this pose assumes the ball in the middle"),
            );
        }
    }
    warnings
}

/// A warning for every stable state of a hanging or floating goal other than the wanted one,
/// when the goal does not ask for uniqueness (with `unique=#true` the goal fails instead), and
/// one for every goal whose enumeration of ball ends was cut.
fn other_states(project: &Project, poses: &[PoseEvaluation]) -> Vec<Problem> {
    let mut warnings = Vec::new();
    for (pose, evaluation) in project.poses.iter().zip(poses) {
        for (goal, outcome) in pose.goals.iter().zip(&evaluation.goals) {
            let (verb, unique, equilibria) = match &outcome.outcome {
                GoalOutcome::Suspend {
                    unique, equilibria, ..
                } => ("hangs", *unique, equilibria),
                GoalOutcome::Immerse {
                    unique, equilibria, ..
                } => ("floats", *unique, equilibria),
                _ => continue,
            };
            if !unique {
                for state in equilibria.unwanted() {
                    warnings.push(
                        Problem::warning(
                            "ballast::goal::other_state",
                            format!(
                                "in pose `{}`, the model also {verb} stably {}",
                                pose.name.value,
                                state.describe()
                            ),
                        )
                        .with_label(goal.span, "this goal")
                        .with_help(format!(
                            "set `unique=#true` on the `{}` goal to have the optimizer remove other stable states",
                            goal.value.keyword()
                        )),
                    );
                }
            }
            if !equilibria.complete {
                warnings.push(
                    Problem::warning(
                        "ballast::goal::states_cut",
                        format!(
                            "in pose `{}`, more than {MAX_ENUMERATED_BALLS} balls can roll: only {} assignments of ball ends (at most two balls moved) were tried for other stable states",
                            pose.name.value, equilibria.assignments
                        ),
                    )
                    .with_label(goal.span, "this goal"),
                );
            }
        }
    }
    warnings
}
