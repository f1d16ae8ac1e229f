//! `ballast verify --gcode FILE`: the sliced file checked against the design, printed as a
//! table (or JSON).

use std::fmt::Write;
use std::path::Path;
use std::sync::Arc;

use super::diagnostics::render_for_terminal;
use super::{compile_file, file_name, MessageFormat, EXIT_INVALID, EXIT_MET, EXIT_UNMET};
use crate::compile::{calibration_path, calibration_text, Compilation, CompileOptions, Workspace};
use crate::diagnostic::{Problem, SourceFile};
use crate::emit::write_atomic;
use crate::gcode::GcodeError;
use crate::sliced::{measured_corrections, verify_gcode, SlicedCheck, SlicedError, SlicedOptions};
use crate::spec::codes;

/// Checks the G-code at `gcode` against the project at `path`; prints the table, or the check
/// as JSON when `json`; when `calibrate`, also writes the project's calibration file from it.
pub fn run(
    path: &Path,
    gcode: &Path,
    json: bool,
    calibrate: bool,
    options: &CompileOptions,
    sliced: &SlicedOptions,
) -> i32 {
    let Ok(compilation) = compile_file(path, options, &mut Workspace::new(), MessageFormat::Human)
    else {
        return EXIT_INVALID;
    };
    let text = match std::fs::read_to_string(gcode) {
        Ok(text) => text,
        Err(error) => {
            eprintln!("error: cannot read {}: {error}", gcode.display());
            return EXIT_INVALID;
        }
    };
    let check = match verify_gcode(&compilation, &compilation.print_plan, &text, sliced) {
        Ok(check) => check,
        Err(SlicedError::Gcode(error)) => {
            let name = gcode.display().to_string();
            let problem = unreadable(&error, &name, &text);
            eprint!("{}", render_for_terminal(&[problem], &name, &text));
            return EXIT_INVALID;
        }
        Err(error) => {
            eprintln!("error: {}: {error}", gcode.display());
            return EXIT_INVALID;
        }
    };
    if json {
        match serde_json::to_string_pretty(&check) {
            Ok(text) => println!("{text}"),
            Err(error) => {
                eprintln!("error: cannot encode the check: {error}");
                return EXIT_INVALID;
            }
        }
    } else {
        print!("{}", table(&check, &file_name(path), &file_name(gcode)));
    }
    if calibrate {
        if let Err(message) = write_calibration(path, gcode, &compilation, &check) {
            eprintln!("error: {message}");
            return EXIT_INVALID;
        }
    }
    if check.passes() {
        EXIT_MET
    } else {
        EXIT_UNMET
    }
}

/// Writes the calibration file of the project at `path` from `check`, atomically, and says so
/// on standard error with each component's correction in grams; refuses when a part was not
/// found as planned, since its deposit would not be its own, and when a correction is not a
/// finite number (the file could not hold it).
fn write_calibration(
    path: &Path,
    gcode: &Path,
    compilation: &Compilation,
    check: &SlicedCheck,
) -> Result<(), String> {
    if let Some(mismatch) = check.components.iter().find_map(|c| c.mismatch.as_ref()) {
        return Err(format!("no calibration written: {mismatch}"));
    }
    let corrections = measured_corrections(compilation, check);
    if let Some(index) = corrections.iter().position(|correction| {
        !(correction.volume.is_finite() && correction.moment.iter().all(|m| m.is_finite()))
    }) {
        return Err(format!(
            "no calibration written: component `{}`'s plastic in the G-code is not a finite amount",
            compilation.project.component_name(index)
        ));
    }
    let text = calibration_text(
        &compilation.project,
        &compilation.meshes,
        &compilation.orientations,
        &corrections,
        &file_name(gcode),
    );
    let target = calibration_path(path);
    write_atomic(&target, text.as_bytes())
        .map_err(|error| format!("cannot write {}: {error}", target.display()))?;
    let grams = compilation.project.material.density * compilation.project.units.cubic_in_cm3();
    let changes: Vec<String> = corrections
        .iter()
        .enumerate()
        .map(|(index, correction)| {
            format!(
                "`{}` {:+.2} g",
                compilation.project.component_name(index),
                correction.volume * grams
            )
        })
        .collect();
    eprintln!(
        "wrote {}: the mass model corrected by {} ({}); build again to design for it",
        target.display(),
        changes.join(", "),
        file_name(gcode)
    );
    Ok(())
}

