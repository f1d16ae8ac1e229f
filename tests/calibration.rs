//! The calibration file: the mass a real slicer deposits, measured from its G-code by
//! `ballast verify --gcode FILE --calibrate`, added to the mass model by every later build.
//! Closed loop against the installed PrusaSlicer: once calibrated, the computed mass and centre of
//! mass of every pose are the sliced file's for the design it was measured on. Then what must not
//! be applied: a correction measured under other print settings, for an unknown component, or a
//! file that does not read. The slicer tests are skipped when `prusa-slicer` is not on the PATH.

mod print_support;

use std::path::{Path, PathBuf};

use ballast::compile::{
    calibration_path, calibration_text, compile, Compilation, CALIBRATION_REFUSED,
    CALIBRATION_STALE, CALIBRATION_UNKNOWN, CALIBRATION_UNREADABLE,
};
use ballast::sliced::{measured_corrections, verify_gcode, SlicedOptions};
use print_support::{sliced_compilation, slicer_available};

/// The T example copied into `dir` (project, solution, mesh), its project path.
fn t_shape_in(dir: &Path) -> PathBuf {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    for file in ["t_shape.kdl", "t_shape.solution.kdl", "meshes/t_shape.obj"] {
        std::fs::copy(examples.join(file), dir.join(file)).unwrap();
    }
    // The copy starts uncalibrated, whatever the example holds.
    let _ = std::fs::remove_file(dir.join("t_shape.calibration.json"));
    dir.join("t_shape.kdl")
}

fn compiled(path: &Path) -> Compilation {
    compile(&std::fs::read_to_string(path).unwrap(), path)
        .unwrap_or_else(|problems| panic!("does not compile: {problems:#?}"))
}

/// Writes the calibration file of the project at `path` from `gcode`.
fn calibrate(path: &Path, compilation: &Compilation, gcode: &str) {
    let check = verify_gcode(
        compilation,
        &compilation.print_plan,
        gcode,
        &SlicedOptions::default(),
    )
    .unwrap();
    let corrections = measured_corrections(compilation, &check);
    let text = calibration_text(
        &compilation.project,
        &compilation.meshes,
        &compilation.orientations,
        &corrections,
        "sliced.gcode",
    );
    std::fs::write(calibration_path(path), text).unwrap();
}

