//! The `ballast` command line: parse arguments, run the pipeline, print, and choose the exit status.
//!
//! Exit status, for every subcommand: [`EXIT_MET`] when every goal is met, [`EXIT_UNMET`] when the
//! project is valid but some goal is not, [`EXIT_INVALID`] for an invalid project or any failure.
//! For `verify`, "met" reads "the simulation agrees with the computed value". A `build` whose search
//! was interrupted exits with [`EXIT_SIGINT`], [`EXIT_SIGTERM`] or [`EXIT_TIME_LIMIT`].

mod args;
mod build;
mod check;
mod diagnostics;
mod new;
mod optimization_table;
mod pauses;
mod poses;
mod progress;
mod sliced;
mod table;
mod verify;
mod watch;

use std::path::Path;

use clap::Parser;

pub use args::{Cli, Command, InputArgs, MessageFormat, OptimizeArgs, Solver};

use crate::compile::{
    compile_with, Compilation, CompileOptions, Failure, OptimizeOptions, Workspace, WriteOptions,
};
use crate::diagnostic::Problem;
use crate::geometry::MeshLimits;
use crate::optimize::{DiskCache, Method, PrecomputeCache};
use crate::sliced::SlicedOptions;
use crate::spec::{codes, read_source};

/// Every goal of every pose is met.
pub const EXIT_MET: i32 = 0;
/// The project is valid, but some goal is not met.
pub const EXIT_UNMET: i32 = 1;
/// The project is invalid, or something failed (unreadable file, failed write).
pub const EXIT_INVALID: i32 = 2;
/// `build` was stopped by Ctrl-C (128 + SIGINT).
pub const EXIT_SIGINT: i32 = 130;
/// `build` was stopped by SIGTERM (128 + SIGTERM).
pub const EXIT_SIGTERM: i32 = 143;
/// `build --time-limit` ran out (as `timeout` exits).
pub const EXIT_TIME_LIMIT: i32 = 124;

/// Runs the command line given by the process arguments; returns the exit status.
pub fn run() -> i32 {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => {
            // Help and version requests print to stdout and succeed; misuse prints to stderr.
            let _ = error.print();
            return if error.use_stderr() {
                EXIT_INVALID
            } else {
                EXIT_MET
            };
        }
    };
    match cli.command {
        Command::Check {
            project,
            inputs,
            json,
            message_format,
            out_dir,
        } => check::run(
            &project,
            json,
            message_format,
            &CompileOptions {
                out_dir,
                ..input_options(&inputs)
            },
        ),
        Command::Verify {
            project,
            inputs,
            json,
            out_dir,
            gcode,
            filament_diameter,
            pause_gcode,
            calibrate,
        } => {
            let options = CompileOptions {
                out_dir,
                ..input_options(&inputs)
            };
            match gcode {
                None => verify::run(&project, json, &options),
                Some(gcode) => {
                    let sliced = SlicedOptions {
                        filament_diameter,
                        pause_gcode,
                    };
                    sliced::run(&project, &gcode, json, calibrate, &options, &sliced)
                }
            }
        }
        Command::Pauses {
            project,
            inputs,
            gcode,
            output,
            pause_gcode,
            filament_diameter,
            json,
            out_dir,
        } => pauses::run(
            &pauses::PausesRun {
                project: &project,
                gcode: &gcode,
                output: &output,
                command: &pause_gcode,
                filament_diameter,
                json,
            },
            &CompileOptions {
                out_dir,
                ..input_options(&inputs)
            },
        ),
        Command::Build {
            project,
            inputs,
            out_dir,
            write_outside,
            message_format,
            time_limit,
            optimize,
        } => build::run(
            &project,
            message_format,
            &optimize_options(out_dir, write_outside, &optimize, &inputs),
            precompute_cache(&optimize),
            time_limit.map(std::time::Duration::from_secs_f64),
        ),
        Command::New {
            mesh,
            output,
            force,
            inputs,
        } => new::run(&mesh, output.as_deref(), force, &input_options(&inputs)),
        Command::Poses {
            project,
            inputs,
            pose,
            out_dir,
        } => poses::run(
            &project,
            pose.as_deref(),
            &CompileOptions {
                out_dir,
                ..input_options(&inputs)
            },
        ),
        Command::Watch {
            project,
            inputs,
            out_dir,
            write_outside,
            message_format,
            optimize,
        } => watch::run(
            &project,
            message_format,
            &optimize_options(out_dir, write_outside, &optimize, &inputs),
            precompute_cache(&optimize),
        ),
    }
}

/// The options of a command that reads the solution file, from its input options.
fn input_options(inputs: &InputArgs) -> CompileOptions {
    CompileOptions {
        out_dir: None,
        optimize: None,
        read_outside: inputs.read_outside,
        mesh_limits: MeshLimits {
            max_bytes: inputs.max_mesh_mb.saturating_mul(1 << 20),
            max_triangles: inputs.max_triangles,
        },
        writes: None,
    }
}

