//! A mesh comes in at the right size: `mesh-units`, `mesh-up` and `scale` on a component, and the
//! glTF specification's metres and +Y up for glTF files. Masses are checked against the closed
//! form of a box (density × width × depth × height), which shares nothing with the mesh code.

mod glb_support;

use std::fs;
use std::path::Path;
use std::process::Command;

use ballast::compile::{compile, Compilation};
use glb_support::glb;

/// The corners of the box `[0, size.x] × [0, size.y] × [0, size.z]`, vertex `i` taking x from bit
/// 0, y from bit 1 and z from bit 2 of `i`, and its 12 triangles counter-clockwise seen from
/// outside (indices from 0).
fn box_mesh(size: [f64; 3]) -> (Vec<[f64; 3]>, Vec<[u16; 3]>) {
    let corners = (0..8)
        .map(|i| {
            let pick = |bit: usize, axis: usize| if i & bit == 0 { 0.0 } else { size[axis] };
            [pick(1, 0), pick(2, 1), pick(4, 2)]
        })
        .collect();
    let triangles = vec![
        [0, 2, 3],
        [0, 3, 1], // z = 0
        [4, 5, 7],
        [4, 7, 6], // z = top
        [0, 1, 5],
        [0, 5, 4], // y = 0
        [2, 6, 7],
        [2, 7, 3], // y = top
        [0, 4, 6],
        [0, 6, 2], // x = 0
        [1, 3, 7],
        [1, 7, 5], // x = top
    ];
    (corners, triangles)
}

/// The box of `size` as OBJ text.
fn box_obj(size: [f64; 3]) -> String {
    let (corners, triangles) = box_mesh(size);
    let mut text = String::new();
    for [x, y, z] in corners {
        text += &format!("v {x} {y} {z}\n");
    }
    for [a, b, c] in triangles {
        text += &format!("f {} {} {}\n", a + 1, b + 1, c + 1);
    }
    text
}

/// The box `size` (metres, Blender's frame: +Z up) as Blender exports it to a GLB file: in metres,
/// each point `(x, y, z)` written as glTF's `(x, z, −y)`, +Y up.
fn blender_box_glb(size: [f64; 3]) -> Vec<u8> {
    let (corners, triangles) = box_mesh(size);
    let gltf: Vec<[f32; 3]> = corners
        .iter()
        .map(|&[x, y, z]| [x as f32, z as f32, -y as f32])
        .collect();
    let mut bin = Vec::new();
    for point in &gltf {
        for c in point {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    for index in triangles.iter().flatten() {
        bin.extend_from_slice(&index.to_le_bytes());
    }
    let positions = 12 * gltf.len();
    let bound =
        |pick: fn(f32, f32) -> f32, axis: usize| gltf.iter().map(|p| p[axis]).reduce(pick).unwrap();
    let min: Vec<f32> = (0..3).map(|axis| bound(f32::min, axis)).collect();
    let max: Vec<f32> = (0..3).map(|axis| bound(f32::max, axis)).collect();
    let json = serde_json::json!({
        "asset": {"version": "2.0", "generator": "Khronos glTF Blender I/O v3.4.50"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "Cube"}],
        "meshes": [{"name": "Cube", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": positions},
            {"buffer": 0, "byteOffset": positions, "byteLength": bin.len() - positions}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": gltf.len(), "type": "VEC3",
             "min": min, "max": max},
            {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}
        ]
    });
    glb(&json, bin)
}

/// A project in millimetres, +z up, of one component `component` (the text of its node), solid
/// uniform PLA, one pose without goals.
fn project(component: &str) -> String {
    format!(
        "units mm\nup z\nmaterial \"PLA\" density=1.25\nprint model=\"uniform\"\n{component}\npose \"p\"\n"
    )
}

fn compiled(folder: &Path, source: &str) -> Compilation {
    let path = folder.join("model.kdl");
    fs::write(&path, source).unwrap();
    compile(source, &path).unwrap_or_else(|problems| panic!("{problems:#?}"))
}

/// The rest-frame bounding box of the first component, `(min, max)`.
fn bounds(compilation: &Compilation) -> ([f64; 3], [f64; 3]) {
    let (lo, hi) = compilation.meshes[0].bounding_box().unwrap();
    (lo.coords.into(), hi.coords.into())
}

/// Equal to 1e-6 relative: mesh files hold single-precision coordinates (7 digits).
fn assert_close(actual: f64, expected: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= 1e-6 * expected.abs().max(1.0),
        "{what}: {actual} != {expected}"
    );
}