#[test]
fn a_calibrated_project_has_the_sliced_mass_of_its_design() {
    if !slicer_available() {
        eprintln!("skipped: prusa-slicer is not on the PATH (apt-get install prusa-slicer)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = t_shape_in(dir.path());
    let before = compiled(&path);
    let gcode = sliced_compilation(&before, dir.path(), "sliced");
    let options = SlicedOptions::default();
    let unchecked = verify_gcode(&before, &before.print_plan, &gcode, &options).unwrap();
    // The T's plastic printed on its side is more than the model's (docs/physics.md, about 1 %
    // of the mass with its design's voids): the uncalibrated model is off by a gap seven orders
    // past the 1e-9 the calibrated one must meet below, so the loop has something to close.
    let pose = &unchecked.poses[0];
    assert!(
        (pose.sliced_mass - pose.computed_mass).abs() > 0.005 * pose.sliced_mass,
        "{} g sliced, {} g computed",
        pose.sliced_mass,
        pose.computed_mass
    );
    calibrate(&path, &before, &gcode);
    let after = compiled(&path);
    assert_eq!(
        after.design, before.design,
        "the solution file is read as it was"
    );
    assert!(after
        .warnings
        .iter()
        .all(|w| !w.code.starts_with("ballast::calibration")));
    let check = verify_gcode(&after, &after.print_plan, &gcode, &options).unwrap();
    for pose in &check.poses {
        assert!(
            (pose.sliced_mass - pose.computed_mass).abs() < 1e-9 * pose.sliced_mass,
            "{}: {} g sliced, {} g computed",
            pose.pose,
            pose.sliced_mass,
            pose.computed_mass
        );
        for axis in 0..3 {
            assert!(
                (pose.sliced_centre[axis] - pose.computed_centre[axis]).abs() < 1e-6,
                "{}: centre {:?} sliced, {:?} computed",
                pose.pose,
                pose.sliced_centre,
                pose.computed_centre
            );
        }
        for goal in &pose.goals {
            assert!(
                (goal.sliced - goal.computed).abs() < 1e-6,
                "{} {}: {} sliced, {} computed",
                pose.pose,
                goal.kind,
                goal.sliced,
                goal.computed
            );
        }
    }
    // Calibrating again from the same file changes nothing: the correction is the whole gap.
    let first = std::fs::read_to_string(calibration_path(&path)).unwrap();
    calibrate(&path, &after, &gcode);
    let second = std::fs::read_to_string(calibration_path(&path)).unwrap();
    assert_calibrations_agree(&first, &second);
}

/// Two calibration files with the same entries, numbers equal to 1e-9 of their size.
fn assert_calibrations_agree(first: &str, second: &str) {
    let first: serde_json::Value = serde_json::from_str(first).unwrap();
    let second: serde_json::Value = serde_json::from_str(second).unwrap();
    let numbers = |value: &serde_json::Value| -> Vec<f64> {
        value["components"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|entry| {
                let c = &entry["correction"];
                let mut n = vec![c["volume"].as_f64().unwrap()];
                n.extend(
                    c["moment"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|x| x.as_f64().unwrap()),
                );
                n
            })
            .collect()
    };
    for (a, b) in numbers(&first).iter().zip(numbers(&second)) {
        assert!((a - b).abs() <= 1e-9 * a.abs().max(1.0), "{a} then {b}");
    }
}

/// A calibration file for `c` that adds 1000 cubic millimetres to component `name`.
fn written(c: &Compilation, name: &str) -> String {
    let text = calibration_text(
        &c.project,
        &c.meshes,
        &c.orientations,
        &[ballast::geometry::PrintCorrection {
            volume: 1000.0,
            moment: [0.0, 0.0, 0.0],
        }],
        "made.gcode",
    );
    text.replace("\"T\"", &format!("\"{name}\""))
}

#[test]
fn a_correction_is_applied_only_where_it_was_measured() {
    let dir = tempfile::tempdir().unwrap();
    let path = t_shape_in(dir.path());
    let plain = compiled(&path);
    // Applied: 1000 mm³ of PLA more, 1.24 g in every pose.
    std::fs::write(calibration_path(&path), written(&plain, "T")).unwrap();
    let corrected = compiled(&path);
    let added = corrected.poses[0].mass - plain.poses[0].mass;
    assert!((added - 1.24).abs() < 1e-9, "{added} g added");
    // Measured under other print settings: left out, with a warning.
    let source = std::fs::read_to_string(&path)
        .unwrap()
        .replace("wall 1.2", "wall 1.2\nprint perimeters=2");
    let other = dir.path().join("other.kdl");
    std::fs::write(&other, &source).unwrap();
    std::fs::copy(
        dir.path().join("t_shape.solution.kdl"),
        dir.path().join("other.solution.kdl"),
    )
    .unwrap();
    let other_plain = compiled(&other);
    std::fs::write(calibration_path(&other), written(&plain, "T")).unwrap();
    let stale = compiled(&other);
    assert!(stale.warnings.iter().any(|w| w.code == CALIBRATION_STALE));
    assert_eq!(stale.poses[0].mass, other_plain.poses[0].mass);
    // A component the project does not have: left out, with a warning.
    std::fs::write(calibration_path(&path), written(&plain, "Bar")).unwrap();
    let unknown = compiled(&path);
    assert!(unknown
        .warnings
        .iter()
        .any(|w| w.code == CALIBRATION_UNKNOWN));
    assert_eq!(unknown.poses[0].mass, plain.poses[0].mass);
}

#[test]
fn a_refused_correction_is_left_out_of_the_designs_material_too() {
    // A correction that takes away more than the bare T's solid material but less than the
    // solid material of the T with its capsules cut (their perimeters and floors are solid):
    // refused for the bare print, so left out of the cut one as well.
    let dir = tempfile::tempdir().unwrap();
    let path = t_shape_in(dir.path());
    let plain = compiled(&path);
    let (bare, cut) = (plain.prints[0].solid.volume, plain.printed[0].solid.volume);
    assert!(
        cut > bare + 10.0,
        "the capsules add {} mm³ of solid",
        cut - bare
    );
    let volume = -(bare + cut) / 2.0;
    let text = written(&plain, "T").replace("\"volume\": 1000.0", &format!("\"volume\": {volume}"));
    assert!(text.contains(&format!("{volume}")));
    std::fs::write(calibration_path(&path), text).unwrap();
    let refused = compiled(&path);
    assert!(refused
        .warnings
        .iter()
        .any(|w| w.code == CALIBRATION_REFUSED));
    assert_eq!(refused.printed, plain.printed);
    assert_eq!(refused.corrections, plain.corrections);
    for (pose, before) in refused.poses.iter().zip(&plain.poses) {
        assert_eq!(pose.mass, before.mass, "pose {}", pose.pose);
    }
}

#[test]
fn a_calibration_file_that_does_not_read_is_a_warning_at_its_place_and_corrects_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = t_shape_in(dir.path());
    let plain = compiled(&path);
    let text = written(&plain, "T").replace("\"volume\": 1000.0", "\"volume\": \"much\"");
    std::fs::write(calibration_path(&path), &text).unwrap();
    let unreadable = compiled(&path);
    let problem = unreadable
        .warnings
        .iter()
        .find(|p| p.code == CALIBRATION_UNREADABLE)
        .unwrap_or_else(|| panic!("{:#?}", unreadable.warnings));
    let (span, _) = &problem.labels[0];
    let line = text[..span.offset()].lines().count();
    let at = text.lines().nth(line - 1).unwrap();
    assert!(at.contains("volume"), "points at {at:?}");
    assert!(problem.file.is_some());
    assert_eq!(unreadable.printed, plain.printed);
    // What a calibration of plastic that overflowed would hold, and a file that is no JSON at
    // all: never a project that does not read.
    for broken in [
        written(&plain, "T").replace("\"volume\": 1000.0", "\"volume\": null"),
        written(&plain, "T").replace("\"volume\": 1000.0", "\"volume\": 1e999"),
        "\u{0}\u{1}".to_owned(),
    ] {
        std::fs::write(calibration_path(&path), &broken).unwrap();
        let read = compiled(&path);
        assert!(read
            .warnings
            .iter()
            .any(|p| p.code == CALIBRATION_UNREADABLE));
        assert_eq!(read.printed, plain.printed);
    }
}

#[test]
fn verify_calibrate_writes_the_file_beside_the_project() {
    if !slicer_available() {
        eprintln!("skipped: prusa-slicer is not on the PATH (apt-get install prusa-slicer)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let path = t_shape_in(dir.path());
    let gcode = sliced_compilation(&compiled(&path), dir.path(), "sliced");
    let gcode_path = dir.path().join("sliced.gcode");
    std::fs::write(&gcode_path, gcode).unwrap();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_ballast"))
        .arg("verify")
        .arg(&path)
        .arg("--gcode")
        .arg(&gcode_path)
        .arg("--calibrate")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("wrote"), "{stderr}");
    let text = std::fs::read_to_string(calibration_path(&path)).unwrap();
    let file: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(file["components"][0]["name"], "T");
    assert_eq!(file["measured_from"], "sliced.gcode");
    // The next check reads it without a warning.
    let after = compiled(&path);
    assert!(after
        .warnings
        .iter()
        .all(|w| !w.code.starts_with("ballast::calibration")));
}

#[test]
fn names_in_a_calibration_file_cannot_drive_the_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let path = t_shape_in(dir.path());
    let plain = compiled(&path);
    // A terminal title set, a bell, a cursor move, a C1 control: printed as escapes.
    let name = "T\u{1b}]0;owned\u{7}\u{1b}[2J\u{9b}";
    let text = written(&plain, "T").replace("\"T\"", &serde_json::to_string(name).unwrap());
    std::fs::write(calibration_path(&path), &text).unwrap();
    let read = compiled(&path);
    assert!(read.warnings.iter().any(|w| w.code == CALIBRATION_UNKNOWN));
    let shown = ballast::diagnostic::render_plain(&read.warnings, "t_shape.kdl", "");
    assert!(shown.contains("T\\u{1b}]0;owned\\u{7}"), "{shown}");
    assert!(
        !shown.chars().any(|c| c.is_control() && c != '\n'),
        "{shown:?}"
    );
    // The file drawn where it does not read: its text too.
    std::fs::write(calibration_path(&path), "{\"calibration\": 1, \u{1b}[2J").unwrap();
    let broken = compiled(&path);
    let shown = ballast::diagnostic::render_plain(&broken.warnings, "t_shape.kdl", "");
    assert!(shown.contains("calibration file"), "{shown}");
    assert!(
        !shown.chars().any(|c| c.is_control() && c != '\n'),
        "{shown:?}"
    );
}
