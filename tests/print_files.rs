//! The print files of a block with two capsule voids: the PrusaSlicer 3MF read back with a zip
//! reader and an XML parser of their own, then sliced by the installed `prusa-slicer` (skipped,
//! with a message, when it is not on the PATH; `.ci/run` installs it): the parts stay where the
//! plan puts them, the layers are the plan's, every pause is in the G-code at its planned Z with
//! its message, and support, when turned on, never enters a void.

mod print_support;

use std::io::Read;
use std::path::Path;

use ballast::emit::print_files::{
    solid_mesh, write_prusa_3mf, write_stl, BedMesh, BedPart, BedPause, BedPlatePause, BedVoid,
    PrintSettings,
};
use nalgebra::Point3;
use print_support::slicer_available;
use quick_xml::events::Event;

/// A 40 × 30 × 20 mm box at x 10..50, y 20..50 (bed, mm).
fn block_surface() -> BedMesh {
    let (min, max) = (Point3::new(10.0, 20.0, 0.0), Point3::new(50.0, 50.0, 20.0));
    let positions = (0..8)
        .map(|i| {
            Point3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        })
        .collect();
    let triangles = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    BedMesh {
        positions,
        triangles,
    }
}

const SETTINGS: PrintSettings = PrintSettings {
    layer_height: 0.3,
    first_layer_height: 0.35,
    perimeters: 3,
    top_solid_layers: 3,
    bottom_solid_layers: 3,
    infill: 0.15,
    extrusion_width: 0.45,
    solid_infill_below_area: 70.0,
    bed: [250.0, 210.0],
};

/// The top of layer `n` (1-based) on the settings' grid.
fn layer_top(n: usize) -> f64 {
    SETTINGS.first_layer_height + (n as f64 - 1.0) * SETTINGS.layer_height
}

/// The block with a vertical capsule (`keel`, 7 mm ball) and a tilted one (`tip`, 5 mm), each
/// ball in at the first layer boundary above the top of its dropped ball.
fn block() -> BedPart {
    let voids = vec![
        BedVoid {
            name: "keel".to_string(),
            from: Point3::new(20.0, 35.0, 7.0),
            to: Point3::new(20.0, 35.0, 13.0),
            radius: 4.0,
            ball_diameter: 7.0,
        },
        BedVoid {
            name: "tip".to_string(),
            from: Point3::new(30.0, 27.0, 5.0),
            to: Point3::new(42.0, 29.0, 12.0),
            radius: 3.0,
            ball_diameter: 5.0,
        },
    ];
    let mut pauses: Vec<BedPause> = voids
        .iter()
        .enumerate()
        .map(|(i, void)| {
            let ball_top = void.ball_rest().z + void.ball_diameter / 2.0;
            let layers_done = (1..).find(|&n| layer_top(n) >= ball_top).unwrap();
            BedPause {
                layers_done,
                height: layer_top(layers_done),
                resume_height: layer_top(layers_done + 1),
                voids: vec![i],
                message: format!(
                    "Insert one {} mm steel ball into capsule `{}`",
                    void.ball_diameter, void.name
                ),
            }
        })
        .collect();
    pauses.sort_by(|a, b| a.height.total_cmp(&b.height));
    BedPart {
        name: "block".to_string(),
        surface: block_surface(),
        voids,
        pauses,
        orientation: "as modelled".to_string(),
    }
}

/// The PrusaSlicer project of a bed holding `part` alone: the bed pauses where the part does,
/// with its messages.
fn prusa_3mf(part: &BedPart) -> Vec<u8> {
    let pauses: Vec<BedPlatePause> = part
        .pauses
        .iter()
        .map(|pause| BedPlatePause {
            resume_height: pause.resume_height,
            message: pause.message.clone(),
        })
        .collect();
    write_prusa_3mf(std::slice::from_ref(part), &pauses, &SETTINGS).unwrap()
}

/// The entries of a zip archive, by name, in archive order.
fn entries(bytes: &[u8]) -> Vec<(String, String)> {
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes)).expect("a zip archive");
    (0..archive.len())
        .map(|i| {
            let mut entry = archive.by_index(i).unwrap();
            let mut text = String::new();
            entry.read_to_string(&mut text).expect("UTF-8 entry");
            (entry.name().to_string(), text)
        })
        .collect()
}

fn entry<'a>(entries: &'a [(String, String)], name: &str) -> &'a str {
    &entries
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no entry {name}"))
        .1
}

