//! STL (binary and ASCII) and 3MF (objects, components, build transforms, units, the production
//! extension's paths) read as components give the mass properties of the OBJ of the same solid;
//! so does a 3MF that PrusaSlicer writes itself (skipped when `prusa-slicer` is not on the PATH).

use std::fs;
use std::io::Write;
use std::path::Path;
use std::process::Command;

use ballast::compile::compile;
use ballast::geometry::{load_mesh, mass_properties, LoadError, MeshSelector, TriMesh};
use nalgebra::{Point3, Rotation3, Vector3};

fn manifest() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The example T, in millimetres.
fn t_shape() -> TriMesh {
    load_mesh(
        &manifest().join("examples/meshes/t_shape.obj"),
        &MeshSelector::Whole,
    )
    .unwrap()
}

/// Corners of triangle `t` of `mesh`.
fn corners(mesh: &TriMesh, t: usize) -> [Point3<f64>; 3] {
    mesh.triangles[t].map(|i| mesh.positions[i as usize])
}

fn binary_stl(mesh: &TriMesh) -> Vec<u8> {
    // Many CAD programs begin the binary header with `solid`, as an ASCII file does.
    let mut bytes = b"solid exported by a CAD program".to_vec();
    bytes.resize(80, b' ');
    bytes.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for t in 0..mesh.triangles.len() {
        bytes.extend_from_slice(&[0; 12]);
        for corner in corners(mesh, t) {
            for c in corner.iter() {
                bytes.extend_from_slice(&(*c as f32).to_le_bytes());
            }
        }
        bytes.extend_from_slice(&[0; 2]);
    }
    bytes
}

fn ascii_stl(solids: &[(&str, &TriMesh)]) -> String {
    let mut text = String::new();
    for (name, mesh) in solids {
        text += &format!("solid {name}\n");
        for t in 0..mesh.triangles.len() {
            text += "  facet normal 0 0 0\n    outer loop\n";
            for p in corners(mesh, t) {
                text += &format!("      vertex {:e} {:e} {:e}\n", p.x, p.y, p.z);
            }
            text += "    endloop\n  endfacet\n";
        }
        text += &format!("endsolid {name}\n");
    }
    text
}

/// A `<mesh>` element of `mesh`, its coordinates times `scale`.
fn mesh_xml(mesh: &TriMesh, scale: f64) -> String {
    let mut xml = String::from("<mesh><vertices>");
    for p in &mesh.positions {
        let p = p * scale;
        xml += &format!("<vertex x=\"{:e}\" y=\"{:e}\" z=\"{:e}\"/>", p.x, p.y, p.z);
    }
    xml += "</vertices><triangles>";
    for [a, b, c] in &mesh.triangles {
        xml += &format!("<triangle v1=\"{a}\" v2=\"{b}\" v3=\"{c}\"/>");
    }
    xml + "</triangles></mesh>"
}

/// A model part: `unit`, the `resources` and `build` given as XML.
fn model(unit: &str, resources: &str, build: &str) -> String {
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"{unit}\" xml:lang=\"en-US\" \
         xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\" \
         xmlns:p=\"http://schemas.microsoft.com/3dmanufacturing/production/2015/06\">\
         <resources>{resources}</resources><build>{build}</build></model>"
    )
}

/// A 3MF archive of the given model parts (name in the archive, XML), the first the root.
fn three_mf(parts: &[(&str, String)]) -> Vec<u8> {
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    let mut file = |name: &str, text: &str| {
        zip.start_file(name, options).unwrap();
        zip.write_all(text.as_bytes()).unwrap();
    };
    file(
        "[Content_Types].xml",
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?><Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\"><Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/><Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/></Types>",
    );
    file(
        "_rels/.rels",
        &format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?><Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\"><Relationship Target=\"/{}\" Id=\"rel0\" Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>",
            parts[0].0
        ),
    );
    for (name, text) in parts {
        file(name, text);
    }
    zip.finish().unwrap().into_inner()
}

