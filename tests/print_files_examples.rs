//! Every example's parts as printable STL: each component, laid on the bed by a plan made here,
//! is closed and consistently oriented with its voids as inner shells, and holds the body's
//! volume less its capsules'.

use std::collections::BTreeMap;
use std::path::Path;

use ballast::compile::{bed_parts, compile};
use ballast::emit::print_files::write_stl;
use ballast::fabrication::{CapsuleInsertion, ComponentPlan, OrientationChoice, Pause, PrintPlan};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// Each component turned so the project's up is +z, its lowest point on the bed, side by side
/// along x; one pause holding every capsule of the component.
fn plan(compilation: &ballast::compile::Compilation) -> PrintPlan {
    let up = compilation.project.up.unit_vector();
    let turn = UnitQuaternion::rotation_between(&up, &Vector3::z()).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    });
    let mut x = 0.0;
    let components = compilation
        .meshes
        .iter()
        .enumerate()
        .map(|(i, mesh)| {
            let turned: Vec<_> = mesh.positions.iter().map(|p| turn * p).collect();
            let low = turned.iter().fold(turned[0], |a, b| a.inf(b));
            let high = turned.iter().fold(turned[0], |a, b| a.sup(b));
            let to_bed = Isometry3::from_parts(Translation3::new(x - low.x, -low.y, -low.z), turn);
            x += high.x - low.x + 10.0;
            let capsules: Vec<usize> = (0..compilation.design.capsules.len())
                .filter(|&c| compilation.design.capsules[c].component == i)
                .collect();
            ComponentPlan {
                component: i,
                to_bed,
                down: -up,
                up,
                orientation: OrientationChoice::Declared,
                capsules: capsules
                    .iter()
                    .map(|&capsule| CapsuleInsertion {
                        capsule,
                        window: None,
                        pause: Some(0),
                        ceiling_bridge: 0.0,
                    })
                    .collect(),
                pauses: vec![Pause {
                    layers_done: 1,
                    height: 0.35,
                    resume_height: 0.65,
                    capsules: capsules.clone(),
                    message: "all".to_string(),
                }],
            }
        })
        .collect();
    PrintPlan {
        first_layer_height: 0.35,
        layer_height: 0.3,
        pause_clearance: 0.2,
        components,
    }
}

#[test]
fn every_examples_stl_is_closed_oriented_and_holds_the_body_less_its_voids() {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut projects: Vec<_> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension().is_some_and(|e| e == "kdl")
                && !p.to_string_lossy().ends_with(".solution.kdl")
        })
        .collect();
    projects.sort();
    assert!(projects.len() >= 6);
    for path in projects {
        let source = std::fs::read_to_string(&path).unwrap();
        let compilation = compile(&source, &path)
            .unwrap_or_else(|problems| panic!("{} does not compile: {problems:?}", path.display()));
        let mm = compilation.project.units.in_metres() * 1000.0;
        let parts = bed_parts(
            &compilation.project,
            &compilation.meshes,
            &compilation.design,
            &plan(&compilation),
        );
        assert_eq!(parts.len(), compilation.meshes.len());
        for (i, part) in parts.iter().enumerate() {
            let name = format!("{} {}", path.display(), part.name);
            let capsules: Vec<_> = compilation
                .design
                .capsules
                .iter()
                .filter(|c| c.component == i)
                .collect();
            assert_eq!(part.voids.len(), capsules.len());
            assert_eq!(
                part.pauses[0].voids,
                (0..capsules.len()).collect::<Vec<_>>()
            );
            let stl = write_stl(part);
            let count = u32::from_le_bytes(stl[80..84].try_into().unwrap()) as usize;
            let vertex = |t: usize, v: usize| -> [u32; 3] {
                [0, 1, 2].map(|k| {
                    let o = 84 + 50 * t + 12 + 12 * v + 4 * k;
                    u32::from_le_bytes(stl[o..o + 4].try_into().unwrap())
                })
            };
            let mut edges = BTreeMap::new();
            let mut volume = 0.0;
            let mut lowest = f64::INFINITY;
            for t in 0..count {
                let corners = [0, 1, 2].map(|v| vertex(t, v));
                for k in 0..3 {
                    *edges.entry((corners[k], corners[(k + 1) % 3])).or_insert(0) += 1;
                }
                let [a, b, c] =
                    corners.map(|c| Vector3::from(c.map(|bits| f64::from(f32::from_bits(bits)))));
                volume += a.dot(&b.cross(&c)) / 6.0;
                lowest = lowest.min(a.z).min(b.z).min(c.z);
            }
            for (&(a, b), &n) in &edges {
                assert_eq!(n, 1, "{name}: edge {a:?}-{b:?} used {n} times");
                assert_eq!(
                    edges.get(&(b, a)),
                    Some(&1),
                    "{name}: edge without its twin"
                );
            }
            let voids: f64 = capsules.iter().map(|c| c.volume()).sum::<f64>() * mm.powi(3);
            let body = compilation.mass[i].volume * mm.powi(3);
            let expected = body - voids;
            println!(
                "{name}: {count} triangles, {volume:.1} mm³ (body {body:.1} less voids {voids:.1})"
            );
            assert!(
                (volume - expected).abs() <= 0.02 * voids + 1e-6 * body,
                "{name}: {volume} vs {expected}"
            );
            assert!(lowest.abs() < 1e-3, "{name}: lowest point at {lowest}");
        }
    }
}