/// Every element named `tag` of `xml` with its attributes, in document order.
fn elements(xml: &str, tag: &str) -> Vec<Vec<(String, String)>> {
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut found = Vec::new();
    loop {
        match reader.read_event().expect("well-formed XML") {
            Event::Start(e) | Event::Empty(e) if e.name().as_ref() == tag.as_bytes() => {
                found.push(
                    e.attributes()
                        .map(|a| {
                            let a = a.unwrap();
                            (
                                String::from_utf8(a.key.as_ref().to_vec()).unwrap(),
                                a.normalized_value(quick_xml::XmlVersion::Implicit1_0)
                                    .unwrap()
                                    .into_owned(),
                            )
                        })
                        .collect(),
                );
            }
            Event::Eof => return found,
            _ => {}
        }
    }
}

fn attribute<'a>(element: &'a [(String, String)], key: &str) -> &'a str {
    &element
        .iter()
        .find(|(k, _)| k == key)
        .unwrap_or_else(|| panic!("no attribute {key} in {element:?}"))
        .1
}

/// The text of every `<metadata name=NAME>` of `xml`.
fn metadata_text(xml: &str, name: &str) -> Option<String> {
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut inside = false;
    loop {
        match reader.read_event().unwrap() {
            Event::Start(e) if e.name().as_ref() == b"metadata" => {
                inside = e.attributes().any(|a| {
                    let a = a.unwrap();
                    a.key.as_ref() == b"name" && a.value.as_ref() == name.as_bytes()
                });
            }
            Event::Text(t) if inside => return Some(t.decode().unwrap().into_owned()),
            Event::Eof => return None,
            _ => inside = false,
        }
    }
}

#[test]
fn the_prusa_3mf_reads_back_to_the_same_triangles_volumes_and_pauses() {
    let part = block();
    let bytes = prusa_3mf(&part);
    assert_eq!(bytes, prusa_3mf(&part), "deterministic");
    let entries = entries(&bytes);
    let names: Vec<&str> = entries.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "[Content_Types].xml",
            "_rels/.rels",
            "3D/3dmodel.model",
            "Metadata/Slic3r_PE.config",
            "Metadata/Slic3r_PE_model.config",
            "Metadata/Prusa_Slicer_custom_gcode_per_print_z.xml",
        ]
    );

    let model = entry(&entries, "3D/3dmodel.model");
    let application = metadata_text(model, "Application").expect("Application metadata");
    assert!(application.starts_with("PrusaSlicer-2."), "{application}");
    let objects = elements(model, "object");
    assert_eq!(objects.len(), 1);
    let triangles = elements(model, "triangle");
    let vertices = elements(model, "vertex");
    let solid = solid_mesh(&part);
    let stl = write_stl(&part);
    let stl_triangles = u32::from_le_bytes(stl[80..84].try_into().unwrap()) as usize;
    assert_eq!(solid.triangles.len(), stl_triangles);
    // Every triangle's vertex index is in range.
    for t in &triangles {
        for key in ["v1", "v2", "v3"] {
            assert!(attribute(t, key).parse::<usize>().unwrap() < vertices.len());
        }
    }

    // The volumes split the triangles: the solid (as in the STL), then one blocker per void.
    let config = entry(&entries, "Metadata/Slic3r_PE_model.config");
    let volumes = elements(config, "volume");
    assert_eq!(volumes.len(), 1 + part.voids.len());
    let mut next = 0;
    for volume in &volumes {
        assert_eq!(attribute(volume, "firstid").parse::<usize>().unwrap(), next);
        next = attribute(volume, "lastid").parse::<usize>().unwrap() + 1;
    }
    assert_eq!(next, triangles.len());
    assert_eq!(
        attribute(&volumes[0], "lastid").parse::<usize>().unwrap() + 1,
        stl_triangles
    );
    let types: Vec<String> = elements(config, "metadata")
        .iter()
        .filter(|m| attribute(m, "key") == "volume_type")
        .map(|m| attribute(m, "value").to_string())
        .collect();
    assert_eq!(types, ["ModelPart", "SupportBlocker", "SupportBlocker"]);
    let object_name = elements(config, "metadata")
        .into_iter()
        .find(|m| attribute(m, "type") == "object" && attribute(m, "key") == "name")
        .unwrap();
    assert_eq!(attribute(&object_name, "value"), "block");

    // The build item puts the object's origin at the centre of the block; vertices are
    // relative to it, so the block spans x 10..50, y 20..50 on the bed.
    let item = &elements(model, "item")[0];
    let transform: Vec<f64> = attribute(item, "transform")
        .split(' ')
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(
        transform,
        [1., 0., 0., 0., 1., 0., 0., 0., 1., 30., 35., 0.]
    );
    let xs: Vec<f64> = vertices
        .iter()
        .take(8)
        .map(|v| attribute(v, "x").parse::<f64>().unwrap() + transform[9])
        .collect();
    assert_eq!(xs.iter().copied().fold(f64::MAX, f64::min), 10.0);
    assert_eq!(xs.iter().copied().fold(f64::MIN, f64::max), 50.0);

    // The pauses, as planned, keyed by the top of the first layer after each.
    let codes = elements(
        entry(
            &entries,
            "Metadata/Prusa_Slicer_custom_gcode_per_print_z.xml",
        ),
        "code",
    );
    let read: Vec<(f64, String, String, String)> = codes
        .iter()
        .map(|c| {
            (
                attribute(c, "print_z").parse().unwrap(),
                attribute(c, "type").to_string(),
                attribute(c, "extra").to_string(),
                attribute(c, "gcode").to_string(),
            )
        })
        .collect();
    let planned: Vec<(f64, String, String, String)> = part
        .pauses
        .iter()
        .map(|p| {
            (
                (p.resume_height * 1e5).round() / 1e5,
                "1".to_string(),
                p.message.clone(),
                "M601".to_string(),
            )
        })
        .collect();
    assert_eq!(read, planned);

    let print = entry(&entries, "Metadata/Slic3r_PE.config");
    for line in [
        "; layer_height = 0.3",
        "; first_layer_height = 0.35",
        "; perimeters = 3",
        "; top_solid_layers = 3",
        "; bottom_solid_layers = 3",
        "; fill_density = 15%",
        "; support_material = 0",
        "; pause_print_gcode = M601",
    ] {
        assert!(print.lines().any(|l| l == line), "{line} missing:\n{print}");
    }
}

