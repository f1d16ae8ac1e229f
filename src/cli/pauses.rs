//! `ballast pauses`: the print plan's pauses put into a G-code file sliced by any slicer, the
//! result written atomically, then checked as `verify --gcode` checks a file.

use std::fmt::Write;
use std::path::Path;

use serde::Serialize;

use super::diagnostics::render_for_terminal;
use super::sliced::{check_gcode, read_gcode, table, unreadable, NO_SHIFT_MM};
use super::{compile_file, file_name, MessageFormat, EXIT_INVALID, EXIT_MET, EXIT_UNMET};
use crate::compile::{CompileOptions, Workspace};
use crate::diagnostic::{printable, Problem};
use crate::emit::write_atomic;
use crate::fabrication::PlatePause;
use crate::file_identity::identity;
use crate::pauses::{insert_pauses, PauseCommand, Paused, PausesError, PlacedPause};
use crate::sliced::{SlicedCheck, SlicedOptions};
use crate::spec::codes;

/// What `ballast pauses` is asked to do.
pub struct PausesRun<'a> {
    /// The project file.
    pub project: &'a Path,
    /// The sliced G-code file read.
    pub gcode: &'a Path,
    /// Where the G-code with the pauses goes.
    pub output: &'a Path,
    /// The printer's pause command.
    pub command: &'a PauseCommand,
    /// The filament the file feeds, mm.
    pub filament_diameter: f64,
    /// Print [`PausesReport`] as JSON instead of the tables.
    pub json: bool,
}

/// What `ballast pauses --json` prints: where each pause of the plan went, and the check of
/// the written file (as `verify --gcode --json` prints it).
#[derive(Serialize)]
struct PausesReport<'a> {
    /// The G-code file read, as given.
    input: &'a str,
    /// The file written, as given.
    output: &'a str,
    /// The pause command put in.
    pause_command: &'a str,
    /// One per pause of the plan, lowest first.
    pauses: &'a [PlacedPause],
    /// The written file checked against the plan.
    check: &'a SlicedCheck,
}

/// Puts the plan's pauses of the project into the G-code file, writes the result and checks
/// it; returns the exit status: as `verify --gcode` for the written file, or
/// [`EXIT_INVALID`] when nothing was written.
pub fn run(request: &PausesRun, options: &CompileOptions) -> i32 {
    let Ok(compilation) = compile_file(
        request.project,
        options,
        &mut Workspace::new(),
        MessageFormat::Human,
    ) else {
        return EXIT_INVALID;
    };
    let shown_input = printable(&request.gcode.display().to_string()).into_owned();
    let shown_output = printable(&request.output.display().to_string()).into_owned();
    if is_same_file(request.output, request.project) {
        eprintln!("error: {shown_output} is the project file: give another output file");
        return EXIT_INVALID;
    }
    let Some(bytes) = read_gcode(request.gcode, &shown_input) else {
        return EXIT_INVALID;
    };
    let project = &compilation.project;
    let mm = project.units.from_millimetres(1.0);
    let names: Vec<&str> = (0..project.components.len())
        .map(|index| project.component_name(index))
        .collect();
    let plan = &compilation.print_plan;
    let pauses: Vec<PlatePause> = plan
        .plate_pauses(&names)
        .into_iter()
        .map(|pause| PlatePause {
            height: pause.height / mm,
            resume_height: pause.resume_height / mm,
            ..pause
        })
        .collect();
    let paused = match insert_pauses(&bytes, &pauses, plan.layer_height / mm, request.command) {
        Ok(paused) => paused,
        Err(error) => {
            let problem = match &error {
                PausesError::Gcode(error) => {
                    unreadable(error, &shown_input, &String::from_utf8_lossy(&bytes))
                }
                PausesError::Empty => Problem::error(codes::PAUSES_NO_LAYER, error.to_string()),
                PausesError::NoLayer { .. } | PausesError::FirstLayer { .. } => {
                    Problem::error(codes::PAUSES_NO_LAYER, printable(&error.to_string())).with_help(
                        format!(
                            "slice with the project's layers: the first {} mm, then {} mm each \
                             (`ballast check` prints the plan)",
                            plan.first_layer_height / mm,
                            plan.layer_height / mm
                        ),
                    )
                }
                PausesError::RepeatedHeight { .. } => {
                    Problem::error(codes::PAUSES_REPEATED_HEIGHT, error.to_string())
                }
            };
            eprint!("{}", render_for_terminal(&[problem], &shown_input, ""));
            eprintln!("nothing written");
            return EXIT_INVALID;
        }
    };
    if let Err(error) = write_atomic(request.output, &paused.bytes) {
        eprintln!(
            "error: cannot write {shown_output}: {}",
            printable(&error.to_string())
        );
        return EXIT_INVALID;
    }
    if !request.json {
        print!(
            "{}",
            summary(
                &paused,
                &file_name(request.project),
                (&file_name(request.gcode), &file_name(request.output)),
                request.command
            )
        );
    }
    let text = String::from_utf8_lossy(&paused.bytes);
    let sliced = SlicedOptions {
        filament_diameter: request.filament_diameter,
        pause_gcode: request.command.as_str().to_string(),
    };
    let Some(check) = check_gcode(&compilation, &text, &shown_output, &sliced) else {
        eprintln!("{shown_output} was written, but cannot be checked against the plan");
        return EXIT_INVALID;
    };
    if request.json {
        let report = PausesReport {
            input: &shown_input,
            output: &shown_output,
            pause_command: request.command.as_str(),
            pauses: &paused.pauses,
            check: &check,
        };
        match serde_json::to_string_pretty(&report) {
            Ok(text) => println!("{text}"),
            Err(error) => {
                eprintln!("error: cannot encode what was done: {error}");
                return EXIT_INVALID;
            }
        }
    } else {
        let no_shift = project.units.from_millimetres(NO_SHIFT_MM);
        print!(
            "\n{}",
            table(
                &check,
                &file_name(request.project),
                &file_name(request.output),
                no_shift
            )
        );
    }
    if check.passes() {
        EXIT_MET
    } else {
        EXIT_UNMET
    }
}

/// Whether `a` and `b` name one existing file.
fn is_same_file(a: &Path, b: &Path) -> bool {
    let of = |path: &Path| std::fs::metadata(path).ok().and_then(|m| identity(&m));
    of(a).is_some_and(|a| Some(a) == of(b))
}

/// What was put where: a line per pause of the plan.
fn summary(
    paused: &Paused,
    project_name: &str,
    (input, output): (&str, &str),
    command: &PauseCommand,
) -> String {
    let mut out = String::new();
    let added = paused.pauses.iter().filter(|p| !p.kept).count();
    let _ = writeln!(
        out,
        "{}: {} of {} planned pause{} put into {}, written to {} (pause command `{}`); heights in mm",
        printable(project_name),
        added,
        paused.pauses.len(),
        if paused.pauses.len() == 1 { "" } else { "s" },
        printable(input),
        printable(output),
        printable(command.as_str())
    );
    for placed in &paused.pauses {
        let pause = &placed.pause;
        let what = if placed.kept {
            "already in the file, kept"
        } else {
            "added"
        };
        let _ = writeln!(
            out,
            "  after layer {} (printed to {:.3}), before the file's layer {} (to {:.3}): {what}, \
             line {}: \"{}\"",
            pause.layers_done,
            pause.height,
            placed.layer + 1,
            pause.resume_height,
            placed.line,
            printable(&pause.message)
        );
    }
    out
}
