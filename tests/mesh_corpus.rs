//! The meshes people bring, from a mesh file to a build as a user goes: `ballast new MESH`, then
//! `check`, then `build` of the stand pose `ballast new` took from the resting facets (the
//! optimizer placing capsules for one broken Spot and the shared meshes; the bundled corpus is
//! built as it is, so the debug-build test stays quick). The corpus:
//! the bundled Spot, broken the ways downloaded meshes are (crossing shells, a punched hole,
//! doubled faces, a flipped patch, a zero-area sliver, inside out), the torus and the Poppy
//! humanoid's assembly (tests/data/corpus, credited in its README.md), the examples' fish and
//! hammer and the benchmarks' boat, and, with
//! `BALLAST_SHARED_CORPUS=1` and the folder there, every mesh in `../shared/meshes` beside the
//! checkout too (minutes in a release build). A repair that changes no solid (flipped, doubled,
//! inside-out, sliver) leaves the mass of the clean mesh; capping a small hole nearly so.

mod geometry_support;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use ballast::geometry::{load_mesh, MeshSelector, TriMesh};
use nalgebra::{Point3, Vector3};

fn ballast(args: &[&str], folder: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ballast"))
        .args(args)
        .current_dir(folder)
        .env("BALLAST_CACHE_DIR", "off")
        .output()
        .unwrap()
}

fn text(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr)
}

/// `mesh` as OBJ text, every coordinate times `scale`.
fn obj(mesh: &TriMesh, scale: f64) -> String {
    let mut out = String::new();
    for p in &mesh.positions {
        out += &format!("v {} {} {}\n", p.x * scale, p.y * scale, p.z * scale);
    }
    for [a, b, c] in &mesh.triangles {
        out += &format!("f {} {} {}\n", a + 1, b + 1, c + 1);
    }
    out
}

/// Spot (public domain), 1.8 units long, scaled by 40 to a 72 mm print.
fn spot() -> TriMesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes/spot.obj");
    load_mesh(&path, &MeshSelector::Whole).unwrap()
}

/// Spot's broken variants: name, mesh, the warning each repair gives, and whether the solid
/// is the clean one's. (The sliver's corners are on a line only up to rounding: it may be
/// warned of as zero-area, or be a valid, very thin triangle.)
fn variants() -> Vec<(&'static str, TriMesh, Option<&'static str>, bool)> {
    let clean = spot();
    let mut crossing = clean.clone();
    let first = crossing.positions.len() as u32;
    crossing.positions.extend(
        clean
            .positions
            .iter()
            .map(|p| Point3::from(p.coords * 0.5) + Vector3::new(0.0, 0.3, 0.3)),
    );
    crossing
        .triangles
        .extend(clean.triangles.iter().map(|t| t.map(|i| i + first)));
    let mut punched = clean.clone();
    punched.triangles.remove(100);
    let mut doubled = clean.clone();
    doubled.triangles.extend_from_within(200..210);
    let mut flipped = clean.clone();
    for t in &mut flipped.triangles[300..306] {
        t.swap(1, 2);
    }
    let mut sliver = clean.clone();
    let [a, b, c] = sliver.triangles[400];
    let m = sliver.positions.len() as u32;
    sliver.positions.push(nalgebra::center(
        &sliver.positions[a as usize],
        &sliver.positions[b as usize],
    ));
    sliver.triangles[400] = [a, m, c];
    sliver.triangles.extend([[m, b, c], [a, b, m]]);
    let mut inside_out = clean.clone();
    for t in &mut inside_out.triangles {
        t.swap(1, 2);
    }
    vec![
        ("crossing", crossing, Some("ballast::mesh::crossing"), false),
        ("punched", punched, Some("ballast::mesh::hole"), false),
        ("doubled", doubled, Some("ballast::mesh::repeated"), true),
        ("flipped", flipped, Some("ballast::mesh::flipped"), true),
        ("sliver", sliver, None, true),
        (
            "inside_out",
            inside_out,
            Some("ballast::mesh::inverted"),
            true,
        ),
    ]
}

/// Runs `ballast new` on `mesh` (a file in `folder`), asserting it wrote a project; returns the
/// project's path and what `new` said.
fn new_project(folder: &Path, mesh: &str) -> (PathBuf, String) {
    let output = ballast(&["new", mesh], folder);
    let said = text(&output);
    assert!(output.status.success(), "ballast new {mesh}: {said}");
    let stem = Path::new(mesh).file_stem().unwrap().to_str().unwrap();
    let project = folder.join(format!("{stem}.kdl"));
    assert!(project.is_file(), "{said}");
    (project, said)
}

/// The mass `ballast check` states for the project's first pose, grams.
fn checked_mass(folder: &Path, project: &Path) -> f64 {
    let output = ballast(&["check", project.to_str().unwrap()], folder);
    let said = text(&output);
    assert!(
        output.status.success(),
        "check {}: {said}",
        project.display()
    );
    said.lines()
        .find_map(|line| line.trim().strip_prefix("mass"))
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|number| number.parse().ok())
        .unwrap_or_else(|| panic!("no mass in: {said}"))
}