/// Writes `bytes` as `name` in `folder` and loads it.
fn load(folder: &Path, name: &str, bytes: &[u8], selector: &MeshSelector) -> TriMesh {
    let path = folder.join(name);
    fs::write(&path, bytes).unwrap();
    load_mesh(&path, selector).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn assert_same_solid(
    read: &TriMesh,
    expected: &TriMesh,
    moved: impl Fn(Point3<f64>) -> Point3<f64>,
) {
    let (a, b) = (mass_properties(read), mass_properties(expected));
    let volume = b.volume.abs();
    assert!(
        (a.volume - b.volume).abs() <= 1e-9 * volume,
        "volume {} != {}",
        a.volume,
        b.volume
    );
    let centroid = moved(b.centroid);
    assert!(
        (a.centroid - centroid).norm() <= 1e-9 * volume.cbrt(),
        "centroid {} != {}",
        a.centroid,
        centroid
    );
}

#[test]
fn binary_and_ascii_stl_give_the_obj_solid() {
    let folder = tempfile::tempdir().unwrap();
    let t = t_shape();
    let binary = load(
        folder.path(),
        "t.stl",
        &binary_stl(&t),
        &MeshSelector::Whole,
    );
    // The T's corners are whole millimetres: single precision holds them exactly.
    assert_same_solid(&binary, &t, |c| c);
    assert_eq!(binary.positions.len(), t.positions.len(), "corners welded");
    let ascii = ascii_stl(&[("T", &t)]);
    let read = load(
        folder.path(),
        "t2.STL",
        ascii.as_bytes(),
        &MeshSelector::Whole,
    );
    assert_same_solid(&read, &t, |c| c);
}

#[test]
fn an_ascii_stl_with_several_solids_selects_one_by_name() {
    let folder = tempfile::tempdir().unwrap();
    let t = t_shape();
    let far = TriMesh {
        positions: t
            .positions
            .iter()
            .map(|p| p + Vector3::new(500.0, 0.0, 0.0))
            .collect(),
        triangles: t.triangles.clone(),
    };
    let text = ascii_stl(&[("near", &t), ("far", &far)]);
    let selected = load(
        folder.path(),
        "two.stl",
        text.as_bytes(),
        &MeshSelector::ObjObject("far".into()),
    );
    assert_same_solid(&selected, &far, |c| c);
    let path = folder.path().join("two.stl");
    match load_mesh(&path, &MeshSelector::ObjObject("fra".into())) {
        Err(LoadError::UnknownPart { available, .. }) => assert_eq!(available, ["far", "near"]),
        other => panic!(
            "expected an unknown part, got {:?}",
            other.map(|m| m.positions.len())
        ),
    }
}

#[test]
fn a_3mf_in_metres_with_a_build_transform_reads_in_millimetres() {
    let folder = tempfile::tempdir().unwrap();
    let t = t_shape();
    // A quarter turn about z, then a move by (0.1, 0.2, 0.03) m, written as 3MF's row-vector
    // matrix: rows (0 1 0), (-1 0 0), (0 0 1), then the move.
    let part = model(
        "meter",
        &format!(
            "<object id=\"1\" type=\"model\" name=\"T\">{}</object>",
            mesh_xml(&t, 1e-3)
        ),
        "<item objectid=\"1\" transform=\"0 1 0 -1 0 0 0 0 1 0.1 0.2 0.03\"/>",
    );
    let read = load(
        folder.path(),
        "t.3mf",
        &three_mf(&[("3D/3dmodel.model", part)]),
        &MeshSelector::Whole,
    );
    let turn = Rotation3::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2);
    assert_same_solid(&read, &t, |c| turn * c + Vector3::new(100.0, 200.0, 30.0));
}

