//! Meshes for print tests (capsules, bodies with capsule voids), binary STL, the example
//! projects, and the PrusaSlicer and CuraEngine command lines when they are installed.
#![allow(dead_code)]

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Command;

use ballast::compile::{bed_parts, bed_plate_pauses, print_settings, Compilation};
use ballast::emit::print_files::write_prusa_3mf;
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
        let mut reversed = void.clone();
        for triangle in &mut reversed.triangles {
            triangle.swap(1, 2);
        }
        mesh = with_shell(&mesh, &reversed);
    }
    mesh
}

/// `body` with `shell` added as one more shell, as it is (two overlapping shells, when they
/// cross).
pub fn with_shell(body: &TriMesh, shell: &TriMesh) -> TriMesh {
    let mut mesh = body.clone();
    let base = mesh.positions.len() as u32;
    mesh.positions.extend(&shell.positions);
    mesh.triangles
        .extend(shell.triangles.iter().map(|t| t.map(|i| base + i)));
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
    let density = format!("{}%", infill * 100.0);
    slice_with(
        input,
        &[
            "--fill-density",
            &density,
            "--skirts",
            "0",
            "--center",
            "100,100",
        ],
    )
}

/// Writes a PrusaSlicer project 3MF holding `objects` (name, mesh, placed on the bed as they
/// are) and pauses `(print_z, message)` in `Metadata/Prusa_Slicer_custom_gcode_per_print_z.xml`:
/// the pause runs before the first layer whose top is at `print_z`.
pub fn write_3mf(objects: &[(&str, &TriMesh)], pauses: &[(f64, &str)], path: &Path) {
    let mut resources = String::new();
    let mut items = String::new();
    for (index, (name, mesh)) in objects.iter().enumerate() {
        let id = index + 1;
        resources.push_str(&format!(
            "<object id=\"{id}\" name=\"{name}\" type=\"model\"><mesh><vertices>"
        ));
        for p in &mesh.positions {
            resources.push_str(&format!(
                "<vertex x=\"{}\" y=\"{}\" z=\"{}\"/>",
                p.x, p.y, p.z
            ));
        }
        resources.push_str("</vertices><triangles>");
        for [a, b, c] in &mesh.triangles {
            resources.push_str(&format!("<triangle v1=\"{a}\" v2=\"{b}\" v3=\"{c}\"/>"));
        }
        resources.push_str("</triangles></mesh></object>");
        items.push_str(&format!("<item objectid=\"{id}\" printable=\"1\"/>"));
    }
    let model = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"millimeter\" \
         xml:lang=\"en-US\" xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\" \
         xmlns:slic3rpe=\"http://schemas.slic3r.org/3mf/2017/06\"><metadata \
         name=\"Application\">PrusaSlicer-2.5.0</metadata><metadata \
         name=\"slic3rpe:Version3mf\">1</metadata><resources>{resources}</resources>\
         <build>{items}</build></model>"
    );
    let codes: String = pauses
        .iter()
        .map(|(z, message)| {
            format!(
                "<code print_z=\"{z}\" type=\"1\" extruder=\"1\" color=\"\" extra=\"{message}\" \
                 gcode=\"M601\"/>"
            )
        })
        .collect();
    let custom = format!(
        "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<custom_gcodes_per_print_z>{codes}<mode \
         value=\"SingleExtruder\"/></custom_gcodes_per_print_z>"
    );
    let types = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types \
        xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\"><Default \
        Extension=\"rels\" \
        ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/><Default \
        Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>\
        </Types>";
    let rels = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships \
        xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\"><Relationship \
        Target=\"/3D/3dmodel.model\" Id=\"rel0\" \
        Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>";
    let entries = [
        ("[Content_Types].xml", types.to_string()),
        ("_rels/.rels", rels.to_string()),
        ("3D/3dmodel.model", model),
        ("Metadata/Prusa_Slicer_custom_gcode_per_print_z.xml", custom),
    ];
    std::fs::write(path, stored_zip(&entries)).expect("write 3MF");
}

/// A zip archive of `entries` (name, text), stored without compression.
fn stored_zip(entries: &[(&str, String)]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut directory = Vec::new();
    for (name, text) in entries {
        let data = text.as_bytes();
        let crc = crc32(data);
        let offset = out.len() as u32;
        let size = data.len() as u32;
        let fields = |out: &mut Vec<u8>| {
            out.extend(20u16.to_le_bytes()); // version needed
            out.extend(0u16.to_le_bytes()); // flags
            out.extend(0u16.to_le_bytes()); // stored
            out.extend(0u32.to_le_bytes()); // time, date
            out.extend(crc.to_le_bytes());
            out.extend(size.to_le_bytes());
            out.extend(size.to_le_bytes());
            out.extend((name.len() as u16).to_le_bytes());
            out.extend(0u16.to_le_bytes()); // extra length
        };
        out.extend(0x0403_4b50u32.to_le_bytes());
        fields(&mut out);
        out.extend(name.as_bytes());
        out.extend(data);
        directory.extend(0x0201_4b50u32.to_le_bytes());
        directory.extend(20u16.to_le_bytes()); // version made by
        fields(&mut directory);
        // Comment length, disk number, internal and external attributes.
        directory.extend([0u8; 10]);
        directory.extend(offset.to_le_bytes());
        directory.extend(name.as_bytes());
    }
    let start = out.len() as u32;
    let length = directory.len() as u32;
    out.extend(directory);
    out.extend(0x0605_4b50u32.to_le_bytes());
    out.extend([0u8; 4]); // disk numbers
    out.extend((entries.len() as u16).to_le_bytes());
    out.extend((entries.len() as u16).to_le_bytes());
    out.extend(length.to_le_bytes());
    out.extend(start.to_le_bytes());
    out.extend(0u16.to_le_bytes());
    out
}

