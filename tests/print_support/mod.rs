//! Meshes for print tests (capsules, bodies with capsule voids), binary STL, and the
//! PrusaSlicer command line when it is installed.
#![allow(dead_code)]

use std::f64::consts::PI;
use std::path::Path;
use std::process::Command;

use ballast::geometry::TriMesh;
use nalgebra::{Point3, UnitQuaternion, Vector3};

/// A capsule around `from`-`to` of radius `r`, `segments` around the axis and `segments / 4`
/// bands per hemisphere, outward.
pub fn capsule_mesh(from: Point3<f64>, to: Point3<f64>, r: f64, segments: u32) -> TriMesh {
    let axis = to - from;
    let length = axis.norm();
    let rotation = UnitQuaternion::rotation_between(&Vector3::z(), &axis)
        .unwrap_or_else(|| UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI));
    let bands = (segments / 4).max(2);
    // Rings from the `to` pole (polar angle 0) to the `from` pole (π), the top half at z = length.
    let mut rings = Vec::new();
    for i in 1..=bands {
        rings.push((PI / 2.0 * f64::from(i) / f64::from(bands), length));
    }
    for i in 0..bands {
        rings.push((PI / 2.0 + PI / 2.0 * f64::from(i) / f64::from(bands), 0.0));
    }
    let mut positions = vec![Point3::new(0.0, 0.0, length + r)];
    for &(polar, z) in &rings {
        for s in 0..segments {
            let azimuth = 2.0 * PI * f64::from(s) / f64::from(segments);
            positions.push(Point3::new(
                r * polar.sin() * azimuth.cos(),
                r * polar.sin() * azimuth.sin(),
                z + r * polar.cos(),
            ));
        }
    }
    positions.push(Point3::new(0.0, 0.0, -r));
    let ring = |k: u32, s: u32| 1 + k * segments + s % segments;
    let last = positions.len() as u32 - 1;
    let mut triangles = Vec::new();
    for s in 0..segments {
        triangles.push([0, ring(0, s), ring(0, s + 1)]);
        let k = rings.len() as u32 - 1;
        triangles.push([last, ring(k, s + 1), ring(k, s)]);
    }
    for k in 0..rings.len() as u32 - 1 {
        for s in 0..segments {
            triangles.push([ring(k, s), ring(k + 1, s), ring(k + 1, s + 1)]);
            triangles.push([ring(k, s), ring(k + 1, s + 1), ring(k, s + 1)]);
        }
    }
    let positions = positions
        .into_iter()
        .map(|p| from + rotation * p.coords)
        .collect();
    TriMesh {
        positions,
        triangles,
    }
}

/// `body` with each of `voids` added as a reversed inner shell: a slicer reads the voids as holes.
pub fn with_voids(body: &TriMesh, voids: &[TriMesh]) -> TriMesh {
    let mut mesh = body.clone();
    for void in voids {
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(&void.positions);
        mesh.triangles.extend(
            void.triangles
                .iter()
                .map(|[a, b, c]| [base + a, base + c, base + b]),
        );
    }
    mesh
}

/// Writes `mesh` as a binary STL file.
pub fn write_stl(mesh: &TriMesh, path: &Path) {
    let mut bytes = vec![0u8; 80];
    bytes.extend((mesh.triangles.len() as u32).to_le_bytes());
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let normal = (b - a)
            .cross(&(c - a))
            .try_normalize(0.0)
            .unwrap_or_default();
        for v in [normal, a.coords, b.coords, c.coords] {
            for x in v.iter() {
                bytes.extend((*x as f32).to_le_bytes());
            }
        }
        bytes.extend([0u8, 0u8]);
    }
    std::fs::write(path, bytes).expect("write STL");
}

/// Whether `prusa-slicer` runs here.
pub fn slicer_available() -> bool {
    Command::new("prusa-slicer")
        .arg("--help")
        .output()
        .is_ok_and(|out| out.status.success())
}

/// The G-code PrusaSlicer writes for the STL `input` at its defaults (no skirt), infill
/// `infill` (a fraction), centred on (100, 100).
pub fn slice(input: &Path, infill: f64) -> String {
    let output = input.with_extension("gcode");
    let status = Command::new("prusa-slicer")
        .arg("--export-gcode")
        .arg("--fill-density")
        .arg(format!("{}%", infill * 100.0))
        .args(["--skirts", "0", "--center", "100,100", "--loglevel", "1"])
        .arg("-o")
        .arg(&output)
        .arg(input)
        .output()
        .expect("run prusa-slicer");
    assert!(
        status.status.success(),
        "prusa-slicer failed: {}",
        String::from_utf8_lossy(&status.stderr)
    );
    std::fs::read_to_string(&output).expect("read G-code")
}
