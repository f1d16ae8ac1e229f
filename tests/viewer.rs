//! Every example's glTF file as a real viewer loads it: three.js's GLTFLoader in Node
//! (`tests/viewer/check.mjs`), checking that each pose is a visible group, the body translucent,
//! the marks meshes, the extras flat scalars and the poses side by side. Skipped, with a message,
//! only when `node` is not installed; three.js comes from `tests/viewer`'s lockfile (`npm ci`).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use ballast::compile::compile;
use ballast::emit::write_glb;

fn viewer_folder() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/viewer")
}

#[test]
fn three_js_reads_every_example_right() {
    if Command::new("node").arg("--version").output().is_err() {
        eprintln!("skipped: `node` is not installed, so three.js cannot load the examples");
        return;
    }
    let folder = viewer_folder();
    if !folder.join("node_modules/three").is_dir() {
        let status = Command::new("npm")
            .args(["ci", "--silent", "--no-audit", "--no-fund", "--prefix"])
            .arg(&folder)
            .status()
            .expect("npm runs where node does");
        assert!(status.success(), "npm ci in tests/viewer failed");
    }

    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer");
    fs::create_dir_all(&out).unwrap();
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut projects: Vec<PathBuf> = fs::read_dir(&examples)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| {
            let name = path.file_name().unwrap().to_string_lossy();
            name.ends_with(".kdl") && !name.ends_with(".solution.kdl")
        })
        .collect();
    projects.sort();
    assert!(!projects.is_empty());
    let mut glbs = Vec::new();
    for project in &projects {
        let source = fs::read_to_string(project).unwrap();
        let compilation = compile(&source, project)
            .unwrap_or_else(|problems| panic!("{} is invalid: {problems:?}", project.display()));
        let glb = out.join(project.file_stem().unwrap()).with_extension("glb");
        fs::write(&glb, write_glb(&compilation.scene()).unwrap()).unwrap();
        glbs.push(glb);
    }

    let output = Command::new("node")
        .arg(folder.join("check.mjs"))
        .args(&glbs)
        .output()
        .unwrap();
    let report = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "three.js finds problems:\n{report}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // One line per file, each with at least one pose.
    assert_eq!(
        report
            .lines()
            .filter(|l| l.ends_with(" 0 problems"))
            .count(),
        glbs.len()
    );
    assert!(!report.contains(": 0 poses"), "{report}");
}