/// The diagnostic for a G-code line that does not read, pointed at the word.
fn unreadable(error: &GcodeError, name: &str, text: &str) -> Problem {
    let start: usize = text
        .split_inclusive('\n')
        .take(error.line.saturating_sub(1))
        .map(str::len)
        .sum();
    let line = text[start..].lines().next().unwrap_or("");
    let at = start + line.find(error.word.as_str()).unwrap_or(0);
    Problem::error(codes::GCODE_NUMBER, error.to_string())
        .with_label((at, error.word.len()).into(), "not a number")
        .in_file(SourceFile {
            name: name.to_string(),
            text: Arc::from(text),
        })
}

/// The table: the parts found, the pauses, the voids, then per pose every goal computed beside
/// sliced, and the failures.
fn table(check: &SlicedCheck, project_name: &str, gcode_name: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{project_name}: checked against {gcode_name} ({} layers); angles in degrees, masses in grams",
        check.layers
    );
    for component in &check.components {
        let object = component
            .object
            .as_deref()
            .map_or("the only object".to_string(), |label| {
                format!("object `{label}`")
            });
        let [x, y, z] = component.centroid;
        let _ = writeln!(
            out,
            "\ncomponent \"{}\": {object}, moved on the bed by ({:+.2}, {:+.2})\n  sliced {:.2} \
             at ({x:.2}, {y:.2}, {z:.2}) in its rest frame, {} extrusions",
            component.component,
            component.shift[0],
            component.shift[1],
            component.mass,
            component.segments
        );
    }
    if !check.pauses.is_empty() {
        let _ = writeln!(out, "\npauses");
        for pause in &check.pauses {
            let what = match (&pause.planned, &pause.found) {
                (Some(planned), Some(found)) => format!(
                    "after layer {} (height {:.2}) \"{}\": found on line {}",
                    planned.layers_done,
                    planned.height,
                    planned.messages.join("\", \""),
                    found.line
                ),
                (Some(planned), None) => format!(
                    "after layer {} (height {:.2}) \"{}\": not found",
                    planned.layers_done,
                    planned.height,
                    planned.messages.join("\", \"")
                ),
                (None, Some(found)) => format!(
                    "after layer {} (line {}): not planned",
                    found.layers_done, found.line
                ),
                (None, None) => continue,
            };
            let verdict = if pause.problem.is_some() {
                "FAILS"
            } else {
                "ok"
            };
            let _ = writeln!(out, "  {what}   {verdict}");
        }
    }
    if !check.voids.is_empty() {
        let _ = writeln!(out, "\nvoids");
        for void in &check.voids {
            let closest = void.closest.map_or("nothing extruded".to_string(), |d| {
                format!("closest extrusion {d:.2}")
            });
            let state = if void.intrusions == 0 {
                "empty".to_string()
            } else {
                format!("{} extrusions inside", void.intrusions)
            };
            let _ = writeln!(
                out,
                "  capsule `{}`: {state} ({closest} from the axis, limit {:.2})",
                void.capsule, void.limit
            );
        }
    }
    for pose in &check.poses {
        let _ = writeln!(
            out,
            "\npose \"{}\": mass computed {:.2}, sliced {:.2}",
            pose.pose, pose.computed_mass, pose.sliced_mass
        );
        for goal in &pose.goals {
            let _ = writeln!(
                out,
                "  {:<10} {:<16} computed {:>7.2}   sliced {:>7.2}   {}",
                goal.kind,
                goal.quantity,
                goal.computed,
                goal.sliced,
                if goal.met { "met" } else { "NOT MET" }
            );
        }
    }
    let failures = check.failures();
    if failures.is_empty() {
        let _ = writeln!(
            out,
            "\nThe file is as planned and every goal is met with its mass."
        );
    } else {
        let _ = writeln!(
            out,
            "\n{} problem{}:",
            failures.len(),
            if failures.len() == 1 { "" } else { "s" }
        );
        for failure in failures {
            let _ = writeln!(out, "  - {failure}");
        }
    }
    out
}
