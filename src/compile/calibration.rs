//! The calibration file, `<project>.calibration.json` beside the project: per component, what
//! a real slicer deposited beyond the mass model ([`PrintCorrection`]), measured by
//! `ballast verify --gcode FILE --calibrate` on a sliced print of the design. Every build reads
//! it and adds each component's correction to its print volumes, so the optimizer designs for
//! the mass the slicer deposits. A correction holds only for the mesh, print orientation and
//! print settings it was measured with: each entry carries their fingerprint, and an entry whose
//! fingerprint no longer matches is left out with a warning.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use miette::{Severity, SourceSpan};
use serde::{Deserialize, Serialize};

use crate::diagnostic::{Problem, SourceFile};
use crate::fabrication::Orientation;
use crate::geometry::{PrintCorrection, PrintVolumes, TriMesh, MODEL_REVISION};
use crate::optimize::content_hash;
use crate::spec::model::Project;
use crate::spec::read_source;

/// The calibration file cannot be read or is not one (a warning: the mass is the model's).
pub const CALIBRATION_UNREADABLE: &str = "ballast::calibration::unreadable";
/// An entry was measured on another mesh, print orientation or print settings.
pub const CALIBRATION_STALE: &str = "ballast::calibration::stale";
/// An entry names no component of the project.
pub const CALIBRATION_UNKNOWN: &str = "ballast::calibration::unknown_component";
/// An entry would take away more material than the component's solid part holds.
pub const CALIBRATION_REFUSED: &str = "ballast::calibration::refused";

/// What an unreadable calibration file means for the build, and how to mend it.
const LEFT_OUT: &str = "no correction is applied: the masses are the model's; write the file again with `ballast verify --gcode FILE --calibrate`, or delete it";

/// The version of the file's layout this build reads and writes.
const VERSION: u32 = 1;

/// The file as written.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CalibrationFile {
    /// [`VERSION`].
    calibration: u32,
    /// The G-code file it was measured from, for the reader.
    measured_from: String,
    /// One entry per component, in project order.
    components: Vec<Entry>,
}

/// One component's correction.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    /// The component's name.
    name: String,
    /// [`fingerprint`] of what it was measured on.
    print: String,
    /// Material to add: volume (cubic project units) and first moment (rest frame).
    correction: PrintCorrection,
}

/// Where the calibration file of the project at `project_path` is: beside it, named after it.
pub fn calibration_path(project_path: &Path) -> PathBuf {
    let stem = project_path
        .file_stem()
        .map_or_else(|| "project".into(), |s| s.to_string_lossy().into_owned());
    project_path.with_file_name(format!("{stem}.calibration.json"))
}

/// What a correction depends on for `mesh` printed as `orientation` under `project`'s print
/// settings: a BLAKE3 digest (16 hex digits) of the mesh content, the settings, the rotation
/// and the mass model's revision.
pub fn fingerprint(project: &Project, mesh: &TriMesh, orientation: &Orientation) -> String {
    fingerprint_under(MODEL_REVISION, project, mesh, orientation)
}

/// [`fingerprint`] as mass model revision `revision` computes it.
fn fingerprint_under(
    revision: u32,
    project: &Project,
    mesh: &TriMesh,
    orientation: &Orientation,
) -> String {
    let mut hasher = blake3::Hasher::new();
    hasher.update(&revision.to_le_bytes());
    hasher.update(&content_hash(mesh).to_le_bytes());
    hasher.update(format!("{:?}", project.print).as_bytes());
    hasher.update(format!("{:?}", orientation.to_print).as_bytes());
    hasher.finalize().to_hex()[..16].to_string()
}

/// The corrections of the calibration file at `path` for `project`'s components (zero where
/// it has none or its entry is stale), and the problems found, every one a warning: a
/// calibration never makes a project unreadable. An unreadable file (not one, not finite
/// numbers, too large) corrects nothing. No file: no correction, no problem.
pub fn read_calibration(
    project: &Project,
    path: &Path,
    meshes: &[TriMesh],
    orientations: &[Orientation],
) -> (Vec<PrintCorrection>, Vec<Problem>) {
    let mut corrections = vec![PrintCorrection::default(); meshes.len()];
    let text = match read_source(path, "calibration file") {
        Ok(Some(text)) => text,
        Ok(None) => return (corrections, Vec::new()),
        Err(problem) => {
            let mut problem = *problem;
            problem.code = CALIBRATION_UNREADABLE;
            problem.severity = Severity::Warning;
            return (corrections, vec![problem.with_help(LEFT_OUT)]);
        }
    };
    let file = SourceFile {
        name: path.display().to_string(),
        text: Arc::from(text.as_str()),
    };
    let parsed: CalibrationFile = match serde_json::from_str(&text) {
        Ok(parsed) => parsed,
        Err(error) => {
            let problem = Problem::warning(
                CALIBRATION_UNREADABLE,
                format!("the calibration file {} does not read: {error}", file.name),
            )
            .with_label(span_at(&text, error.line(), error.column()), "here")
            .with_help(LEFT_OUT)
            .in_file(file);
            return (corrections, vec![problem]);
        }
    };
    if parsed.calibration != VERSION {
        let problem = Problem::warning(
            CALIBRATION_UNREADABLE,
            format!(
                "the calibration file {} is of version {}; this ballast reads version {VERSION}",
                file.name, parsed.calibration
            ),
        )
        .with_help(LEFT_OUT)
        .in_file(file);
        return (corrections, vec![problem]);
    }
    let mut problems = Vec::new();
    for entry in &parsed.components {
        let Some(index) = (0..meshes.len()).find(|&i| project.component_name(i) == entry.name)
        else {
            problems.push(
                Problem::warning(
                    CALIBRATION_UNKNOWN,
                    format!(
                        "the calibration file corrects component `{}`, which the project does not have; its entry is left out",
                        entry.name
                    ),
                )
                .in_file(file.clone()),
            );
            continue;
        };
        if entry.print != fingerprint(project, &meshes[index], &orientations[index]) {
            problems.push(
                Problem::warning(
                    CALIBRATION_STALE,
                    format!(
                        "component `{}`'s mass correction was measured on another mesh, print orientation or print settings; it is left out, and the mass is the model's",
                        entry.name
                    ),
                )
                .with_help("slice the new print files and run `ballast verify --gcode FILE --calibrate` again")
                .in_file(file.clone()),
            );
            continue;
        }
        corrections[index] = entry.correction;
    }
    (corrections, problems)
}

