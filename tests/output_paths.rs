//! Where `ballast build` may write: never over a file it reads, never one file twice, and
//! outside the project's folder only with `--write-outside` (or into `--out-dir`).

mod cli_support;

use std::fs;
use std::path::{Path, PathBuf};

use cli_support::{ballast, stderr};

fn data(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// A project `model.kdl` in a fresh folder (inside `project/` of it, so `..` has somewhere to
/// go), with the T shape's mesh in `meshes/`.
fn project(text: &str) -> (tempfile::TempDir, PathBuf) {
    let (folder, path) = cli_support::scratch_folder("project", &["t_shape.obj"]);
    fs::write(&path, text).unwrap();
    (folder, path)
}

const T: &str = "component \"T\" mesh=\"meshes/t_shape.obj\"\npose \"up\" { stand }\n";

/// Builds `path` and asserts it was refused with `code`, the label `label` under the text
/// `pointed`, and nothing written into `build/`.
fn refused(path: &Path, extra: &[&str], code: &str, pointed: &str) -> String {
    let mut args = vec!["build", path.to_str().unwrap()];
    args.extend(extra);
    let output = ballast(&args);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(2), "stderr: {err}");
    assert!(err.contains(code), "{err}");
    assert!(err.contains(pointed), "the span under {pointed:?}: {err}");
    assert!(!path.parent().unwrap().join("build").exists(), "{err}");
    err
}

#[test]
fn an_output_that_is_the_project_or_a_mesh_is_refused_at_its_span() {
    let text =
        format!("{T}output {{\n    gltf \"model.kdl\"\n    report \"meshes/t_shape.obj\"\n}}\n");
    let (_folder, path) = project(&text);
    let mesh = path.parent().unwrap().join("meshes/t_shape.obj");
    let mesh_bytes = fs::read(&mesh).unwrap();
    let err = refused(
        &path,
        &[],
        "ballast::output::overwrites_input",
        "\"model.kdl\"",
    );
    assert!(err.contains("the `gltf` output"), "{err}");
    assert!(err.contains("the `report` output"), "{err}");
    assert!(err.contains("this output"), "{err}");
    assert_eq!(fs::read_to_string(&path).unwrap(), text);
    assert_eq!(fs::read(&mesh).unwrap(), mesh_bytes);
}

#[test]
fn an_output_that_is_a_calibration_file_is_refused_whether_or_not_it_exists() {
    // The project's own calibration file (not written yet), then another project's.
    for (name, exists) in [
        ("model.calibration.json", false),
        ("other.Calibration.json", true),
    ] {
        let text = format!("{T}output {{\n    report \"{name}\"\n}}\n");
        let (_folder, path) = project(&text);
        let calibration = path.parent().unwrap().join(name);
        if exists {
            fs::write(&calibration, "{}").unwrap();
        }
        let err = refused(&path, &[], "ballast::output::overwrites_input", name);
        assert!(err.contains("is a calibration file"), "{err}");
        assert_eq!(calibration.exists(), exists);
        if exists {
            assert_eq!(fs::read_to_string(&calibration).unwrap(), "{}");
        }
    }
}

#[test]
fn an_output_that_is_a_gltf_buffer_is_refused() {
    let (_folder, path) = project("");
    let root = path.parent().unwrap();
    // The test mesh with its buffer moved out of its data URI into `two_parts.bin`.
    let text = fs::read_to_string(data("tests/data/meshes/two_parts.gltf")).unwrap();
    let mut gltf: serde_json::Value = serde_json::from_str(&text).unwrap();
    let uri = gltf["buffers"][0]["uri"].as_str().unwrap().to_owned();
    let encoded = uri.split_once("base64,").unwrap().1;
    use base64::Engine;
    let bytes = base64::engine::general_purpose::STANDARD
        .decode(encoded)
        .unwrap();
    fs::write(root.join("two_parts.bin"), bytes).unwrap();
    gltf["buffers"][0]["uri"] = "two_parts.bin".into();
    fs::write(root.join("two_parts.gltf"), gltf.to_string()).unwrap();
    fs::write(
        &path,
        "units cm\ncomponent \"base\" mesh=\"two_parts.gltf\" node=\"base\"\n\
         pose \"rest\" { stand }\noutput { prusa \"two_parts.bin\"; }\n",
    )
    .unwrap();
    let buffer = fs::read(root.join("two_parts.bin")).unwrap();
    refused(
        &path,
        &[],
        "ballast::output::overwrites_input",
        "\"two_parts.bin\"",
    );
    assert_eq!(fs::read(root.join("two_parts.bin")).unwrap(), buffer);
}

