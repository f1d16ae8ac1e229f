//! The command line, as clap parses it.

use std::path::PathBuf;

use clap::{Parser, Subcommand};

use crate::pauses::PauseCommand;

/// ballast: design 3D-printed objects that balance, with steel balls rolling in capsules.
#[derive(Debug, Parser)]
#[command(name = "ballast", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Check a project and show what the object does in every pose. Writes nothing (but
    /// finishes replacing the outputs of a build killed while it replaced them).
    ///
    /// Exit status: 0 every goal met, 1 the project is valid but some goal is not met,
    /// 2 invalid project or failure.
    Check {
        /// The project file (.kdl).
        project: PathBuf,
        /// Where meshes may be read from, and how large they may be.
        #[command(flatten)]
        inputs: InputArgs,
        /// Print the JSON report on standard output instead of the table.
        #[arg(long)]
        json: bool,
        /// How diagnostics are printed: `human` (drawn on standard error) or `json` (one JSON
        /// object per diagnostic on standard output, every other line of output on standard error).
        #[arg(long, value_enum, value_name = "FORMAT", default_value_t = MessageFormat::Human)]
        message_format: MessageFormat,
        /// Read the solution file from this folder (where `build --out-dir` wrote it) instead of
        /// the path the project names.
        #[arg(long, value_name = "DIR")]
        out_dir: Option<PathBuf>,
    },
    /// Re-check every goal with a rigid-body simulation (rapier) instead of ballast's own physics,
    /// and print the simulated value beside the computed one. Writes nothing (but finishes
    /// replacing the outputs of a build killed while it replaced them).
    ///
    /// The design is the one `check` evaluates (the written capsules, or the solution file). A
    /// stand goal is set down and the ground tilted slowly until the model topples (in the worst
    /// direction ballast computed and eleven others); imbalance is set down; suspend hangs from a
    /// spherical joint and immerse floats, each let go from ten orientations, and the distinct
    /// final states are listed.
    ///
    /// With `--gcode FILE`, checks that G-code file, sliced from the project's print files,
    /// instead: every goal with the sliced mass, the pauses at the planned layers with their
    /// messages, no extrusion inside a void (the simulation is not run then).
    ///
    /// Exit status: 0 every goal agrees (within 1°, same state), 1 the project is valid but some
    /// goal disagrees, 2 invalid project or failure. With `--gcode`: 0 the file is as planned and
    /// every goal is met with its mass, 1 something is not, 2 invalid project or unreadable file.
    Verify {
        /// The project file (.kdl).
        project: PathBuf,
        /// Where meshes may be read from, and how large they may be.
        #[command(flatten)]
        inputs: InputArgs,
        /// Print the verification as JSON on standard output instead of the table.
        #[arg(long)]
        json: bool,
        /// Check this G-code file, sliced from the project's print files.
        #[arg(long, value_name = "FILE")]
        gcode: Option<PathBuf>,
        /// Diameter of the filament the G-code feeds, mm, 0.5 to 5 (with `--gcode`).
        #[arg(long, value_name = "MM", default_value_t = 1.75, value_parser = filament_mm)]
        filament_diameter: f64,
        /// The command the G-code pauses with (with `--gcode`).
        #[arg(long, value_name = "GCODE", default_value = "M601")]
        pause_gcode: String,
        /// With `--gcode`: also write the project's calibration file
        /// (`<project>.calibration.json`), the mass the file deposits less the mass model's per
        /// component, which every later build adds to the mass model.
        #[arg(long, requires = "gcode")]
        calibrate: bool,
        /// Read the solution file from this folder (where `build --out-dir` wrote it) instead of
        /// the path the project names.
        #[arg(long, value_name = "DIR")]
        out_dir: Option<PathBuf>,
    },
    /// Put the print plan's pauses into a G-code file sliced from the project's print files by
    /// any slicer (PrusaSlicer, SuperSlicer, OrcaSlicer, Bambu Studio, Cura), then check the
    /// result as `verify --gcode` does.
    ///
    /// Each pause goes before the first layer printed after it, found by its height (the plan's
    /// resume height), right after the slicer's layer marker (`;LAYER_CHANGE`, `; CHANGE_LAYER`,
    /// `;LAYER:n`): `M117` with the insertion sheet's message, then the pause command. A pause
    /// the file already has there (the same command) is kept and none added. The output is
    /// written atomically; the input is left as it is unless OUT is IN.
    ///
    /// Exit status: 0 written, and the result is as planned and every goal is met with its mass;
    /// 1 written, but some check fails; 2 invalid project, or nothing written (an unreadable
    /// file, or a planned pause at a height the file has no layer at).
    Pauses {
        /// The project file (.kdl).
        project: PathBuf,
        /// Where meshes may be read from, and how large they may be.
        #[command(flatten)]
        inputs: InputArgs,
        /// The G-code file sliced from the project's print files.
        #[arg(long, value_name = "IN")]
        gcode: PathBuf,
        /// Where to write the G-code with the pauses (IN itself is replaced atomically).
        #[arg(short, long, value_name = "OUT")]
        output: PathBuf,
        /// The printer's pause command: `M601` (Prusa firmware, Marlin), `M0` (Marlin),
        /// `M400 U1` (Bambu Lab), `PAUSE` (Klipper), or any one line of G-code.
        #[arg(long, value_name = "GCODE", default_value = "M601", value_parser = pause_command)]
        pause_gcode: PauseCommand,
        /// Diameter of the filament the G-code feeds, mm, 0.5 to 5.
        #[arg(long, value_name = "MM", default_value_t = 1.75, value_parser = filament_mm)]
        filament_diameter: f64,
        /// Print what was put where and the check as one JSON object instead of the tables.
        #[arg(long)]
        json: bool,
        /// Read the solution file from this folder (where `build --out-dir` wrote it) instead of
        /// the path the project names.
        #[arg(long, value_name = "DIR")]
        out_dir: Option<PathBuf>,
    },
    /// Check a project, optimize its capsules when it has an `optimize` node, then write its
    /// glTF file, JSON report and (when optimized) solution file.
    ///
    /// Nothing is written when the project is invalid. Exit status as for `check`.
    ///
    /// Ctrl-C, SIGTERM or `--time-limit` stop the optimizer's search: the best design of the
    /// capsule counts tried so far is written, marked as interrupted in the report, and the exit
    /// status is 130, 143 or 124 (nothing is written when no capsule count was finished). A
    /// second Ctrl-C or SIGTERM exits at once.
    Build {
        /// The project file (.kdl).
        project: PathBuf,
        /// Where meshes may be read from, and how large they may be.
        #[command(flatten)]
        inputs: InputArgs,
        /// Write the outputs into this folder instead of the ones the project file names.
        #[arg(long, value_name = "DIR")]
        out_dir: Option<PathBuf>,
        /// Accept output paths in the project file outside its folder (absolute, or through
        /// `..`); refused otherwise.
        #[arg(long)]
        write_outside: bool,
        /// How diagnostics are printed: `human` (drawn on standard error) or `json` (one JSON
        /// object per diagnostic on standard output, every other line of output on standard error).
        #[arg(long, value_enum, value_name = "FORMAT", default_value_t = MessageFormat::Human)]
        message_format: MessageFormat,
        /// Stop the optimizer's search after this many seconds of build and write the best design
        /// found so far.
        #[arg(long, value_name = "SECONDS", value_parser = positive_seconds)]
        time_limit: Option<f64>,
        /// How to optimize.
        #[command(flatten)]
        optimize: OptimizeArgs,
    },
    /// Write a starter project beside a mesh file (.obj, .stl, .3mf, .ply, .gltf, .glb): the mesh as
    /// its one component, read in the unit its size suggests when the file states none, the
    /// facets the solid model rests on stably as poses (the most stable active, the others
    /// commented out) with a `stand` goal, and `optimize`.
    ///
    /// Exit status 0, or 2 when the mesh cannot be read or used (its diagnostics are printed and
    /// nothing is written) or the project file exists (without `--force`).
    New {
        /// The mesh file.
        mesh: PathBuf,
        /// The project file to write (default: beside the mesh, its name with `.kdl`); it must
        /// be in the mesh's folder or above it.
        #[arg(short, long, value_name = "PROJECT")]
        output: Option<PathBuf>,
        /// Replace the project file when it exists.
        #[arg(long)]
        force: bool,
        /// Where meshes may be read from, and how large they may be.
        #[command(flatten)]
        inputs: InputArgs,
    },
    /// List the facets of the model's convex hull it rests on stably, most stable first, with
    /// each one's tilt margin, area and the `pose` lines to paste into the project.
    ///
    /// The margin is the solid model's (no capsules) and, when the project has capsules (written,
    /// or the solution file of an `optimize` project), the design's too. A facet is listed when
    /// either rests on it stably. Exit status 0, or 2 for an invalid project.
    Poses {
        /// The project file (.kdl).
        project: PathBuf,
        /// Where meshes may be read from, and how large they may be.
        #[command(flatten)]
        inputs: InputArgs,
        /// Place the components as this pose does (default: the first pose), for a project whose
        /// poses move components.
        #[arg(long, value_name = "NAME")]
        pose: Option<String>,
        /// Read the solution file from this folder (where `build --out-dir` wrote it) instead of
        /// the path the project names.
        #[arg(long, value_name = "DIR")]
        out_dir: Option<PathBuf>,
    },
    /// Build the project, then rebuild it whenever the project file or one of its meshes changes,
    /// until Ctrl-C.
    ///
    /// Prints what changed since the last good build and how long it took. An invalid project
    /// prints its diagnostics and leaves the last good outputs as they were. A newer save cancels
    /// the build in progress. Meshes, distance grids and skeletons are kept between builds; after
    /// a change that leaves the meshes alone, the optimizer first starts from the last design
    /// (written at once), then runs the full search, so the outputs end as `build` writes them.
    /// Exit status 0 on Ctrl-C; 2 when watching cannot start.
    Watch {
        /// The project file (.kdl).
        project: PathBuf,
        /// Where meshes may be read from, and how large they may be.
        #[command(flatten)]
        inputs: InputArgs,
        /// Write the outputs into this folder instead of the ones the project file names.
        #[arg(long, value_name = "DIR")]
        out_dir: Option<PathBuf>,
        /// Accept output paths in the project file outside its folder (absolute, or through
        /// `..`); refused otherwise.
        #[arg(long)]
        write_outside: bool,
        /// How diagnostics are printed: `human` (drawn on standard error) or `json` (one JSON
        /// object per diagnostic on standard output, every other line of output on standard error).
        #[arg(long, value_enum, value_name = "FORMAT", default_value_t = MessageFormat::Human)]
        message_format: MessageFormat,
        /// How to optimize.
        #[command(flatten)]
        optimize: OptimizeArgs,
    },
}