#[test]
fn a_multi_object_3mf_selects_a_build_item_by_its_object_name() {
    let folder = tempfile::tempdir().unwrap();
    let t = t_shape();
    let part = model(
        "millimeter",
        &format!(
            "<object id=\"1\" type=\"model\" name=\"left\">{0}</object>\
             <object id=\"2\" type=\"model\" name=\"right\">{0}</object>\
             <object id=\"3\" type=\"support\" name=\"brace\">{0}</object>",
            mesh_xml(&t, 1.0)
        ),
        "<item objectid=\"1\"/><item objectid=\"2\" transform=\"1 0 0 0 1 0 0 0 1 300 0 0\"/>\
         <item objectid=\"3\"/>",
    );
    let bytes = three_mf(&[("3D/3dmodel.model", part)]);
    let right = load(
        folder.path(),
        "two.3mf",
        &bytes,
        &MeshSelector::ObjObject("right".into()),
    );
    assert_same_solid(&right, &t, |c| c + Vector3::new(300.0, 0.0, 0.0));
    // The whole build: both T's, not the support object.
    let whole = load(folder.path(), "two.3mf", &bytes, &MeshSelector::Whole);
    let (one, both) = (mass_properties(&t), mass_properties(&whole));
    assert!((both.volume - 2.0 * one.volume).abs() <= 1e-9 * one.volume);
    match load_mesh(
        &folder.path().join("two.3mf"),
        &MeshSelector::ObjObject("middle".into()),
    ) {
        Err(LoadError::UnknownPart { available, .. }) => {
            assert_eq!(available, ["left", "right"])
        }
        other => panic!(
            "expected an unknown part, got {:?}",
            other.map(|m| m.positions.len())
        ),
    }
}

#[test]
fn components_in_other_model_parts_are_placed_as_bambu_studio_writes_them() {
    let folder = tempfile::tempdir().unwrap();
    let t = t_shape();
    // Bambu Studio and OrcaSlicer keep each object's mesh in its own part, referred to by a
    // component with the production extension's `p:path`.
    let object = model(
        "millimeter",
        &format!(
            "<object id=\"1\" type=\"model\">{}</object>",
            mesh_xml(&t, 1.0)
        ),
        "",
    );
    let root = model(
        "millimeter",
        "<object id=\"2\" type=\"model\" name=\"T\"><components>\
         <component p:path=\"/3D/Objects/object_1.model\" objectid=\"1\" \
         transform=\"1 0 0 0 1 0 0 0 1 0 0 5\"/></components></object>",
        "<item objectid=\"2\" transform=\"1 0 0 0 1 0 0 0 1 10 20 0\"/>",
    );
    let bytes = three_mf(&[
        ("3D/3dmodel.model", root),
        ("3D/Objects/object_1.model", object),
    ]);
    let read = load(
        folder.path(),
        "bambu.3mf",
        &bytes,
        &MeshSelector::ObjObject("T".into()),
    );
    assert_same_solid(&read, &t, |c| c + Vector3::new(10.0, 20.0, 5.0));
}

#[test]
fn broken_3mf_files_are_errors_not_panics() {
    let folder = tempfile::tempdir().unwrap();
    let t = t_shape();
    let path = folder.path().join("bad.3mf");
    let message = |bytes: &[u8]| {
        fs::write(&path, bytes).unwrap();
        load_mesh(&path, &MeshSelector::Whole)
            .err()
            .map(|e| e.to_string())
    };
    let not_zip = message(b"solid T\nendsolid T\n").unwrap();
    assert!(not_zip.contains("not a 3MF archive"), "{not_zip}");
    let no_model = message(&three_mf(&[("3D/other.model", String::new())])).unwrap();
    assert!(
        no_model.contains("not well-formed") || no_model.contains("has no"),
        "{no_model}"
    );
    let missing = model("millimeter", "", "<item objectid=\"7\"/>");
    let missing = message(&three_mf(&[("3D/3dmodel.model", missing)])).unwrap();
    assert!(missing.contains("no object 7"), "{missing}");
    let out_of_range = model(
        "millimeter",
        "<object id=\"1\"><mesh><vertices><vertex x=\"0\" y=\"0\" z=\"0\"/></vertices>\
         <triangles><triangle v1=\"0\" v2=\"0\" v3=\"3\"/></triangles></mesh></object>",
        "<item objectid=\"1\"/>",
    );
    let out_of_range = message(&three_mf(&[("3D/3dmodel.model", out_of_range)])).unwrap();
    assert!(out_of_range.contains("vertex 3 of 1"), "{out_of_range}");
    let cycle = model(
        "millimeter",
        "<object id=\"1\"><components><component objectid=\"1\"/></components></object>",
        "<item objectid=\"1\"/>",
    );
    let cycle = message(&three_mf(&[("3D/3dmodel.model", cycle)])).unwrap();
    assert!(cycle.contains("nest"), "{cycle}");
    let unit = model(
        "furlong",
        &format!("<object id=\"1\">{}</object>", mesh_xml(&t, 1.0)),
        "<item objectid=\"1\"/>",
    );
    let unit = message(&three_mf(&[("3D/3dmodel.model", unit)])).unwrap();
    assert!(unit.contains("unknown unit `furlong`"), "{unit}");
}

