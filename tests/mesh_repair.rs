//! Meshes a slicer prints though they are not clean solids: shells that cross are taken as their
//! union with a warning that says how much they overlap, and the union's mass properties are the
//! closed form's; flipped, doubled and inside-out triangles are repaired with a warning, and the
//! solid weighs what the clean mesh does.

use std::fs;

use ballast::compile::compile;
use ballast::geometry::MassProperties;
use nalgebra::Point3;

/// OBJ text of the boxes `[low, high]`, each a closed outward shell.
fn boxes(boxes: &[([f64; 3], [f64; 3])]) -> String {
    let mut text = String::new();
    for (n, (low, high)) in boxes.iter().enumerate() {
        for i in 0..8 {
            let pick = |bit: usize, axis: usize| if i & bit != 0 { high[axis] } else { low[axis] };
            text += &format!("v {} {} {}\n", pick(1, 0), pick(2, 1), pick(4, 2));
        }
        let first = 8 * n + 1;
        for [a, b, c] in [
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
        ] {
            text += &format!("f {} {} {}\n", a + first, b + first, c + first);
        }
    }
    text
}

/// Compiles a project of one component whose mesh is `obj`: its problems (warnings too) as
/// (code, message), and whether it compiled.
fn problems(obj: &str) -> (Vec<(String, String)>, bool) {
    let (problems, solid) = compiled(obj);
    (problems, solid.is_some())
}

/// Compiles a project of one component whose mesh is `obj`: its problems (warnings too) as
/// (code, message), and the mass properties of its solid when it compiled.
fn compiled(obj: &str) -> (Vec<(String, String)>, Option<MassProperties>) {
    let folder = tempfile::tempdir().unwrap();
    fs::write(folder.path().join("part.obj"), obj).unwrap();
    let source = "material \"PLA\" density=1.24\ncomponent \"part\" mesh=\"part.obj\"\npose \"p\" {\n    stand\n}\n";
    let path = folder.path().join("part.kdl");
    fs::write(&path, source).unwrap();
    let listed = |problems: &[ballast::diagnostic::Problem]| {
        problems
            .iter()
            .map(|p| (p.code.to_string(), p.message.clone()))
            .collect()
    };
    match compile(source, &path) {
        Ok(compiled) => (listed(&compiled.warnings), Some(compiled.mass[0])),
        Err(problems) => (listed(&problems), None),
    }
}