/// Slices `input` with the command line the docs give, plus `extra` options.
fn slice(input: &Path, extra: &[&str]) -> String {
    print_support::slice_with(input, &[&["--dont-arrange"], extra].concat())
}

/// One extruding move's end point (at mid-layer) and its feature type.
struct Extrusion {
    at: Point3<f64>,
    kind: String,
}

/// Every extruding G1 move of PrusaSlicer's G-code (absolute E, as it writes by default).
fn extrusions(gcode: &str) -> Vec<Extrusion> {
    let (mut x, mut y, mut e, mut z) = (0.0, 0.0, 0.0, 0.0);
    let mut kind = String::new();
    let mut found = Vec::new();
    for line in gcode.lines() {
        if let Some(t) = line.strip_prefix(";TYPE:") {
            kind = t.to_string();
        }
        if let Some(t) = line.strip_prefix(";Z:") {
            z = t.parse().unwrap();
        }
        if line.starts_with("G92") && line.contains("E0") {
            e = 0.0;
        }
        let Some(rest) = line.strip_prefix("G1 ") else {
            continue;
        };
        let mut new_e = e;
        for word in rest.split(';').next().unwrap().split_whitespace() {
            let value = || word[1..].parse::<f64>().unwrap();
            match word.as_bytes()[0] {
                b'X' => x = value(),
                b'Y' => y = value(),
                b'E' => new_e = value(),
                _ => {}
            }
        }
        if new_e > e + 1e-9 && (rest.contains('X') || rest.contains('Y')) {
            found.push(Extrusion {
                at: Point3::new(x, y, z - SETTINGS.layer_height / 2.0),
                kind: kind.clone(),
            });
        }
        e = new_e;
    }
    found
}

/// Distance from `p` to the axis segment of `void`.
fn axis_distance(void: &BedVoid, p: &Point3<f64>) -> f64 {
    let axis = void.to - void.from;
    let t = ((p - void.from).dot(&axis) / axis.norm_squared()).clamp(0.0, 1.0);
    (p - (void.from + axis * t)).norm()
}