/// A project in millimetres of one component whose mesh is `mesh`, printed solid.
fn project(mesh: &str) -> String {
    format!(
        "units mm\nup z\nmaterial \"PLA\" density=1.25\nprint model=\"uniform\"\n\
         component \"T\" mesh=\"{mesh}\"\npose \"p\"\n"
    )
}

#[test]
fn stl_and_3mf_components_weigh_what_the_obj_weighs() {
    let folder = tempfile::tempdir().unwrap();
    let t = t_shape();
    fs::copy(
        manifest().join("examples/meshes/t_shape.obj"),
        folder.path().join("t.obj"),
    )
    .unwrap();
    fs::write(folder.path().join("t.stl"), binary_stl(&t)).unwrap();
    let part = model(
        "centimeter",
        &format!("<object id=\"1\" name=\"T\">{}</object>", mesh_xml(&t, 0.1)),
        "<item objectid=\"1\"/>",
    );
    fs::write(
        folder.path().join("t.3mf"),
        three_mf(&[("3D/3dmodel.model", part)]),
    )
    .unwrap();
    let mass = |mesh: &str| {
        let path = folder.path().join(format!("{mesh}.kdl"));
        let source = project(mesh);
        fs::write(&path, &source).unwrap();
        let compiled = compile(&source, &path).unwrap_or_else(|p| panic!("{mesh}: {p:#?}"));
        (
            compiled.poses[0].mass,
            compiled.project.components[0].frame.clone(),
        )
    };
    let (obj, _) = mass("t.obj");
    for mesh in ["t.stl", "t.3mf"] {
        let (grams, frame) = mass(mesh);
        assert!(
            (grams - obj).abs() <= 1e-6 * obj,
            "{mesh}: {grams} g, the OBJ {obj} g"
        );
        if mesh == "t.3mf" {
            assert_eq!(frame.units_from.keyword(), "3mf");
        }
    }
}

#[test]
fn a_3mf_that_prusaslicer_writes_reads_back_as_the_solid() {
    let has_slicer = Command::new("prusa-slicer")
        .arg("--help")
        .output()
        .is_ok_and(|out| out.status.success());
    if !has_slicer {
        eprintln!("skipped: prusa-slicer is not on the PATH (apt-get install prusa-slicer)");
        return;
    }
    let folder = tempfile::tempdir().unwrap();
    let obj = folder.path().join("t.obj");
    fs::copy(manifest().join("examples/meshes/t_shape.obj"), &obj).unwrap();
    let out = folder.path().join("t.3mf");
    let status = Command::new("prusa-slicer")
        .arg("--export-3mf")
        .arg("-o")
        .arg(&out)
        .arg(&obj)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let read = load_mesh(&out, &MeshSelector::Whole).unwrap();
    let (a, b) = (mass_properties(&read), mass_properties(&t_shape()));
    // PrusaSlicer moves the part onto its bed; the solid is the same.
    assert!(
        (a.volume - b.volume).abs() <= 1e-6 * b.volume,
        "volume {} != {}",
        a.volume,
        b.volume
    );
}

#[test]
fn mesh_units_on_a_3mf_is_an_error_naming_the_files_own_unit() {
    let folder = tempfile::tempdir().unwrap();
    let t = t_shape();
    let part = model(
        "millimeter",
        &format!("<object id=\"1\">{}</object>", mesh_xml(&t, 1.0)),
        "<item objectid=\"1\"/>",
    );
    fs::write(
        folder.path().join("t.3mf"),
        three_mf(&[("3D/3dmodel.model", part)]),
    )
    .unwrap();
    let source = project("t.3mf\" mesh-units=\"cm");
    let path = folder.path().join("t.kdl");
    fs::write(&path, &source).unwrap();
    let Err(problems) = compile(&source, &path) else {
        panic!("mesh-units on a 3MF compiled");
    };
    let problem = problems
        .iter()
        .find(|p| p.code == "ballast::mesh_units_stated")
        .unwrap_or_else(|| panic!("{problems:#?}"));
    assert!(problem.message.contains("3MF"), "{}", problem.message);
}

