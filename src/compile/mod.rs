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
mod mesh_repairs;
mod meshes;
mod optimization;
mod optimize;
mod orientation;
mod output_paths;
mod outputs;
mod pose_warnings;
mod print_cache;
mod print_files;
mod report;
mod sanity;
mod scene;
mod solution;
mod workspace;

use limits::optimizer_limits;
use optimize::precompute_ahead;
use pose_warnings::{
    lost_goal_warnings, other_states, settled_poses, solid_goals_lost, undetermined_balls,
};

use std::path::{Path, PathBuf};

pub use calibration::{
    calibration_path, calibration_text, CALIBRATION_REFUSED, CALIBRATION_STALE,
    CALIBRATION_UNKNOWN, CALIBRATION_UNREADABLE,
};
pub use design::{fabrication_problems, hand_placed_design};
pub use insertion::{direction_words, plan_insertions_into, BRIDGE_LIMIT_MM};
pub use mesh_cache::MeshCache;
pub use meshes::load_components;
pub use optimization::{
    CandidateReport, CapsuleOrigin, GoalName, Optimization, SeedReport, Starts, Timings,
};
pub use optimize::{
    length_decimals, optimize_design, prepare, unfit_design, OptimizeOptions, Preparation,
    WarmStart, UNFIT_DESIGN,
};
pub use orientation::{
    insertion_rank, layer_grid, print_orientations, print_plan, print_setup, BED_CENTRE_MM,
    BED_GAP_MM,
};
pub(crate) use output_paths::lexical;
pub use output_paths::{
    check_output_paths, input_files, output_targets, OutputScope, OutputTarget, WriteOptions,
    DUPLICATE_OUTPUT, INTERRUPTED_OUTPUTS, OUTSIDE_PROJECT, OVERWRITES_INPUT,
};
pub use outputs::{
    finish_interrupted_outputs, journal_path, write_outputs, write_outputs_with, PrintFileCache,
    WrittenOutputs,
};
pub use print_cache::PrintCache;
pub use print_files::{bed_parts, bed_plate_pauses, print_settings};
pub use report::{Report, REPORT_FORMAT};
pub use solution::{interrupted_solution_text, read_solution, solution_text};
pub use workspace::{Failure, Stage, Workspace};

use std::sync::Arc;

