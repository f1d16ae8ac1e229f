//! `ballast new MESH`: from a downloaded STL to a valid project in one command. The unit is
//! guessed from the size, the active pose is the most stable facet `ballast poses` lists, and
//! a mesh that cannot be used writes nothing.

use std::fs;
use std::path::Path;
use std::process::{Command, Output};

use ballast::geometry::{load_mesh, MeshSelector, TriMesh};

fn ballast(args: &[&str], folder: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ballast"))
        .args(args)
        .current_dir(folder)
        .env("BALLAST_CACHE_DIR", "off")
        .output()
        .unwrap()
}

fn t_shape() -> TriMesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes/t_shape.obj");
    load_mesh(&path, &MeshSelector::Whole).unwrap()
}

/// `mesh` as a binary STL, every coordinate times `scale`.
fn binary_stl(mesh: &TriMesh, scale: f64) -> Vec<u8> {
    let mut bytes = vec![0u8; 80];
    bytes.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for triangle in &mesh.triangles {
        bytes.extend_from_slice(&[0; 12]);
        for &i in triangle {
            for c in mesh.positions[i as usize].iter() {
                bytes.extend_from_slice(&((c * scale) as f32).to_le_bytes());
            }
        }
        bytes.extend_from_slice(&[0; 2]);
    }
    bytes
}

fn text(output: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

#[test]
fn a_stl_in_metres_becomes_a_project_resting_on_its_most_stable_facet() {
    let folder = tempfile::tempdir().unwrap();
    fs::write(folder.path().join("tee.stl"), binary_stl(&t_shape(), 1e-3)).unwrap();
    let made = ballast(&["new", "tee.stl"], folder.path());
    assert_eq!(made.status.code(), Some(0), "{}", text(&made));
    let project = fs::read_to_string(folder.path().join("tee.kdl")).unwrap();
    // 0.13 in its numbers: metres, a 130 mm T.
    assert!(
        project.contains("mesh=\"tee.stl\" mesh-units=m"),
        "{project}"
    );
    assert!(project.contains("130.0 × 20.0 × 40.0 mm"), "{project}");
    assert!(project.contains("\noptimize\n"), "{project}");

    let checked = ballast(&["check", "tee.kdl"], folder.path());
    assert_ne!(checked.status.code(), Some(2), "{}", text(&checked));
    // The T as the OBJ weighs it (PLA at 1.24 g/cm³, the default print).
    let obj_folder = tempfile::tempdir().unwrap();
    fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes/t_shape.obj"),
        obj_folder.path().join("tee.obj"),
    )
    .unwrap();
    let obj_made = ballast(&["new", "tee.obj"], obj_folder.path());
    assert_eq!(obj_made.status.code(), Some(0), "{}", text(&obj_made));
    let obj_checked = ballast(&["check", "tee.kdl"], obj_folder.path());
    let mass = |output: &Output| {
        let out = String::from_utf8_lossy(&output.stdout).into_owned();
        out.lines()
            .find(|line| line.trim_start().starts_with("mass "))
            .map(str::to_string)
            .unwrap_or_else(|| panic!("no mass line in {out}"))
    };
    assert_eq!(mass(&checked), mass(&obj_checked));

    // The active pose is the first facet `ballast poses` lists for the project.
    let poses = ballast(&["poses", "tee.kdl"], folder.path());
    let listed = String::from_utf8_lossy(&poses.stdout);
    let first = listed
        .lines()
        .find(|line| line.starts_with("pose \"facet 1\""))
        .unwrap_or_else(|| panic!("{listed}"));
    let down = first
        .split("down ")
        .nth(1)
        .and_then(|rest| rest.split(';').next())
        .unwrap();
    assert!(
        project.contains(&format!("pose \"facet 1\" {{\n    down {down} //")),
        "{down} in\n{project}"
    );
    // The other stable facets are there too, commented out.
    assert!(project.contains("// pose \"facet 2\""), "{project}");
}

#[test]
fn an_existing_project_is_kept_unless_forced() {
    let folder = tempfile::tempdir().unwrap();
    fs::write(folder.path().join("tee.stl"), binary_stl(&t_shape(), 1.0)).unwrap();
    fs::write(folder.path().join("tee.kdl"), "// mine\n").unwrap();
    let refused = ballast(&["new", "tee.stl"], folder.path());
    assert_eq!(refused.status.code(), Some(2), "{}", text(&refused));
    assert!(text(&refused).contains("--force"), "{}", text(&refused));
    assert_eq!(
        fs::read_to_string(folder.path().join("tee.kdl")).unwrap(),
        "// mine\n"
    );
    let forced = ballast(&["new", "tee.stl", "--force"], folder.path());
    assert_eq!(forced.status.code(), Some(0), "{}", text(&forced));
    let project = fs::read_to_string(folder.path().join("tee.kdl")).unwrap();
    // 130 in its numbers: millimetres, read as written.
    assert!(project.contains("mesh=\"tee.stl\"\n"), "{project}");
    let named = ballast(&["new", "tee.stl", "-o", "other.kdl"], folder.path());
    assert_eq!(named.status.code(), Some(0), "{}", text(&named));
    assert!(folder.path().join("other.kdl").exists());
}

#[test]
fn a_mesh_that_cannot_be_used_writes_nothing() {
    let folder = tempfile::tempdir().unwrap();
    let mut open = t_shape();
    open.triangles.pop();
    fs::write(folder.path().join("open.stl"), binary_stl(&open, 1.0)).unwrap();
    let refused = ballast(&["new", "open.stl"], folder.path());
    assert_eq!(refused.status.code(), Some(2), "{}", text(&refused));
    assert!(
        text(&refused).contains("ballast::mesh::open"),
        "{}",
        text(&refused)
    );
    assert!(!folder.path().join("open.kdl").exists());
    fs::write(folder.path().join("junk.stl"), b"not a mesh").unwrap();
    let junk = ballast(&["new", "junk.stl"], folder.path());
    assert_eq!(junk.status.code(), Some(2), "{}", text(&junk));
    assert!(!folder.path().join("junk.kdl").exists());
}

#[test]
fn what_the_mesh_check_says_of_a_usable_mesh_is_said_at_once() {
    let folder = tempfile::tempdir().unwrap();
    let mut t = t_shape();
    // A triangle an exporter left with two corners at one point.
    t.triangles.push([0, 0, 1]);
    fs::write(folder.path().join("tee.stl"), binary_stl(&t, 1.0)).unwrap();
    let made = ballast(&["new", "tee.stl"], folder.path());
    assert_eq!(made.status.code(), Some(0), "{}", text(&made));
    let stderr = String::from_utf8_lossy(&made.stderr);
    assert!(stderr.contains("ballast::mesh::collapsed"), "{stderr}");
    assert!(folder.path().join("tee.kdl").exists());
}
