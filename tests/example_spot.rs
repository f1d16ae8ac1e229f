//! `examples/spot.kdl`, the six-pose showcase: it compiles, its capsules meet every
//! goal, and without them the solid cow fails the three goals the file's header says it
//! fails.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")
}

fn check_json(project: &Path) -> (Output, Value) {
    let output = Command::new(env!("CARGO_BIN_EXE_ballast"))
        .args(["check", "--json", project.to_str().unwrap()])
        .env("NO_COLOR", "1")
        .output()
        .expect("the ballast binary runs");
    let report = serde_json::from_slice(&output.stdout).unwrap_or_else(|e| {
        panic!(
            "no JSON report ({e}); stderr: {}",
            String::from_utf8_lossy(&output.stderr)
        )
    });
    (output, report)
}

/// The project's text with its `capsule` nodes left out.
fn without_capsules(text: &str) -> String {
    let mut kept = String::new();
    let mut in_capsule = false;
    for line in text.lines() {
        if line.starts_with("capsule ") {
            in_capsule = true;
        }
        if !in_capsule {
            kept.push_str(line);
            kept.push('\n');
        }
        if in_capsule && line == "}" {
            in_capsule = false;
        }
    }
    kept
}

/// Each pose's name and whether its one goal is met, with the goal's kind.
fn verdicts(report: &Value) -> Vec<(String, String, bool)> {
    report["poses"]
        .as_array()
        .unwrap()
        .iter()
        .map(|pose| {
            let goals = pose["goals"].as_array().unwrap();
            assert_eq!(goals.len(), 1, "{pose}");
            (
                pose["pose"].as_str().unwrap().to_string(),
                goals[0]["kind"].as_str().unwrap().to_string(),
                goals[0]["met"].as_bool().unwrap(),
            )
        })
        .collect()
}

fn owned(rows: &[(&str, &str, bool)]) -> Vec<(String, String, bool)> {
    rows.iter()
        .map(|(pose, kind, met)| (pose.to_string(), kind.to_string(), *met))
        .collect()
}

#[test]
fn spot_compiles_and_its_capsules_meet_all_six_goals() {
    let (output, report) = check_json(&examples().join("spot.kdl"));
    assert_eq!(
        output.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    // No error and no warning: every capsule the optimizer placed takes its ball at a pause in
    // the part's print orientation.
    let stderr = String::from_utf8_lossy(&output.stderr);
    let codes: Vec<&str> = stderr
        .lines()
        .filter(|line| line.starts_with("ballast::"))
        .collect();
    assert!(codes.is_empty(), "{stderr}");
    // With stock balls the optimizer takes two capsules (two 9 mm balls).
    assert_eq!(report["capsules"].as_array().unwrap().len(), 2);
    assert_eq!(report["all_goals_met"], true);
    assert_eq!(
        verdicts(&report),
        owned(&[
            ("standing", "stand", true),
            ("rearing up", "stand", true),
            ("grazing", "stand", true),
            ("on its left side", "stand", true),
            ("on its back", "imbalance", true),
            ("hung level", "suspend", true),
        ])
    );
}

#[test]
fn the_solid_cow_fails_rearing_up_rolling_off_its_back_and_hanging_level() {
    let folder = tempfile::tempdir().unwrap();
    fs::create_dir(folder.path().join("meshes")).unwrap();
    fs::copy(
        examples().join("meshes/spot.obj"),
        folder.path().join("meshes/spot.obj"),
    )
    .unwrap();
    let text = fs::read_to_string(examples().join("spot.kdl")).unwrap();
    let solid = without_capsules(&text);
    assert!(
        !solid.lines().any(|line| line.starts_with("capsule ")),
        "{solid}"
    );
    let project = folder.path().join("spot.kdl");
    fs::write(&project, solid).unwrap();

    let (output, report) = check_json(&project);
    assert_eq!(
        output.status.code(),
        Some(1),
        "stderr: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(report["capsules"].as_array().unwrap().is_empty());
    assert_eq!(
        verdicts(&report),
        owned(&[
            ("standing", "stand", true),
            ("rearing up", "stand", false),
            ("grazing", "stand", true),
            ("on its left side", "stand", true),
            ("on its back", "imbalance", false),
            ("hung level", "suspend", false),
        ])
    );
    let goal = |pose: usize| &report["poses"][pose]["goals"][0];
    // It still stands on its hind legs and tail, but only just (3.9 degrees printed, 5 needed).
    let rearing = goal(1)["tilt_margin"].as_f64().unwrap();
    assert!((2.0..4.0).contains(&rearing), "{rearing}");
    // It stays on its back instead of rolling off, if only just (0.3 degrees printed, resting on
    // the three hull vertices that touch; a 0.05 mm contact tolerance counted six and said 3.2).
    let back = goal(4)["tilt_margin"].as_f64().unwrap();
    assert!((0.0..4.0).contains(&back), "{back}");
    assert_eq!(
        report["poses"][4]["support"]["contacts"]
            .as_array()
            .unwrap()
            .len(),
        3
    );
    // Hung from its back it tips head down, the string some 30 degrees off vertical.
    let angle = goal(5)["angle"].as_f64().unwrap();
    assert!(angle > 20.0, "{angle}");
}
