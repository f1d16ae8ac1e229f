//! `ballast pauses` end to end: a project's STL files, as `ballast build` writes them, sliced by
//! the installed PrusaSlicer and by CuraEngine (files that hold no pause), the plan's pauses put
//! in, and the result checked by `ballast verify --gcode`: every pause after its planned layer,
//! with the chosen command and the sheet's message, no void filled, every goal met with the
//! sliced mass. Each slicer's test is skipped, with a message, when the slicer is not on the
//! PATH (`.ci/run` installs both).

mod cli_support;
mod geometry_support;
mod print_support;

use std::fs;
use std::path::{Path, PathBuf};

use ballast::compile::compile;
use cli_support::{ballast, build_ok, stderr, stdout};
use geometry_support::{box_mesh, obj_text};
use print_support::{cura_available, cura_settings, slice_with, slice_with_cura, slicer_available};

/// The OBJ text of the box of `size` with its lowest corner at `origin`.
fn box_obj(origin: [f64; 3], size: [f64; 3]) -> String {
    let mut mesh = box_mesh(size[0], size[1], size[2]);
    for p in &mut mesh.positions {
        p.coords += nalgebra::Vector3::from(origin);
    }
    obj_text(&mesh)
}

/// The box with a level capsule void along x, standing, and on its end; built, so that its STL
/// file is in `build/box-stl/`.
fn box_project() -> (tempfile::TempDir, PathBuf) {
    let folder = tempfile::tempdir().unwrap();
    fs::write(
        folder.path().join("box.obj"),
        box_obj([0.0; 3], [40.0, 30.0, 20.0]),
    )
    .unwrap();
    let project = folder.path().join("box.kdl");
    fs::write(
        &project,
        "units mm\nup z\nmaterial \"PLA\" density=1.24\ninfill 0.15\n\
         component \"box\" mesh=\"box.obj\"\n\
         capsule \"keel\" component=\"box\" radius=4 {\n    from 10 15 8\n    to 30 15 12\n}\n\
         pose \"upright\" {\n    stand margin=2\n}\n\
         pose \"on its end\" {\n    rotate 0 90 0\n    stand margin=2\n}\n",
    )
    .unwrap();
    build_ok(&project);
    (folder, project)
}

/// The plan's pauses of the project at `path`: (layers done, resume height in mm, message).
fn planned_pauses(path: &Path) -> Vec<(usize, f64, String)> {
    let source = fs::read_to_string(path).unwrap();
    let compilation = compile(&source, path).expect("the project compiles");
    let mut pauses: Vec<(usize, f64, String)> = compilation
        .print_plan
        .components
        .iter()
        .flat_map(|c| &c.pauses)
        .map(|p| (p.layers_done, p.resume_height, p.message.clone()))
        .collect();
    pauses.sort_by_key(|p| p.0);
    pauses
}

/// The box project built, its one planned pause (layers done, resume height, message) and the
/// STL file its build wrote.
fn box_with_one_pause() -> (tempfile::TempDir, PathBuf, (usize, f64, String), PathBuf) {
    let (folder, project) = box_project();
    let planned = planned_pauses(&project);
    assert_eq!(planned.len(), 1, "{planned:?}");
    let stl = folder.path().join("build/box-stl/box.stl");
    (folder, project, planned[0].clone(), stl)
}

fn run(args: &[&str]) -> std::process::Output {
    let output = ballast(args);
    println!("{}{}", stdout(&output), stderr(&output));
    output
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Each line of `text` that is `command` (the pause), with the lines before it.
fn pause_blocks<'a>(text: &'a str, command: &str) -> Vec<Vec<&'a str>> {
    let lines: Vec<&str> = text.lines().collect();
    (0..lines.len())
        .filter(|&i| lines[i] == command)
        .map(|i| lines[i.saturating_sub(6)..=i].to_vec())
        .collect()
}