#[test]
fn the_default_glb_does_not_overwrite_a_mesh_of_that_name() {
    // A first project writes a GLB; a second one, in another folder, reads it as its mesh from
    // `build/model.glb`, where its own default glTF output would go.
    let (_first, first) = project(T);
    let output = ballast(&["build", first.to_str().unwrap()]);
    assert_ne!(output.status.code(), Some(2), "stderr: {}", stderr(&output));
    let glb = fs::read(first.parent().unwrap().join("build/model.glb")).unwrap();

    let second = tempfile::tempdir().unwrap();
    fs::create_dir_all(second.path().join("build")).unwrap();
    let mesh = second.path().join("build/model.glb");
    fs::write(&mesh, &glb).unwrap();
    let path = second.path().join("model.kdl");
    fs::write(
        &path,
        "component \"T\" mesh=\"build/model.glb\"\npose \"up\" { stand }\n",
    )
    .unwrap();
    let output = ballast(&["build", path.to_str().unwrap()]);
    let err = stderr(&output);
    assert_eq!(output.status.code(), Some(2), "stderr: {err}");
    assert!(err.contains("ballast::output::overwrites_input"), "{err}");
    assert!(
        err.contains("the default `gltf` output is this file"),
        "{err}"
    );
    assert_eq!(fs::read(&mesh).unwrap(), glb);
    assert_eq!(
        fs::read_dir(second.path().join("build")).unwrap().count(),
        1
    );
}

#[test]
fn two_outputs_of_one_path_are_refused_before_optimizing() {
    // The report where the solution file goes: refused before the optimizer runs.
    let text = format!("optimize capsules=1\n{T}output {{ report \"model.solution.kdl\"; }}\n");
    let (_folder, path) = project(&text);
    let err = refused(
        &path,
        &[],
        "ballast::output::duplicate",
        "\"model.solution.kdl\"",
    );
    assert!(err.contains("the `report` and `solution` outputs"), "{err}");
    assert!(!path.parent().unwrap().join("model.solution.kdl").exists());
}

#[test]
fn outputs_outside_the_project_folder_need_write_outside() {
    let (folder, path) = project("");
    let outside = folder.path().join("outside.glb");
    let absolute = folder.path().join("elsewhere").join("model.report.json");
    let text = format!(
        "{T}output {{\n    gltf \"../outside.glb\"\n    report \"{}\"\n}}\n",
        absolute.display()
    );
    fs::write(&path, &text).unwrap();
    let err = refused(
        &path,
        &[],
        "ballast::output::outside_project",
        "\"../outside.glb\"",
    );
    assert!(err.contains("--write-outside"), "{err}");
    assert!(err.contains("the `report` output"), "{err}");
    assert!(!outside.exists() && !absolute.exists());

    let output = ballast(&["build", path.to_str().unwrap(), "--write-outside"]);
    assert_ne!(output.status.code(), Some(2), "stderr: {}", stderr(&output));
    assert!(outside.is_file() && absolute.is_file());

    // `--out-dir` names its folder itself: anywhere is accepted, the project's paths are not
    // looked at.
    let chosen = folder.path().join("chosen");
    let output = ballast(&[
        "build",
        path.to_str().unwrap(),
        "--out-dir",
        chosen.to_str().unwrap(),
    ]);
    assert_ne!(output.status.code(), Some(2), "stderr: {}", stderr(&output));
    assert!(chosen.join("outside.glb").is_file());
}
