//! `ballast verify --gcode FILE`: the sliced file checked against the design, printed as a
//! table (or JSON).

use std::fmt::Write;
use std::path::Path;
use std::sync::Arc;

use super::diagnostics::render_for_terminal;
use super::{compile_file, file_name, MessageFormat, EXIT_INVALID, EXIT_MET, EXIT_UNMET};
use crate::compile::{calibration_path, calibration_text, Compilation, CompileOptions, Workspace};
use crate::diagnostic::{printable, Problem, SourceFile, MAX_DRAWN_BYTES};
use crate::emit::write_atomic;
use crate::gcode::{GcodeError, GcodeErrorKind};
use crate::regular_file::read_limited;
use crate::sliced::{
    measured_corrections, verify_gcode, SlicedCheck, SlicedError, SlicedOptions, MAX_GCODE_BYTES,
};
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
    let shown_path = printable(&gcode.display().to_string()).into_owned();
    let Some(bytes) = read_gcode(gcode, &shown_path) else {
        return EXIT_INVALID;
    };
    // Text that is not UTF-8 (a label in another encoding) is read with its bad bytes
    // replaced: no number or command holds one.
    let text = String::from_utf8(bytes)
        .unwrap_or_else(|error| String::from_utf8_lossy(error.as_bytes()).into_owned());
    let Some(check) = check_gcode(&compilation, &text, &shown_path, sliced) else {
        return EXIT_INVALID;
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
        let no_shift = compilation.project.units.from_millimetres(NO_SHIFT_MM);
        print!(
            "{}",
            table(&check, &file_name(path), &file_name(gcode), no_shift)
        );
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

/// The bytes of the G-code file at `path` (shown as `shown_path`), within
/// [`MAX_GCODE_BYTES`]; `None`, said on standard error, when it cannot be read.
pub(super) fn read_gcode(path: &Path, shown_path: &str) -> Option<Vec<u8>> {
    match read_limited(path, MAX_GCODE_BYTES) {
        Ok(bytes) => Some(bytes),
        Err(error) => {
            eprintln!(
                "error: cannot read {shown_path}: {}",
                printable(&error.to_string())
            );
            if error.kind() == std::io::ErrorKind::FileTooLarge {
                eprintln!("  help: ballast reads G-code files of at most 1 GiB (docs/limits.md)");
            }
            None
        }
    }
}

/// The G-code `text` (of the file shown as `shown_path`) checked against `compilation`'s print
/// plan; `None`, said on standard error, when it cannot be checked at all.
pub(super) fn check_gcode(
    compilation: &Compilation,
    text: &str,
    shown_path: &str,
    sliced: &SlicedOptions,
) -> Option<SlicedCheck> {
    match verify_gcode(compilation, &compilation.print_plan, text, sliced) {
        Ok(check) => Some(check),
        Err(SlicedError::Gcode(error)) => {
            let problem = unreadable(&error, shown_path, text);
            eprint!("{}", render_for_terminal(&[problem], shown_path, ""));
            None
        }
        Err(error) => {
            eprintln!("error: {shown_path}: {}", printable(&error.to_string()));
            None
        }
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
        return Err(format!("no calibration written: {}", printable(mismatch)));
    }
    let corrections = measured_corrections(compilation, check);
    // The reader bounds every number, so this should not happen; no file of infinities either way.
    if let Some(index) = corrections.iter().position(|correction| {
        !(correction.volume.is_finite() && correction.moment.iter().all(|m| m.is_finite()))
    }) {
        return Err(format!(
            "no calibration written: component `{}`'s plastic in the G-code is not a finite amount",
            printable(compilation.project.component_name(index))
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
                printable(compilation.project.component_name(index)),
                correction.volume * grams
            )
        })
        .collect();
    eprintln!(
        "wrote {}: the mass model corrected by {} ({}); build again to design for it",
        printable(&target.display().to_string()),
        changes.join(", "),
        printable(&file_name(gcode))
    );
    Ok(())
}

/// The most lines before a G-code error that its drawing counts (as empty lines, so that the
/// line numbers drawn are the file's); past it, the error is given by its message alone.
const MAX_LINES_BEFORE_DRAWN: usize = 1 << 20;

/// The diagnostic for a G-code line that does not read, pointed at the word: drawn with the
/// line before and after it, each [`printable`], the lines above left empty (a few bytes each,
/// however long the file).
pub(super) fn unreadable(error: &GcodeError, name: &str, text: &str) -> Problem {
    let (code, label) = match error.kind {
        GcodeErrorKind::NotANumber => (codes::GCODE_NUMBER, "not a number"),
        GcodeErrorKind::Repeated => (codes::GCODE_REPEATED, "an axis given again"),
        GcodeErrorKind::OutOfRange | GcodeErrorKind::TooMuchFilament => {
            (codes::GCODE_RANGE, "out of range")
        }
        GcodeErrorKind::NotAnArc(_) => (codes::GCODE_ARC, "not an arc"),
        GcodeErrorKind::TooManyPauses => (codes::GCODE_PAUSES, "one pause too many"),
        GcodeErrorKind::TooLong => (codes::GCODE_TEXT, "too long"),
    };
    let problem = Problem::error(code, printable(&error.to_string()).into_owned());
    let first = error.line.saturating_sub(1).max(1);
    if first > MAX_LINES_BEFORE_DRAWN {
        return problem;
    }
    let mut shown = "\n".repeat(first - 1);
    let mut start = 0;
    let lines = text.split_inclusive('\n').enumerate();
    for (index, line) in lines.skip(first - 1).take(error.line + 2 - first) {
        if index + 1 == error.line {
            start = shown.len();
        }
        let body = line.strip_suffix('\n').unwrap_or(line);
        let body = body.strip_suffix('\r').unwrap_or(body);
        if body.len() > MAX_DRAWN_BYTES {
            // Too long to draw: its line and column are still given.
            let mut end = MAX_DRAWN_BYTES;
            while !body.is_char_boundary(end) {
                end -= 1;
            }
            shown.push_str(&printable(&body[..end]));
        } else {
            shown.push_str(&printable(body));
        }
        shown.push('\n');
    }
    let line = shown[start..].lines().next().unwrap_or("");
    let word = printable(error.word.strip_suffix('…').unwrap_or(&error.word));
    let (at, length) = match line.find(word.as_ref()) {
        Some(at) => (start + at, word.len()),
        None => (start, 0),
    };
    problem
        .with_label((at, length).into(), label)
        .in_file(SourceFile {
            name: name.to_string(),
            text: Arc::from(shown),
        })
}

/// A shift shorter than this, mm, is printed as none: the part is where planned.
pub(super) const NO_SHIFT_MM: f64 = 0.01;

/// The table: the parts found, the pauses, the voids, then per pose every goal computed beside
/// sliced, and the failures; a shift shorter than `no_shift` (project units) is printed as none.
pub(super) fn table(
    check: &SlicedCheck,
    project_name: &str,
    gcode_name: &str,
    no_shift: f64,
) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{}: checked against {} ({} layers); angles in degrees, masses in grams",
        printable(project_name),
        printable(gcode_name),
        check.layers
    );
    for component in &check.components {
        let object = component
            .object
            .as_deref()
            .map_or("the only object".to_string(), |label| {
                format!("object `{}`", printable(label))
            });
        let [x, y, z] = component.centroid;
        let [dx, dy] = component.shift;
        let moved = if component.doubt.is_some() {
            "its place on the bed not found (the plan's assumed)".to_string()
        } else if dx.hypot(dy) < no_shift {
            "where planned on the bed".to_string()
        } else {
            format!("moved on the bed by ({dx:+.2}, {dy:+.2})")
        };
        let _ = writeln!(
            out,
            "\ncomponent \"{}\": {object}, {moved} (outer perimeter fitted on {} layers, \
             residual {:.3})\n  sliced {:.2} at ({x:.2}, {y:.2}, {z:.2}) in its rest frame, {} \
             extrusions",
            printable(&component.component),
            component.fit.layers,
            component.fit.residual,
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
                    printable(&planned.messages.join("\", \"")),
                    found.line
                ),
                (Some(planned), None) => format!(
                    "after layer {} (height {:.2}) \"{}\": not found",
                    planned.layers_done,
                    planned.height,
                    printable(&planned.messages.join("\", \""))
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
                printable(&void.capsule),
                void.limit
            );
        }
    }
    for pose in &check.poses {
        let _ = writeln!(
            out,
            "\npose \"{}\": mass computed {:.2}, sliced {:.2}",
            printable(&pose.pose),
            pose.computed_mass,
            pose.sliced_mass
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
            let _ = writeln!(out, "  - {}", printable(&failure));
        }
    }
    out
}