#[test]
fn prusaslicer_gcode_from_the_stl_gets_the_planned_pause() {
    if !slicer_available() {
        eprintln!("skipped: prusa-slicer is not on the PATH (apt-get install prusa-slicer)");
        return;
    }
    let (folder, project, (layers_done, resume, message), stl) = box_with_one_pause();
    let sliced = slice_with(&stl, &["--fill-density", "15%", "--gcode-label-objects"]);
    assert!(!sliced.contains("\nM601"), "PrusaSlicer pauses on its own");
    let input = stl.with_extension("gcode");
    let output = folder.path().join("paused.gcode");

    // Without the pauses the file is not as planned.
    let unpaused = run(&["verify", path(&project), "--gcode", path(&input)]);
    assert_eq!(unpaused.status.code(), Some(1));
    assert!(stdout(&unpaused).contains("not found"));

    let done = run(&[
        "pauses",
        path(&project),
        "--gcode",
        path(&input),
        "-o",
        path(&output),
    ]);
    assert_eq!(done.status.code(), Some(0), "{}", stderr(&done));
    assert!(stdout(&done).contains("1 of 1 planned pause put into box.gcode"));
    assert!(stdout(&done).contains("The file is as planned and every goal is met with its mass."));
    assert_eq!(
        fs::read_to_string(&input).unwrap(),
        sliced,
        "the input is left alone"
    );

    // The pause: the four lines right after the marker of the layer at the resume height, and
    // nothing else changed.
    let paused = fs::read_to_string(&output).unwrap();
    let blocks = pause_blocks(&paused, "M601");
    assert_eq!(blocks.len(), 1);
    let block = &blocks[0];
    assert_eq!(block[0], ";LAYER_CHANGE");
    let z: f64 = block[1].strip_prefix(";Z:").unwrap().parse().unwrap();
    assert!((z - resume).abs() < 1e-6, "{z} against {resume}");
    assert!(block[2].starts_with(";HEIGHT:"));
    assert_eq!(block[3], ";PAUSE_PRINT");
    assert!(block[4].starts_with(&format!("; ballast: after layer {layers_done} ")));
    assert_eq!(block[5], format!("M117 {message}"));
    let kept: Vec<&str> = paused
        .lines()
        .filter(|line| !block[3..].contains(line))
        .collect();
    assert_eq!(kept, sliced.lines().collect::<Vec<_>>());
    // The layers before it: as many `;LAYER_CHANGE` as the plan prints before the pause.
    let at = paused.find(";PAUSE_PRINT").unwrap();
    assert_eq!(
        paused[..at].matches(";LAYER_CHANGE").count(),
        layers_done + 1
    );

    let check = run(&["verify", path(&project), "--gcode", path(&output)]);
    assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));

    // Again, into the file itself: the pause is there already, nothing changes.
    let again = run(&[
        "pauses",
        path(&project),
        "--gcode",
        path(&output),
        "-o",
        path(&output),
    ]);
    assert_eq!(again.status.code(), Some(0));
    assert!(stdout(&again).contains("0 of 1 planned pause"));
    assert!(stdout(&again).contains("already in the file, kept"));
    assert_eq!(fs::read_to_string(&output).unwrap(), paused);
}

#[test]
fn cura_gcode_gets_the_planned_pause_with_the_chosen_command() {
    if !cura_available() {
        eprintln!("skipped: CuraEngine is not on the PATH (apt-get install cura-engine)");
        return;
    }
    let (folder, project, (layers_done, _, message), stl) = box_with_one_pause();
    let input = folder.path().join("box.gcode");
    let sliced = slice_with_cura(&[&stl], &cura_settings(0.15), &input);
    assert!(sliced.contains(";LAYER_COUNT:"));
    assert!(sliced.contains(&format!(";MESH:{}", stl.display())));
    let output = folder.path().join("paused.gcode");
    let done = run(&[
        "pauses",
        path(&project),
        "--gcode",
        path(&input),
        "-o",
        path(&output),
        "--pause-gcode",
        "M0",
    ]);
    assert_eq!(done.status.code(), Some(0), "{}", stderr(&done));
    assert!(stdout(&done).contains("(pause command `M0`)"));
    assert!(stdout(&done).contains("component \"box\": object `"));
    assert!(stdout(&done).contains("capsule `keel`: empty"));

    // Cura counts layers from 0: the layer after `layers_done` layers is `;LAYER:<layers_done>`.
    let paused = fs::read_to_string(&output).unwrap();
    let blocks = pause_blocks(&paused, "M0");
    assert_eq!(blocks.len(), 1);
    let block = &blocks[0];
    assert_eq!(block[2], format!(";LAYER:{layers_done}"));
    assert_eq!(block[3], ";PAUSE_PRINT");
    assert_eq!(block[5], format!("M117 {message}"));

    let check = run(&[
        "verify",
        path(&project),
        "--gcode",
        path(&output),
        "--pause-gcode",
        "M0",
    ]);
    assert_eq!(check.status.code(), Some(0), "{}", stderr(&check));
    // Checked for another command, the file has no pause.
    let other = run(&["verify", path(&project), "--gcode", path(&output)]);
    assert_eq!(other.status.code(), Some(1));

    // The same as JSON: where the pause went (kept, now that the file has it) and the check.
    let again = folder.path().join("again.gcode");
    let json = run(&[
        "pauses",
        path(&project),
        "--gcode",
        path(&output),
        "-o",
        path(&again),
        "--pause-gcode",
        "M0",
        "--json",
    ]);
    assert_eq!(json.status.code(), Some(0), "{}", stderr(&json));
    let report: serde_json::Value = serde_json::from_str(&stdout(&json)).unwrap();
    assert_eq!(report["pause_command"], "M0");
    let pauses = report["pauses"].as_array().unwrap();
    assert_eq!(pauses.len(), 1);
    assert_eq!(pauses[0]["kept"], true);
    assert_eq!(pauses[0]["pause"]["layers_done"], layers_done);
    assert_eq!(pauses[0]["pause"]["message"], message.as_str());
    assert_eq!(report["check"]["pauses"].as_array().unwrap().len(), 1);
    assert!(report["check"]["pauses"][0]["problem"].is_null());
    assert_eq!(fs::read(&again).unwrap(), paused.as_bytes());
}