/// `prints` with `corrections` applied, and a warning for each correction refused (one that
/// would leave a component's solid part without material: then its print is the model's).
pub fn corrected_prints(
    project: &Project,
    prints: &[PrintVolumes],
    corrections: &[PrintCorrection],
) -> Corrected {
    let mut refused = Vec::new();
    let (prints, applied) = prints
        .iter()
        .zip(corrections)
        .enumerate()
        .map(|(index, (print, correction))| {
            if *correction == PrintCorrection::default() {
                return (*print, *correction);
            }
            match correction.apply(print) {
                Some(corrected) => (corrected, *correction),
                None => {
                    refused.push(Problem::warning(
                        CALIBRATION_REFUSED,
                        format!(
                            "component `{}`'s mass correction takes away more than its solid material; it is left out",
                            project.component_name(index)
                        ),
                    ));
                    (*print, PrintCorrection::default())
                }
            }
        })
        .unzip();
    Corrected {
        prints,
        applied,
        refused,
    }
}

/// Each component's print volumes with the calibration's corrections added.
#[derive(Debug, Clone)]
pub struct Corrected {
    /// Per component, its print volumes, corrected where the correction was applied.
    pub prints: Vec<PrintVolumes>,
    /// Per component, the correction in `prints`: zero where there was none or it was refused.
    pub applied: Vec<PrintCorrection>,
    /// A warning per correction refused.
    pub refused: Vec<Problem>,
}

/// The calibration file's text for `corrections` (one per component, in project order),
/// measured from the G-code file named `measured_from`. The same corrections give the same
/// bytes.
pub fn calibration_text(
    project: &Project,
    meshes: &[TriMesh],
    orientations: &[Orientation],
    corrections: &[PrintCorrection],
    measured_from: &str,
) -> String {
    let file = CalibrationFile {
        calibration: VERSION,
        measured_from: measured_from.to_string(),
        components: corrections
            .iter()
            .enumerate()
            .map(|(index, correction)| Entry {
                name: project.component_name(index).to_string(),
                print: fingerprint(project, &meshes[index], &orientations[index]),
                correction: *correction,
            })
            .collect(),
    };
    let mut text = serde_json::to_string_pretty(&file).expect("plain numbers and strings encode");
    text.push('\n');
    text
}

/// The byte span of 1-based `line` and `column` in `text` (one character, or the end).
fn span_at(text: &str, line: usize, column: usize) -> SourceSpan {
    let start: usize = text
        .split_inclusive('\n')
        .take(line.saturating_sub(1))
        .map(str::len)
        .sum();
    let offset = (start + column.saturating_sub(1)).min(text.len());
    let length = usize::from(offset < text.len());
    SourceSpan::new(offset.into(), length)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compile::compile;

    #[test]
    fn a_correction_measured_against_another_model_revision_is_stale() {
        let path = Path::new("examples/articulated.kdl");
        let source = std::fs::read_to_string(path).unwrap();
        let c = compile(&source, path).unwrap();
        let correction = PrintCorrection {
            volume: 1000.0,
            moment: [0.0; 3],
        };
        let corrections = vec![correction; c.meshes.len()];
        let text = calibration_text(&c.project, &c.meshes, &c.orientations, &corrections, "x");
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("articulated.calibration.json");
        // Measured against this revision: every entry applies.
        std::fs::write(&file, &text).unwrap();
        let (read, problems) = read_calibration(&c.project, &file, &c.meshes, &c.orientations);
        assert!(problems.is_empty(), "{problems:?}");
        assert_eq!(read, corrections);
        // The same entries measured against the model before: all stale, none applied.
        let mut earlier = text.clone();
        for (index, mesh) in c.meshes.iter().enumerate() {
            let (now, then) = (
                fingerprint(&c.project, mesh, &c.orientations[index]),
                fingerprint_under(MODEL_REVISION - 1, &c.project, mesh, &c.orientations[index]),
            );
            assert_ne!(now, then);
            earlier = earlier.replace(&now, &then);
        }
        std::fs::write(&file, &earlier).unwrap();
        let (read, problems) = read_calibration(&c.project, &file, &c.meshes, &c.orientations);
        assert_eq!(read, vec![PrintCorrection::default(); c.meshes.len()]);
        assert_eq!(problems.len(), c.meshes.len());
        assert!(problems.iter().all(|p| p.code == CALIBRATION_STALE));
    }
}