#[test]
fn triangles_with_two_corners_at_one_point_are_left_out_with_a_warning() {
    let folder = tempfile::tempdir().unwrap();
    let mut t = t_shape();
    let clean = t.clone();
    // Two triangles an exporter left behind: two corners at one point, once and twice over.
    t.triangles.insert(3, [0, 0, 1]);
    t.triangles.push([2, 2, 2]);
    fs::write(folder.path().join("t.stl"), binary_stl(&t)).unwrap();
    let loaded = ballast::geometry::load_mesh_with(
        &folder.path().join("t.stl"),
        &MeshSelector::Whole,
        &ballast::geometry::ReadPolicy::within(folder.path()),
    )
    .unwrap();
    assert_eq!(
        loaded.repairs.collapsed_triangles,
        [3, t.triangles.len() - 1]
    );
    assert_eq!(loaded.mesh.triangles.len(), clean.triangles.len());
    assert_same_solid(&loaded.mesh, &clean, |c| c);
    let source = project("t.stl");
    let path = folder.path().join("t.kdl");
    fs::write(&path, &source).unwrap();
    let compiled = compile(&source, &path).unwrap_or_else(|p| panic!("{p:#?}"));
    let warning = compiled
        .warnings
        .iter()
        .find(|w| w.code == "ballast::mesh::collapsed")
        .expect("a warning");
    assert!(
        warning.message.contains("2 triangles"),
        "{}",
        warning.message
    );
    assert!(
        warning.message.contains("triangle 4 of the file"),
        "{}",
        warning.message
    );
}

/// `mesh` as a PLY file: ASCII, or binary little-endian with float coordinates, with a normal
/// per vertex and a colour per face that the reader skips.
fn ply(mesh: &TriMesh, binary: bool) -> Vec<u8> {
    let format = if binary {
        "binary_little_endian"
    } else {
        "ascii"
    };
    let mut bytes = format!(
        "ply\nformat {format} 1.0\ncomment exported by a scanner\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\nproperty float nx\n\
         property float ny\nproperty float nz\nelement face {}\n\
         property list uchar int vertex_indices\nproperty uchar red\nend_header\n",
        mesh.positions.len(),
        mesh.triangles.len()
    )
    .into_bytes();
    for p in &mesh.positions {
        let values = [p.x as f32, p.y as f32, p.z as f32, 0.0, 0.0, 1.0];
        if binary {
            values
                .iter()
                .for_each(|v| bytes.extend_from_slice(&v.to_le_bytes()));
        } else {
            let line: Vec<String> = values.iter().map(|v| v.to_string()).collect();
            bytes.extend_from_slice(format!("{}\n", line.join(" ")).as_bytes());
        }
    }
    for t in &mesh.triangles {
        if binary {
            bytes.push(3);
            t.iter()
                .for_each(|&i| bytes.extend_from_slice(&(i as i32).to_le_bytes()));
            bytes.push(200);
        } else {
            bytes.extend_from_slice(format!("3 {} {} {} 200\n", t[0], t[1], t[2]).as_bytes());
        }
    }
    bytes
}

#[test]
fn ascii_and_binary_ply_give_the_obj_solid() {
    let folder = tempfile::tempdir().unwrap();
    let t = t_shape();
    for binary in [false, true] {
        let read = load(
            folder.path(),
            "t.ply",
            &ply(&t, binary),
            &MeshSelector::Whole,
        );
        assert_same_solid(&read, &t, |c| c);
    }
    let path = folder.path().join("t.ply");
    assert!(matches!(
        load_mesh(&path, &MeshSelector::ObjObject("T".into())),
        Err(LoadError::UnknownPart { .. })
    ));
}