/// Two parts on one bed, sliced by CuraEngine together: each object is found by its `;MESH:`
/// label (the STL file's name), and the parts' pauses after one layer are one pause.
#[test]
fn cura_gcode_of_two_parts_matches_each_mesh_to_its_component() {
    if !cura_available() {
        eprintln!("skipped: CuraEngine is not on the PATH (apt-get install cura-engine)");
        return;
    }
    let folder = tempfile::tempdir().unwrap();
    fs::write(
        folder.path().join("long.obj"),
        box_obj([0.0; 3], [40.0, 30.0, 20.0]),
    )
    .unwrap();
    fs::write(
        folder.path().join("short.obj"),
        box_obj([50.0, 0.0, 0.0], [30.0, 30.0, 20.0]),
    )
    .unwrap();
    let project = folder.path().join("pair.kdl");
    fs::write(
        &project,
        "units mm\nup z\nmaterial \"PLA\" density=1.24\ninfill 0.15\n\
         component \"long\" mesh=\"long.obj\"\ncomponent \"short\" mesh=\"short.obj\"\n\
         capsule \"a\" component=\"long\" radius=4 {\n    from 10 15 8\n    to 30 15 12\n}\n\
         capsule \"b\" component=\"short\" radius=4 {\n    from 58 15 8\n    to 72 15 11\n}\n\
         pose \"upright\" {\n    stand margin=2\n}\n",
    )
    .unwrap();
    build_ok(&project);
    let planned = planned_pauses(&project);
    assert!(!planned.is_empty());
    let stls: Vec<PathBuf> = ["short", "long"]
        .iter()
        .map(|name| folder.path().join(format!("build/pair-stl/{name}.stl")))
        .collect();
    let input = folder.path().join("pair.gcode");
    let stl_paths: Vec<&Path> = stls.iter().map(PathBuf::as_path).collect();
    slice_with_cura(&stl_paths, &cura_settings(0.15), &input);
    let output = folder.path().join("paused.gcode");
    let done = run(&[
        "pauses",
        path(&project),
        "--gcode",
        path(&input),
        "-o",
        path(&output),
    ]);
    assert_eq!(done.status.code(), Some(0), "{}", stderr(&done));
    let printed = stdout(&done);
    for (name, file) in [("long", &stls[1]), ("short", &stls[0])] {
        assert!(
            printed.contains(&format!(
                "component \"{name}\": object `{}`",
                file.display()
            )),
            "{name}"
        );
    }
    let paused = fs::read_to_string(&output).unwrap();
    let blocks = pause_blocks(&paused, "M601");
    let mut layers: Vec<usize> = planned.iter().map(|p| p.0).collect();
    layers.dedup();
    assert_eq!(blocks.len(), layers.len());
    for (layers_done, block) in layers.iter().zip(&blocks) {
        assert_eq!(block[2], format!(";LAYER:{layers_done}"));
        for (_, _, message) in planned.iter().filter(|p| p.0 == *layers_done) {
            assert!(block[5].contains(message.as_str()), "{block:?}");
        }
    }
}

/// A file whose layers are not the plan's gets no pause and is not written.
#[test]
fn a_file_without_the_planned_layers_is_refused_and_nothing_is_written() {
    let (folder, project) = box_project();
    let input = folder.path().join("thin.gcode");
    // Layers of 1 mm topped half-way between whole millimetres: none within a quarter of the
    // plan's 0.3 mm layers of its resume height (on the grid 0.35 + 0.3 n, at .05, .35, .65 or
    // .95 mm).
    let mut text = String::from("M83\n");
    for layer in 0..40 {
        let z = f64::from(layer) + 0.5;
        text.push_str(&format!(
            ";LAYER_CHANGE\n;Z:{z}\nG1 Z{z}\nG1 X10 E1\nG1 X0 E1\n"
        ));
    }
    fs::write(&input, &text).unwrap();
    let output = folder.path().join("paused.gcode");
    let refused = run(&[
        "pauses",
        path(&project),
        "--gcode",
        path(&input),
        "-o",
        path(&output),
    ]);
    assert_eq!(refused.status.code(), Some(2));
    assert!(stderr(&refused).contains("ballast::pauses::no_layer"));
    assert!(stderr(&refused).contains("the file's layers are not the plan's"));
    assert!(!output.exists());
    // A pause command of two lines, or with a comment, is refused before anything is read.
    for bad in ["M0\nG28", "M0 ; wait"] {
        let refused = run(&[
            "pauses",
            path(&project),
            "--gcode",
            path(&input),
            "-o",
            path(&output),
            "--pause-gcode",
            bad,
        ]);
        assert_eq!(refused.status.code(), Some(2));
        assert!(!output.exists());
    }
}