/// The options of a command that optimizes and writes its outputs.
fn optimize_options(
    out_dir: Option<std::path::PathBuf>,
    write_outside: bool,
    args: &OptimizeArgs,
    inputs: &InputArgs,
) -> CompileOptions {
    CompileOptions {
        out_dir,
        writes: Some(WriteOptions {
            outside_project: write_outside,
        }),
        optimize: Some(OptimizeOptions {
            method: match args.solver {
                Solver::Hybrid => Method::Hybrid,
                Solver::Slsqp => Method::Slsqp,
                Solver::Cobyla => Method::Cobyla,
            },
            capsules: args.capsules,
            exhaustive: args.exhaustive,
            judge_warm_start: false,
            warm_start: None,
        }),
        ..input_options(inputs)
    }
}

/// The precompute cache of a command that optimizes: over the disk cache at its default location
/// unless `--no-cache` is given or there is none.
fn precompute_cache(args: &OptimizeArgs) -> PrecomputeCache {
    match DiskCache::default_location().filter(|_| !args.no_cache) {
        Some(root) => PrecomputeCache::with_disk(DiskCache::at(root)),
        None => PrecomputeCache::new(),
    }
}

/// Why [`compile_file`] gave no compilation.
enum NotCompiled {
    /// The project is unreadable or invalid; its diagnostics were printed.
    Invalid(Invalid),
    /// The workspace's cancel flag was set.
    Cancelled,
}

/// An unreadable or invalid project: its diagnostics and the text their spans point into.
struct Invalid {
    /// The project file's name, as given.
    name: String,
    /// Its text (empty when it could not be read).
    source: String,
    /// Every problem found, warnings too.
    problems: Vec<Problem>,
}

/// Prints `text`, the human-readable output of a command: on standard output, or on standard error
/// when standard output carries JSON diagnostics.
fn say(format: MessageFormat, text: &str) {
    match format {
        MessageFormat::Human => print!("{text}"),
        MessageFormat::Json => eprint!("{text}"),
    }
}

/// Prints `problems` found in `source` (named `name`) as `format` says.
fn print_problems(format: MessageFormat, problems: &[Problem], name: &str, source: &str) {
    if problems.is_empty() {
        return;
    }
    match format {
        MessageFormat::Human => eprint!(
            "{}",
            diagnostics::render_for_terminal(problems, name, source)
        ),
        MessageFormat::Json => print!("{}", diagnostics::render_json_lines(problems, name, source)),
    }
}

/// Reads and compiles the project at `path` as `options` say, in `workspace` (its cache, cancel
/// flag and progress), printing every diagnostic (warnings too) as `format` says.
fn compile_file(
    path: &Path,
    options: &CompileOptions,
    workspace: &mut Workspace,
    format: MessageFormat,
) -> Result<Compilation, NotCompiled> {
    let name = path.display().to_string();
    let invalid = |source: String, problems: Vec<Problem>| {
        NotCompiled::Invalid(Invalid {
            name: name.clone(),
            source,
            problems,
        })
    };
    let source = match read_source(path, "project file") {
        Ok(Some(source)) => source,
        Ok(None) => {
            let problem = Problem::error(
                codes::FILE_UNREADABLE,
                format!("cannot read {name}: there is no such file"),
            );
            match format {
                MessageFormat::Human => eprintln!("error: {}", problem.message),
                MessageFormat::Json => {
                    print_problems(format, std::slice::from_ref(&problem), &name, "")
                }
            }
            return Err(invalid(String::new(), vec![problem]));
        }
        Err(problem) => {
            print_problems(format, std::slice::from_ref(&*problem), &name, "");
            return Err(invalid(String::new(), vec![*problem]));
        }
    };
    let compiled = compile_with(&source, path, options, workspace);
    progress::clear(workspace);
    match compiled {
        Ok(compilation) => {
            print_problems(format, &compilation.warnings, &name, &source);
            Ok(compilation)
        }
        Err(Failure::Cancelled) => Err(NotCompiled::Cancelled),
        Err(Failure::Invalid(problems)) => {
            print_problems(format, &problems, &name, &source);
            let errors = problems.iter().filter(|p| p.is_error()).count();
            eprintln!(
                "error: {name} is invalid: {errors} error{}",
                if errors == 1 { "" } else { "s" }
            );
            Err(invalid(source, problems))
        }
    }
}

/// The exit status for a valid project.
fn goals_status(compilation: &Compilation) -> i32 {
    if compilation.all_goals_met() {
        EXIT_MET
    } else {
        EXIT_UNMET
    }
}

/// The file name of `path`, for headings.
fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|name| name.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}