/// Builds the project, asserting every goal is met: with the optimizer placing capsules as
/// `ballast new` asks, or (`optimize` false, to keep a debug-build test quick) without it, the
/// goals judged for the model as it is.
fn build(folder: &Path, project: &Path, optimize: bool) {
    let source = fs::read_to_string(project).unwrap();
    assert!(source.contains("\noptimize\n"), "{source}");
    if !optimize {
        fs::write(project, source.replace("\noptimize\n", "\n")).unwrap();
    }
    let output = ballast(
        &["build", project.to_str().unwrap(), "--out-dir", "out"],
        folder,
    );
    let said = text(&output);
    assert!(
        output.status.success(),
        "build {}: {said}",
        project.display()
    );
    assert!(said.contains("1 of 1 goal met"), "{said}");
}

#[test]
fn broken_variants_of_spot_are_repaired_checked_and_built() {
    let folder = tempfile::tempdir().unwrap();
    fs::write(folder.path().join("spot.obj"), obj(&spot(), 40.0)).unwrap();
    let (clean_project, said) = new_project(folder.path(), "spot.obj");
    assert!(!said.contains("warning"), "{said}");
    let clean_mass = checked_mass(folder.path(), &clean_project);
    for (name, mesh, code, same_solid) in variants() {
        let file = format!("{name}.obj");
        fs::write(folder.path().join(&file), obj(&mesh, 40.0)).unwrap();
        let (project, said) = new_project(folder.path(), &file);
        match code {
            Some(code) => assert!(said.contains(code), "{name}: {said}"),
            None => assert!(
                !said.contains("warning") || said.contains("ballast::mesh::degenerate"),
                "{name}: {said}"
            ),
        }
        let mass = checked_mass(folder.path(), &project);
        if same_solid {
            assert_eq!(mass, clean_mass, "{name}");
        } else if name == "punched" {
            assert!(
                (mass - clean_mass).abs() <= 0.002 * clean_mass,
                "{name}: {mass}"
            );
        } else {
            // The half-size copy pushed into Spot adds less than its own volume (an eighth).
            assert!(
                mass > clean_mass && mass < clean_mass * 1.125,
                "{name}: {mass}"
            );
        }
    }
    // One of them all the way through a build: the one the most repairs touch.
    build(folder.path(), &folder.path().join("crossing.kdl"), true);
}

#[test]
fn the_corpus_meshes_check_and_build() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/corpus");
    let mut meshes: Vec<PathBuf> = fs::read_dir(&corpus)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "obj"))
        .collect();
    meshes.sort();
    assert!(meshes.len() >= 2, "{meshes:?}");
    // The other real meshes the repository holds, as a user would bring them: the examples'
    // fish and hammer, the benchmarks' boat.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    meshes.extend(
        [
            "examples/meshes/blub_fish.obj",
            "examples/meshes/hammer.obj",
            "benches/projects/meshes/boat.obj",
        ]
        .map(|name| root.join(name)),
    );
    let bundled = meshes.len();
    let shared = std::env::var_os("BALLAST_SHARED_CORPUS").is_some_and(|v| v == "1");
    match shared.then(|| geometry_support::shared_mesh("")).flatten() {
        Some(shared) => {
            let mut more: Vec<PathBuf> = fs::read_dir(&shared)
                .unwrap()
                .map(|entry| entry.unwrap().path())
                .filter(|path| path.extension().is_some_and(|e| e == "obj"))
                .collect();
            more.sort();
            meshes.extend(more);
        }
        None => {
            eprintln!("the bundled corpus only (BALLAST_SHARED_CORPUS=1 adds ../shared/meshes)")
        }
    }
    for (index, mesh) in meshes.into_iter().enumerate() {
        let folder = tempfile::tempdir().unwrap();
        let name = mesh.file_name().unwrap().to_str().unwrap().to_string();
        fs::copy(&mesh, folder.path().join(&name)).unwrap();
        let (project, _) = new_project(folder.path(), &name);
        // The unit guess (from the size alone) is stated; a print is meant to be held in a
        // hand: 40 to 250 mm along its longest side, as a user would set it.
        let source = fs::read_to_string(&project).unwrap();
        let extent = source
            .lines()
            .find_map(|line| line.split("Its largest extent is ").nth(1))
            .and_then(|rest| rest.split(' ').next())
            .and_then(|number| number.parse::<f64>().ok());
        if let Some(extent) = extent {
            let scale = (120.0 / extent).clamp(1e-6, 1e6);
            let fixed = source
                .lines()
                .map(|line| {
                    if line.starts_with("component ") {
                        let kept: Vec<&str> = line
                            .split_whitespace()
                            .filter(|word| !word.starts_with("mesh-units="))
                            .collect();
                        format!("{} mesh-units=mm scale={scale}", kept.join(" "))
                    } else {
                        line.to_string()
                    }
                })
                .collect::<Vec<_>>()
                .join("\n");
            fs::write(&project, fixed + "\n").unwrap();
        }
        checked_mass(folder.path(), &project);
        build(folder.path(), &project, index >= bundled);
    }
}