/// Closed form: a solid box of `size_mm` at 1.25 g/cm³.
fn box_grams(size_mm: [f64; 3]) -> f64 {
    1.25 * size_mm.iter().product::<f64>() / 1000.0
}

#[test]
fn a_metres_obj_scaled_into_millimetres() {
    let folder = tempfile::tempdir().unwrap();
    // A 40 × 20 × 60 mm box, written in metres as a scanner would.
    fs::write(folder.path().join("scan.obj"), box_obj([0.04, 0.02, 0.06])).unwrap();
    let scaled = compiled(
        folder.path(),
        &project("component \"scan\" mesh=\"scan.obj\" mesh-units=m"),
    );
    let expected = box_grams([40.0, 20.0, 60.0]);
    assert_close(scaled.poses[0].mass, expected, "mass");
    let (lo, hi) = bounds(&scaled);
    for (axis, size) in [40.0, 20.0, 60.0].into_iter().enumerate() {
        assert_close(lo[axis], 0.0, "min");
        assert_close(hi[axis], size, "max");
    }
    let centre = scaled.poses[0].centre_of_mass;
    for (axis, half) in [20.0, 10.0, 30.0].into_iter().enumerate() {
        assert_close(centre[axis], half, "centre of mass");
    }
    // Unscaled, OBJ stays in project units: the same file is a 0.04 mm speck.
    let unscaled = compiled(
        folder.path(),
        &project("component \"scan\" mesh=\"scan.obj\""),
    );
    let speck = unscaled.poses[0].mass;
    assert!(
        (speck / (expected * 1e-9) - 1.0).abs() < 1e-6,
        "unscaled mass {speck}"
    );
    // `scale` multiplies after the unit: at one half, an eighth of the mass.
    let half = compiled(
        folder.path(),
        &project("component \"scan\" mesh=\"scan.obj\" mesh-units=m scale=0.5"),
    );
    assert_close(half.poses[0].mass, expected / 8.0, "half-size mass");
    // A bare factor works too: metres to millimetres is 1000.
    let factor = compiled(
        folder.path(),
        &project("component \"scan\" mesh=\"scan.obj\" scale=1000"),
    );
    assert_close(factor.poses[0].mass, expected, "mass with scale=1000");
}

#[test]
fn a_blender_glb_in_metres_gives_the_right_mass_standing_as_in_blender() {
    let folder = tempfile::tempdir().unwrap();
    // In Blender: 40 mm along x, 20 along y, 60 up (z), its corner at the origin.
    fs::write(
        folder.path().join("figure.glb"),
        blender_box_glb([0.04, 0.02, 0.06]),
    )
    .unwrap();
    let compilation = compiled(
        folder.path(),
        &project("component \"figure\" mesh=\"figure.glb\""),
    );
    // f32 coordinates in the file: 1e-7 relative.
    let expected = box_grams([40.0, 20.0, 60.0]);
    let mass = compilation.poses[0].mass;
    assert!(
        (mass - expected).abs() < 1e-5 * expected,
        "{mass} g, expected {expected} g"
    );
    // Blender's frame, in millimetres: x, y, and the 60 mm side up.
    let (lo, hi) = bounds(&compilation);
    for axis in 0..3 {
        let size = [40.0, 20.0, 60.0][axis];
        assert!(lo[axis].abs() < 1e-5, "{lo:?}");
        assert!((hi[axis] - size).abs() < 1e-5, "{hi:?}");
    }
    let frame = &compilation.project.components[0].frame;
    assert_eq!(frame.factor(compilation.project.units), 1000.0);
}