/// The optimizer options of `build` and `watch`.
#[derive(Debug, Clone, clap::Args)]
pub struct OptimizeArgs {
    /// Use exactly this many capsules (pinned ones included), overriding `optimize capsules=`.
    #[arg(long, value_name = "N")]
    pub capsules: Option<usize>,
    /// Also optimize N random starts per capsule count and show where the heuristic's result
    /// ranks among them (slow).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub exhaustive: usize,
    /// The local solver: `hybrid` (SLSQP, then COBYLA where SLSQP misses; the default),
    /// `slsqp` (exact gradients) or `cobyla` (derivative-free).
    #[arg(long, value_enum, default_value_t = Solver::Hybrid)]
    pub solver: Solver,
    /// Neither read nor write the disk cache of distance grids and skeletons (by default in the
    /// user's cache folder, or `BALLAST_CACHE_DIR`; `off` there disables it too).
    #[arg(long)]
    pub no_cache: bool,
}

/// Where meshes may be read from and how large they may be: options of every command.
#[derive(Debug, Clone, clap::Args)]
pub struct InputArgs {
    /// Let mesh paths and glTF buffer URIs point outside the project file's folder (by default
    /// every mesh and buffer file must be inside it, symbolic links followed).
    #[arg(long)]
    pub read_outside: bool,
    /// The most one mesh may read, in MiB: its file and its glTF buffer files together.
    #[arg(long, value_name = "MB", default_value_t = crate::geometry::DEFAULT_MAX_MESH_BYTES >> 20)]
    pub max_mesh_mb: u64,
    /// The most triangles one mesh may have (and three times as many vertices read).
    #[arg(long, value_name = "N", default_value_t = crate::geometry::DEFAULT_MAX_TRIANGLES)]
    pub max_triangles: usize,
}