/// The CRC-32 (IEEE) of `data`.
fn crc32(data: &[u8]) -> u32 {
    let mut crc = !0u32;
    for byte in data {
        crc ^= u32::from(*byte);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// The G-code PrusaSlicer writes for the file `input` (an STL or a 3MF) at its defaults, with
/// the extra command-line arguments `args`.
pub fn slice_with(input: &Path, args: &[&str]) -> String {
    let output = input.with_extension("gcode");
    let status = Command::new("prusa-slicer")
        .arg("--export-gcode")
        .args(["--loglevel", "1"])
        .args(args)
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

/// Whether `CuraEngine` (Debian's `cura-engine`) runs here.
pub fn cura_available() -> bool {
    Command::new("CuraEngine")
        .arg("help")
        .output()
        .is_ok_and(|out| out.status.success())
}

/// The Cura settings ballast's print settings at their defaults come to (3 perimeters, 3 top
/// and 3 bottom solid layers, 0.45 mm extrusions, layers of 0.3 mm over a first of 0.35 mm),
/// with `infill` (a fraction) as Cura's grid infill: its lines `2 × width / infill` apart, as
/// Cura computes `infill_line_distance` from `infill_sparse_density`. Parts stay where the STL
/// files put them (`machine_center_is_zero`) on a 250 × 210 mm bed; a skirt, no support,
/// filament of 1.75 mm.
pub fn cura_settings(infill: f64) -> Vec<(String, String)> {
    let width = 0.45;
    let fixed = [
        ("layer_height", "0.3"),
        ("layer_height_0", "0.35"),
        ("line_width", "0.45"),
        ("wall_line_width_0", "0.45"),
        ("wall_line_width_x", "0.45"),
        ("skin_line_width", "0.45"),
        ("infill_line_width", "0.45"),
        ("skirt_brim_line_width", "0.45"),
        ("wall_line_count", "3"),
        ("top_layers", "3"),
        ("bottom_layers", "3"),
        ("initial_bottom_layers", "3"),
        ("infill_pattern", "grid"),
        ("material_diameter", "1.75"),
        ("machine_center_is_zero", "true"),
        ("machine_width", "250"),
        ("machine_depth", "210"),
        ("machine_height", "210"),
        ("adhesion_type", "skirt"),
        ("support_enable", "false"),
    ];
    let mut settings: Vec<(String, String)> = fixed
        .iter()
        .map(|(key, value)| (key.to_string(), value.to_string()))
        .collect();
    settings.push((
        "infill_sparse_density".to_string(),
        format!("{}", infill * 100.0),
    ));
    settings.push((
        "infill_line_distance".to_string(),
        format!("{}", 2.0 * width / infill),
    ));
    settings
}

/// The G-code CuraEngine writes for the STL files `inputs` (one mesh group, each file an object
/// that Cura labels `;MESH:<path>`), written to `output`: every setting from
/// `tests/data/cura/defaults.def.json` (Cura 4.13's printer and extruder settings at their
/// default values), then `settings`.
pub fn slice_with_cura(inputs: &[&Path], settings: &[(String, String)], output: &Path) -> String {
    let definition =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/cura/defaults.def.json");
    let mut command = Command::new("CuraEngine");
    command.arg("slice").arg("-j").arg(&definition);
    for (key, value) in settings {
        command.arg("-s").arg(format!("{key}={value}"));
    }
    for input in inputs {
        command.arg("-l").arg(input);
    }
    let status = command
        .arg("-o")
        .arg(output)
        .output()
        .expect("run CuraEngine");
    assert!(
        status.status.success(),
        "CuraEngine failed: {}",
        String::from_utf8_lossy(&status.stderr)
    );
    std::fs::read_to_string(output).expect("read G-code")
}

/// The G-code of the PrusaSlicer project `ballast build` writes for `compilation`, written as
/// `<name>.3mf` in `folder` and sliced there without rearranging the bed.
pub fn sliced_compilation(compilation: &Compilation, folder: &Path, name: &str) -> String {
    let parts = bed_parts(
        &compilation.project,
        &compilation.meshes,
        &compilation.design,
        &compilation.print_plan,
    );
    let settings = print_settings(&compilation.project, &compilation.design);
    let project = folder.join(format!("{name}.3mf"));
    let pauses = bed_plate_pauses(&compilation.project, &compilation.print_plan);
    std::fs::write(
        &project,
        write_prusa_3mf(&parts, &pauses, &settings).unwrap(),
    )
    .unwrap();
    slice_with(&project, &["--dont-arrange"])
}

/// The example projects, in name order.
pub fn examples() -> Vec<PathBuf> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut projects: Vec<_> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| {
            path.extension().is_some_and(|e| e == "kdl")
                && !path.to_string_lossy().ends_with(".solution.kdl")
        })
        .collect();
    projects.sort();
    projects
}