#[test]
fn a_gltf_written_in_project_units_says_so() {
    let folder = tempfile::tempdir().unwrap();
    // A 40 × 60 × 20 box exported with +Y up but in millimetres, against the specification:
    // the file spans x 0..40, y 0..20, z −60..0.
    let glb = blender_box_glb([40.0, 60.0, 20.0]);
    fs::write(folder.path().join("part.glb"), &glb).unwrap();
    let compilation = compiled(
        folder.path(),
        &project("component \"part\" mesh=\"part.glb\" mesh-units=mm"),
    );
    // Read as millimetres with +Y up: turned back into Blender's frame, unscaled.
    let (lo, hi) = bounds(&compilation);
    assert_eq!((lo, hi), ([0.0; 3], [40.0, 60.0, 20.0]));
    assert_close(
        compilation.poses[0].mass,
        box_grams([40.0, 60.0, 20.0]),
        "mass",
    );
    // With `mesh-up=z` too, nothing is turned: the file's own axes.
    let as_written = compiled(
        folder.path(),
        &project("component \"part\" mesh=\"part.glb\" mesh-units=mm mesh-up=z"),
    );
    let (lo, hi) = bounds(&as_written);
    assert_eq!((lo, hi), ([0.0, 0.0, -60.0], [40.0, 20.0, 0.0]));
}

#[test]
fn check_prints_how_each_mesh_was_read() {
    let folder = tempfile::tempdir().unwrap();
    fs::write(
        folder.path().join("figure.glb"),
        blender_box_glb([0.04, 0.02, 0.06]),
    )
    .unwrap();
    fs::write(folder.path().join("scan.obj"), box_obj([4.0, 2.0, 6.0])).unwrap();
    let path = folder.path().join("model.kdl");
    fs::write(
        &path,
        "units mm\ncomponent \"figure\" mesh=\"figure.glb\"\n\
         component \"scan\" mesh=\"scan.obj\" mesh-units=cm scale=0.5\n\
         component \"plain\" mesh=\"scan.obj\"\npose \"p\"\n",
    )
    .unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_ballast"))
        .args(["check", path.to_str().unwrap()])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains(
            "  figure: figure.glb, in metres (glTF), +y up (glTF), × 1000 into millimetres, turned +y to +z; 40.00 × 20.00 × 60.00 mm\n"
        ),
        "{stdout}"
    );
    assert!(
        stdout.contains(
            "  scan: scan.obj, in centimetres, scale 0.5, × 5 into millimetres; 20.00 × 10.00 × 30.00 mm\n"
        ),
        "{stdout}"
    );
    assert!(
        stdout.contains(
            "  plain: scan.obj, in millimetres, used as written; 4.00 × 2.00 × 6.00 mm\n"
        ),
        "{stdout}"
    );
    let json = Command::new(env!("CARGO_BIN_EXE_ballast"))
        .args(["check", "--json", path.to_str().unwrap()])
        .output()
        .unwrap();
    let report: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let frame = &report["components"][0]["mesh_frame"];
    assert_eq!(frame["units"], "m");
    assert_eq!(frame["units_from"], "gltf");
    assert_eq!(frame["up"], "y");
    assert_eq!(frame["up_from"], "gltf");
    assert_eq!(frame["factor"], 1000.0);
    let frame = &report["components"][1]["mesh_frame"];
    assert_eq!(frame["units_from"], "written");
    assert_eq!(frame["up_from"], "project");
    assert_eq!(frame["scale"], 0.5);
    assert_eq!(frame["factor"], 5.0);
}