/// How `check`, `build` and `watch` print diagnostics (`--message-format`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MessageFormat {
    /// Drawn against the source on standard error.
    Human,
    /// One JSON object per line on standard output; the rest of the output on standard error.
    Json,
}

/// The local solvers `build --solver` offers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Solver {
    /// SLSQP, then COBYLA from its best point where it misses a goal or a constraint.
    Hybrid,
    /// Sequential quadratic programming with exact gradients.
    Slsqp,
    /// Constrained optimization by linear approximations, derivative-free.
    Cobyla,
}

/// A positive, finite number of seconds.
fn positive_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(value) if value.is_finite() && value > 0.0 && value < 1e9 => Ok(value),
        _ => Err(format!("`{text}` is not a positive number of seconds")),
    }
}

/// A filament diameter within [`crate::sliced::FILAMENT_DIAMETER_MM`].
fn filament_mm(text: &str) -> Result<f64, String> {
    let range = crate::sliced::FILAMENT_DIAMETER_MM;
    match text.parse::<f64>() {
        Ok(value) if range.contains(&value) => Ok(value),
        _ => Err(format!(
            "`{text}` is not a filament diameter: give one from {} to {} mm",
            range.start(),
            range.end()
        )),
    }
}

/// A pause command: one line of G-code (`crate::pauses::PauseCommand`).
fn pause_command(text: &str) -> Result<PauseCommand, String> {
    PauseCommand::new(text)
}