#[test]
fn prusaslicer_slices_the_3mf_where_planned_with_every_pause_at_its_height() {
    if !slicer_available() {
        eprintln!("skipped: prusa-slicer is not on the PATH (apt-get install prusa-slicer)");
        return;
    }
    let part = block();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("block.3mf");
    std::fs::write(&path, prusa_3mf(&part)).unwrap();
    let gcode = slice(&path, &[]);

    // The layers are the plan's grid.
    let tops: Vec<f64> = gcode
        .lines()
        .filter_map(|l| l.strip_prefix(";Z:"))
        .map(|z| z.parse().unwrap())
        .collect();
    for (n, top) in tops.iter().enumerate() {
        assert!(
            (top - layer_top(n + 1)).abs() < 1e-6,
            "layer {} at {top}",
            n + 1
        );
    }
    assert!((tops.last().unwrap() - 19.85).abs() < 1e-6);

    // Each pause right after the layer change to its resume height: message, then M601.
    let lines: Vec<&str> = gcode.lines().collect();
    let pauses: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i] == ";PAUSE_PRINT")
        .collect();
    assert_eq!(pauses.len(), part.pauses.len());
    for (at, planned) in pauses.iter().zip(&part.pauses) {
        assert_eq!(lines[at + 1], format!("M117 {}", planned.message));
        assert_eq!(lines[at + 2], "M601");
        let z = lines[..*at]
            .iter()
            .rev()
            .find_map(|l| l.strip_prefix(";Z:"))
            .unwrap();
        assert!(
            (z.parse::<f64>().unwrap() - planned.resume_height).abs() < 1e-6,
            "pause before the layer at {z}, planned {}",
            planned.resume_height
        );
        let finished = tops.iter().filter(|&&t| t < planned.resume_height - 1e-6);
        assert_eq!(finished.count(), planned.layers_done);
    }

    // The part stays where the plan put it: its outer perimeter hugs x 10..50, y 20..50.
    let outer: Vec<Point3<f64>> = extrusions(&gcode)
        .into_iter()
        .filter(|e| e.kind == "External perimeter")
        .map(|e| e.at)
        .collect();
    let low = outer
        .iter()
        .fold(Point3::new(f64::MAX, f64::MAX, 0.0), |a, b| a.inf(b));
    let high = outer
        .iter()
        .fold(Point3::new(f64::MIN, f64::MIN, 0.0), |a, b| a.sup(b));
    let half = SETTINGS.extrusion_width / 2.0;
    for (got, want) in [
        (low.x, 10.0 + half),
        (low.y, 20.0 + half),
        (high.x, 50.0 - half),
        (high.y, 50.0 - half),
    ] {
        assert!(
            (got - want).abs() < 0.1,
            "outer perimeter at {got}, expected {want}"
        );
    }
    assert!(gcode.contains("; printing object block"));
    for line in [
        "; fill_density = 15%",
        "; perimeters = 3",
        "; support_material = 0",
    ] {
        assert!(gcode.contains(line), "{line}");
    }

    // No plastic inside a void.
    for e in extrusions(&gcode) {
        for void in &part.voids {
            assert!(
                axis_distance(void, &e.at) > void.radius - 0.1,
                "{} extruded inside `{}` at {:?}",
                e.kind,
                void.name,
                e.at
            );
        }
    }
}

#[test]
fn support_turned_on_stays_out_of_the_voids_by_the_blockers() {
    if !slicer_available() {
        eprintln!("skipped: prusa-slicer is not on the PATH (apt-get install prusa-slicer)");
        return;
    }
    let part = block();
    let dir = tempfile::tempdir().unwrap();
    let support = ["--support-material", "--support-material-threshold", "60"];

    // Without blockers (the bare STL) PrusaSlicer fills the voids' ceilings with support.
    let stl = dir.path().join("block.stl");
    std::fs::write(&stl, write_stl(&part)).unwrap();
    let bare = slice(&stl, &support);
    let bare_support = extrusions(&bare)
        .into_iter()
        .filter(|e| e.kind.starts_with("Support"))
        .count();
    assert!(
        bare_support > 0,
        "the bare STL gets support inside its voids"
    );

    let path = dir.path().join("block.3mf");
    std::fs::write(&path, prusa_3mf(&part)).unwrap();
    let gcode = slice(&path, &support);
    let supported = extrusions(&gcode)
        .into_iter()
        .filter(|e| e.kind.starts_with("Support"))
        .count();
    println!("support moves: bare STL {bare_support}, 3MF with blockers {supported}");
    assert_eq!(supported, 0);
}