/// The part each extruding move of PrusaSlicer's G-code belongs to (by its `; printing object`
/// labels), with the move's end point in x and y; absolute E, as PrusaSlicer writes by default.
fn labelled_extrusions(gcode: &str) -> Vec<(String, f64, f64)> {
    let (mut x, mut y, mut e) = (0.0, 0.0, 0.0);
    let mut object: Option<String> = None;
    let mut external = false;
    let mut found = Vec::new();
    for line in gcode.lines() {
        if let Some(rest) = line.strip_prefix("; printing object ") {
            object = rest.split(" id:").next().map(str::to_string);
        } else if line.starts_with("; stop printing object") {
            object = None;
        } else if let Some(kind) = line.strip_prefix(";TYPE:") {
            external = kind == "External perimeter";
        } else if line.starts_with("G92") && line.contains("E0") {
            e = 0.0;
        } else if let Some(rest) = line.strip_prefix("G1 ") {
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
            if new_e > e + 1e-9 && external {
                if let Some(name) = &object {
                    found.push((name.clone(), x, y));
                }
            }
            e = new_e;
        }
    }
    found
}

#[test]
fn prusaslicer_slices_the_built_3mf_with_every_part_where_the_plan_put_it() {
    if std::process::Command::new("prusa-slicer")
        .arg("--help")
        .output()
        .is_err()
    {
        eprintln!("skipped: prusa-slicer is not on the PATH (apt-get install prusa-slicer)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    // Two components at 100% infill, and one part with voids at 15%.
    for name in ["articulated", "t_shape"] {
        let path = folder.join(format!("{name}.kdl"));
        let source = std::fs::read_to_string(&path).unwrap();
        let compilation = compile(&source, &path).unwrap();
        let out = dir.path().join(name);
        let written = ballast::compile::write_outputs(&compilation, &path, Some(&out)).unwrap();
        let model = out.join(format!("{name}.3mf"));
        assert!(written.written.contains(&model));
        let gcode_path = out.join(format!("{name}.gcode"));
        let run = std::process::Command::new("prusa-slicer")
            .args(["--export-gcode", "--dont-arrange", "-o"])
            .arg(&gcode_path)
            .arg(&model)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{name}: {}{}",
            String::from_utf8_lossy(&run.stdout),
            String::from_utf8_lossy(&run.stderr)
        );
        let gcode = std::fs::read_to_string(&gcode_path).unwrap();
        let moves = labelled_extrusions(&gcode);
        let mm = compilation.project.units.in_metres() * 1000.0;
        for (component, plan) in compilation.print_plan.components.iter().enumerate() {
            let part = &compilation.project.components[component].name.value;
            let bed: Vec<_> = compilation.meshes[component]
                .positions
                .iter()
                .map(|p| (plan.to_bed * p) * mm)
                .collect();
            let low = bed.iter().fold(bed[0], |a, b| a.inf(b));
            let high = bed.iter().fold(bed[0], |a, b| a.sup(b));
            let mine: Vec<_> = moves.iter().filter(|m| &m.0 == part).collect();
            assert!(!mine.is_empty(), "{name}: no extrusion labelled `{part}`");
            let (x0, x1, y0, y1) = mine.iter().fold(
                (f64::MAX, f64::MIN, f64::MAX, f64::MIN),
                |(a, b, c, d), m| (a.min(m.1), b.max(m.1), c.min(m.2), d.max(m.2)),
            );
            println!(
                "{name} {part}: outer perimeter x {x0:.2}..{x1:.2}, y {y0:.2}..{y1:.2}; \
                 plan x {:.2}..{:.2}, y {:.2}..{:.2}",
                low.x, high.x, low.y, high.y
            );
            // The outer perimeter's centre line lies half an extrusion width inside the outline;
            // a slanted or rounded side is met a little further in.
            for (got, want) in [(x0, low.x), (x1, high.x), (y0, low.y), (y1, high.y)] {
                assert!((got - want).abs() < 0.5, "{name} {part}: {got} vs {want}");
            }
        }
    }
}