#[test]
fn shells_that_cross_a_little_are_their_union_with_a_warning() {
    // A 40 × 30 × 20 mm block and a lug pushed 0.1 mm into its side: 10 mm³ in common.
    let obj = boxes(&[
        ([0.0, 0.0, 0.0], [40.0, 30.0, 20.0]),
        ([39.9, 10.0, 5.0], [45.0, 20.0, 15.0]),
    ]);
    let (problems, compiled) = problems(&obj);
    assert!(compiled, "{problems:#?}");
    let (_, message) = problems
        .iter()
        .find(|(code, _)| code == "ballast::mesh::crossing")
        .unwrap_or_else(|| panic!("{problems:#?}"));
    // 10 / 24,500 of the solid: 0.041 %, measured on slices a step (45 / 256 mm) apart.
    let share: f64 = message
        .split("overlap by ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|number| number.parse().ok())
        .unwrap_or_else(|| panic!("{message}"));
    assert!((share - 0.0408).abs() < 0.01, "{message}");
    assert!(message.contains("union"), "{message}");
}

#[test]
fn shells_that_overlap_much_weigh_as_their_union() {
    // A 40 × 30 × 20 block and a 40 × 30 × 10 one across its corner: 20 × 18 × 10 in common.
    let obj = boxes(&[
        ([0.0, 0.0, 0.0], [40.0, 30.0, 20.0]),
        ([20.0, 12.0, 0.0], [60.0, 42.0, 10.0]),
    ]);
    let (problems, solid) = compiled(&obj);
    let solid = solid.unwrap_or_else(|| panic!("{problems:#?}"));
    let (_, message) = problems
        .iter()
        .find(|(code, _)| code == "ballast::mesh::crossing")
        .unwrap_or_else(|| panic!("{problems:#?}"));
    // 3,600 of 32,400 mm³ in common: 11.1 %.
    let share: f64 = message
        .split("overlap by ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|number| number.parse().ok())
        .unwrap_or_else(|| panic!("{message}"));
    assert!((share - 11.11).abs() < 0.1, "{message}");
    // Closed forms: the union is the two blocks less their common block, counted once.
    let blocks = [
        (24_000.0, [20.0, 15.0, 10.0]),
        (12_000.0, [40.0, 27.0, 5.0]),
        (-3_600.0, [30.0, 21.0, 5.0]),
    ];
    let volume: f64 = blocks.iter().map(|b| b.0).sum();
    let centre = blocks.iter().fold(Point3::origin(), |c, (v, at)| {
        c + Point3::from(*at).coords * (*v / volume)
    });
    // Measured on slices a step (60 / 256 mm) apart, exact along each row: each face of the
    // common block facing ±y or ±z may be off by half a step.
    let half_step = 60.0 / 256.0 / 2.0;
    let faces = 2.0 * 20.0 * 10.0 + 2.0 * 20.0 * 18.0;
    assert!(
        (solid.volume - volume).abs() <= half_step * faces,
        "{} against {volume}",
        solid.volume
    );
    assert!(
        (solid.centroid - centre).norm() < 0.05,
        "{} against {centre}",
        solid.centroid
    );
    // The sum of the two blocks' (the overlap counted twice) is far off: (26.67, 19, 8.33).
    let sum = Point3::new(960_000.0, 684_000.0, 300_000.0) / 36_000.0;
    assert!((solid.centroid - sum).norm() > 0.3);
    // The second moment about the centroid, along x: the union's, as the closed form sums it.
    let about_x = |volume: f64, at: [f64; 3], size: [f64; 3]| {
        volume * (size[0] * size[0] / 12.0 + at[0] * at[0])
    };
    let xx = about_x(24_000.0, [20.0, 15.0, 10.0], [40.0, 30.0, 20.0])
        + about_x(12_000.0, [40.0, 27.0, 5.0], [40.0, 30.0, 10.0])
        - about_x(3_600.0, [30.0, 21.0, 5.0], [20.0, 18.0, 10.0]);
    let relative = (solid.second_moment[(0, 0)] - xx).abs() / xx;
    assert!(
        relative < 5e-3,
        "{} against {xx}",
        solid.second_moment[(0, 0)]
    );
}

#[test]
fn misnested_shells_weigh_as_their_union() {
    // A 40 × 30 × 20 block with a 10 mm cube inside it facing out (a cavity turned the wrong
    // way: filled, as a slicer prints it), and a 10 mm cube beside it facing in (inside nothing:
    // nothing printed).
    let mut obj = boxes(&[
        ([0.0, 0.0, 0.0], [40.0, 30.0, 20.0]),
        ([5.0, 5.0, 5.0], [15.0, 15.0, 15.0]),
    ]);
    let beside = boxes(&[([60.0, 0.0, 0.0], [70.0, 10.0, 10.0])]);
    for line in beside.lines() {
        obj += &match line.strip_prefix("f ") {
            Some(face) => {
                let corners: Vec<usize> = face
                    .split_whitespace()
                    .map(|c| c.parse::<usize>().unwrap() + 16)
                    .collect();
                format!("f {} {} {}\n", corners[0], corners[2], corners[1])
            }
            None => format!("{line}\n"),
        };
    }
    let (problems, solid) = compiled(&obj);
    let solid = solid.unwrap_or_else(|| panic!("{problems:#?}"));
    assert!(
        problems
            .iter()
            .any(|(code, message)| code == "ballast::mesh::nested_shells"
                && message.contains("union")),
        "{problems:#?}"
    );
    // The block alone: measured on slices 70 / 256 mm apart, each face of the two cubes
    // facing ±y or ±z off by half a step at most.
    let half_step = 70.0 / 256.0 / 2.0;
    let faces = 2.0 * 4.0 * 100.0;
    assert!(
        (solid.volume - 24_000.0).abs() <= half_step * faces,
        "{}",
        solid.volume
    );
    // Each cube's volume off by up to half a step times its faces, at 10 and 45 mm from the
    // block's centre.
    let bound = half_step * faces / 2.0 * (10.0 + 45.0) / 24_000.0;
    assert!(
        (solid.centroid - Point3::new(20.0, 15.0, 10.0)).norm() < bound,
        "{} (within {bound})",
        solid.centroid
    );
}

#[test]
fn flipped_doubled_and_inside_out_triangles_are_repaired() {
    let clean = boxes(&[([0.0, 0.0, 0.0], [40.0, 30.0, 20.0])]);
    let (_, solid) = compiled(&clean);
    let clean_solid = solid.unwrap();
    assert!((clean_solid.volume - 24_000.0).abs() < 1e-6);
    let faces: Vec<&str> = clean.lines().filter(|l| l.starts_with("f ")).collect();
    let vertices: String = clean
        .lines()
        .filter(|l| l.starts_with("v "))
        .map(|l| format!("{l}\n"))
        .collect();
    let reversed = |face: &str| {
        let corners: Vec<&str> = face.split_whitespace().skip(1).collect();
        format!("f {} {} {}", corners[0], corners[2], corners[1])
    };
    let with_faces = |faces: Vec<String>| vertices.clone() + &faces.join("\n") + "\n";
    let own = |f: &[&str]| f.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let mut flipped = own(&faces);
    flipped[3] = reversed(faces[3]);
    let mut doubled = own(&faces);
    doubled.push(faces[5].to_string());
    let inside_out: Vec<String> = faces.iter().map(|f| reversed(f)).collect();
    for (mesh, code) in [
        (with_faces(flipped), "ballast::mesh::flipped"),
        (with_faces(doubled), "ballast::mesh::repeated"),
        (with_faces(inside_out), "ballast::mesh::inverted"),
    ] {
        let (problems, solid) = compiled(&mesh);
        let solid = solid.unwrap_or_else(|| panic!("{code}: {problems:#?}"));
        assert!(
            problems.iter().any(|(c, _)| c == code),
            "{code}: {problems:#?}"
        );
        assert!(
            problems.iter().all(|(c, _)| c == code),
            "only the repair is reported: {problems:#?}"
        );
        assert!((solid.volume - clean_solid.volume).abs() < 1e-6, "{code}");
        assert!(
            (solid.centroid - clean_solid.centroid).norm() < 1e-9,
            "{code}"
        );
    }
}

#[test]
fn a_box_without_a_face_is_refused_as_open() {
    let clean = boxes(&[([0.0, 0.0, 0.0], [40.0, 30.0, 20.0])]);
    // Without the two triangles of its top: a 40 × 30 mm opening.
    let open: String = clean
        .lines()
        .enumerate()
        .filter(|&(i, _)| i != 8 + 2 && i != 8 + 3)
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    let (problems, solid) = compiled(&open);
    assert!(solid.is_none());
    let (_, message) = problems
        .iter()
        .find(|(code, _)| code == "ballast::mesh::open")
        .unwrap_or_else(|| panic!("{problems:#?}"));
    // Four times its area over the length around it: 4 × 1,200 / 140.
    assert!(message.contains("34.2857 mm across"), "{message}");
}