use crate::balance::{
    bare_bodies, cut_bodies, evaluate_pose, ComponentBody, PartPrints, PoseEvaluation,
};
use crate::design::Design;
use crate::diagnostic::Problem;
use crate::fabrication::{Orientation, PrintPlan};
use crate::geometry::{
    ConvexHull, MassProperties, MeshLimits, PrintCorrection, PrintVolumes, ReadPolicy, TriMesh,
};
use crate::spec::model::{Optimize, Project};
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
    /// Each component's convex hull, rest frame, in project order (`None` for a mesh with no
    /// volume): computed once, moved into every pose.
    pub hulls: Arc<[Option<ConvexHull>]>,
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
        cut_bodies(&self.meshes, &self.hulls, &self.mass, &self.printed)
    }

    /// What it takes to print each component's material for any design (for the optimizer).
    pub fn part_prints(&self) -> PartPrints {
        part_prints(
            &self.project,
            self.mass.clone(),
            self.hulls.clone(),
            self.prints.clone(),
            &self.orientations,
            &self.corrections,
        )
    }

    /// The components' bodies before any capsule is cut (`prints`).
    pub fn bare_bodies(&self) -> Vec<ComponentBody<'_>> {
        bare_bodies(&self.meshes, &self.hulls, &self.mass, &self.prints)
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
    // A build killed while it replaced its outputs left a journal: finishing it first means
    // every command sees one build's outputs (the solution file read below among them).
    if let Err(error) =
        finish_interrupted_outputs(&project, project_path, options.out_dir.as_deref())
    {
        problems.push(Problem::warning(
            INTERRUPTED_OUTPUTS,
            format!("cannot finish replacing the outputs of an interrupted build: {error}"),
        ));
    }
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
    let (loaded, mesh_problems) = load_components(&project, &mut workspace.meshes, &policy);
    problems.extend(mesh_problems);
    // Each component's hull, once (computed while its mesh was checked): the print orientation
    // turns it, every pose moves it.
    let (meshes, solids, hulls): (_, _, Option<Arc<[Option<ConvexHull>]>>) = match loaded {
        Some((meshes, solids, hulls)) => (Some(meshes), Some(solids), Some(hulls.into())),
        None => (None, None, None),
    };
    // The written capsules as they stand, for the ball-gap warnings and the capsules the print
    // orientation is chosen for; their problems come with the fabrication checks below, and the
    // ball-gap warnings after them, since a gap matters only for a capsule that is valid.
    let (written, _) = hand_placed_design(&project);
    let ball_gaps = design::ball_gap_warnings(&project, &written);
    let known = design::fixed_capsules(&project, &written);
    let orientations = meshes.as_ref().zip(hulls.as_ref()).map(|(meshes, hulls)| {
        let (orientations, orientation_problems) =
            print_orientations(&project, meshes, hulls, &known);
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
    if let (Some(meshes), Some(hulls), Some(solids), Some(orientations)) = (
        meshes
            .as_ref()
            .filter(|_| project.poses.iter().any(|pose| pose.down.is_some())),
        &hulls,
        &solids,
        &orientations,
    ) {
        let prints = &corrected
            .insert(corrected_volumes(
                &project,
                meshes,
                solids,
                orientations,
                &corrections,
                &mut workspace.prints,
            ))
            .prints;
        let bodies = bare_bodies(meshes, hulls, solids, prints);
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
    let (meshes, hulls, solids, orientations) = match (meshes, hulls, solids, orientations) {
        (Some(meshes), Some(hulls), Some(solids), Some(orientations))
            if !problems.iter().any(Problem::is_error) =>
        {
            (meshes, hulls, solids, orientations)
        }
        _ => return Err(Failure::Invalid(problems)),
    };
    let corrected = corrected.unwrap_or_else(|| {
        // The search's grids and skeletons do not depend on the print volumes: they are
        // computed beside them (each uses every core, but not all the time).
        let ahead = searched(&project, options.optimize.as_ref(), &meshes);
        let (prints, cache, cancel, reporter) = workspace.split();
        std::thread::scope(|scope| {
            if let Some((settings, warm)) = ahead {
                let (project, meshes) = (&project, &meshes);
                scope.spawn(move || {
                    precompute_ahead(project, settings, meshes, warm, cache, cancel, reporter)
                });
            }
            corrected_volumes(
                &project,
                &meshes,
                &solids,
                &orientations,
                &corrections,
                prints,
            )
        })
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
    let parts = part_prints(
        &project,
        solids,
        hulls.clone(),
        prints,
        &orientations,
        &corrections,
    )
    .with_rasters(rasters);
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
                // What `check` would refuse in the solution file is never written as one.
                let unfit = fabrication_problems(&project, &meshes, &design, &print);
                if let Some(first) = unfit.iter().find(|p| p.is_error()) {
                    problems.push(unfit_design(settings, first));
                    return Err(Failure::Invalid(problems));
                }
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
    let bodies = cut_bodies(&meshes, &hulls, &parts.solids, &printed);
    let mass = parts.solids.clone();
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
        hulls,
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

/// What it takes to print each component's material for any design: its solid's mass
/// properties, its `bare` print volumes (corrected), its print rotation and its calibration
/// correction.
fn part_prints(
    project: &Project,
    solids: Vec<MassProperties>,
    hulls: Arc<[Option<ConvexHull>]>,
    bare: Vec<PrintVolumes>,
    orientations: &[Orientation],
    corrections: &[PrintCorrection],
) -> PartPrints {
    PartPrints::new(
        solids,
        hulls,
        bare,
        orientations.iter().map(|o| o.to_print).collect(),
        corrections.to_vec(),
        project.print,
    )
}

/// Each component's print volumes in its print orientation (from the `prints` cache), with the
/// calibration's corrections added, the corrections applied and the problems of those refused.
fn corrected_volumes(
    project: &Project,
    meshes: &[TriMesh],
    solids: &[MassProperties],
    orientations: &[Orientation],
    corrections: &[PrintCorrection],
    prints: &mut PrintCache,
) -> calibration::Corrected {
    let prints: Vec<PrintVolumes> = meshes
        .iter()
        .zip(solids)
        .zip(orientations)
        .map(|((mesh, solid), o)| prints.volumes(project, mesh, solid, o.to_print))
        .collect();
    calibration::corrected_prints(project, &prints, corrections)
}

/// When `project` is built with a search (optimized, within the optimizer's limits over
/// `meshes`, and not asked to judge a warm start first): its optimizer settings, and whether a
/// warm start is given. Whether that warm start fits the meshes is left to the optimizer (it
/// hashes every mesh): one given, the precomputation ahead stops at the grids.
fn searched<'p>(
    project: &'p Project,
    run: Option<&OptimizeOptions>,
    meshes: &[TriMesh],
) -> Option<(&'p Optimize, bool)> {
    let (settings, run) = (project.optimize.as_ref()?, run?);
    let warm = run.warm_start.is_some();
    if (warm && run.judge_warm_start)
        || !optimizer_limits(project, settings, meshes, run).is_empty()
    {
        return None;
    }
    Some((settings, warm))
}

/// Where an output goes: its own path, or its file name inside `out_dir`.
pub fn output_path(path: &Path, out_dir: Option<&Path>) -> PathBuf {
    match (out_dir, path.file_name()) {
        (Some(folder), Some(name)) => folder.join(name),
        _ => path.to_path_buf(),
    }
}
