//! What the tests of the `ballast` binary share: running it, reading what it printed, and a
//! scratch project folder with copies of the example meshes.
#![allow(dead_code)]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the binary with `args`, plain text and without the disk cache, so no test writes into
/// the user's cache folder.
pub fn ballast(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ballast"))
        .args(args)
        .env("NO_COLOR", "1")
        .env("BALLAST_CACHE_DIR", "off")
        .output()
        .expect("the ballast binary runs")
}

/// `ballast build` of the project at `path`.
pub fn build(path: &Path) -> Output {
    ballast(&["build", path.to_str().expect("a UTF-8 path")])
}

/// `ballast build` of the project at `path`, which must succeed (exit status 0: every goal met);
/// what it printed on standard output.
pub fn build_ok(path: &Path) -> String {
    let output = build(path);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}{}",
        stdout(&output),
        stderr(&output)
    );
    stdout(&output)
}

/// What `output` printed on standard output.
pub fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// What `output` printed on standard error.
pub fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A project of the example mesh `hinged_arm.obj` in `meshes/`: its base and arm as two
/// components, a pose `out` that must stand and a pose `round`, the arm turned round, that asks
/// for `imbalance`.
pub const ARM: &str = r#"
component "base" mesh="meshes/hinged_arm.obj" object="base"
component "arm" mesh="meshes/hinged_arm.obj" object="arm"
pose "out" { stand }
pose "round" {
    component "arm" { pivot -22 0 20; rotate 0 0 180 }
    imbalance
}
"#;

/// The bundled examples' folder.
pub fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")
}

/// A fresh folder holding, in its subfolder `within` (`""` for the folder itself), copies of the
/// example meshes `meshes` in `meshes/`; the path of `model.kdl` there (not written).
pub fn scratch_folder(within: &str, meshes: &[&str]) -> (tempfile::TempDir, PathBuf) {
    let folder = tempfile::tempdir().unwrap();
    let root = folder.path().join(within);
    fs::create_dir_all(root.join("meshes")).unwrap();
    for name in meshes {
        fs::copy(
            examples().join("meshes").join(name),
            root.join("meshes").join(name),
        )
        .unwrap();
    }
    (folder, root.join("model.kdl"))
}
