//! Warnings for a valid project that is probably not what its author meant: a model of
//! implausible size or mass, a suspension point far from the model, a stand on a tiny facet or a
//! sliver. No bundled example raises one.

use std::fs;
use std::path::Path;

use ballast::compile::{compile, Compilation};
use ballast::diagnostic::Problem;

/// A frustum with a rectangular base `bottom` (x and y sides) at z = 0 and a top `top` at
/// z = `height`, both centred on the z axis, as OBJ text (counter-clockwise seen from outside).
fn frustum_obj(bottom: [f64; 2], top: [f64; 2], height: f64) -> String {
    let mut text = String::new();
    // Vertex i: x from bit 0, y from bit 1, z (bottom or top) from bit 2.
    for i in 0..8 {
        let (half, z) = if i & 4 == 0 {
            (bottom, 0.0)
        } else {
            (top, height)
        };
        let side = |bit: usize, axis: usize| {
            if i & bit == 0 {
                -half[axis] / 2.0
            } else {
                half[axis] / 2.0
            }
        };
        text += &format!("v {} {} {z}\n", side(1, 0), side(2, 1));
    }
    let faces = [
        [0, 2, 3, 1], // z = 0
        [4, 5, 7, 6], // top
        [0, 1, 5, 4], // -y
        [2, 6, 7, 3], // +y
        [0, 4, 6, 2], // -x
        [1, 3, 7, 5], // +x
    ];
    for [a, b, c, d] in faces {
        text += &format!(
            "f {} {} {}\nf {} {} {}\n",
            a + 1,
            b + 1,
            c + 1,
            a + 1,
            c + 1,
            d + 1
        );
    }
    text
}

fn box_obj(size: [f64; 3]) -> String {
    frustum_obj([size[0], size[1]], [size[0], size[1]], size[2])
}

/// Compiles `source` beside the mesh `mesh.obj` holding `obj`.
fn compiled(obj: &str, source: &str) -> Compilation {
    let folder = tempfile::tempdir().unwrap();
    fs::write(folder.path().join("mesh.obj"), obj).unwrap();
    let path = folder.path().join("model.kdl");
    fs::write(&path, source).unwrap();
    compile(source, &path).unwrap_or_else(|problems| panic!("{problems:#?}"))
}

/// A solid uniform project (1.25 g/cm³) of `mesh.obj` with `poses`.
fn project(component: &str, poses: &str) -> String {
    format!(
        "units mm\nmaterial \"PLA\" density=1.25\nprint model=\"uniform\"\ncomponent \"part\" mesh=\"mesh.obj\"{component}\n{poses}\n"
    )
}

fn with_code<'a>(compilation: &'a Compilation, code: &str) -> Vec<&'a Problem> {
    compilation
        .warnings
        .iter()
        .filter(|problem| problem.code == code)
        .collect()
}

const SANITY: [&str; 4] = [
    "ballast::model::size",
    "ballast::model::mass",
    "ballast::goal::suspend_far",
    "ballast::goal::small_support",
];

fn assert_none(compilation: &Compilation) {
    for code in SANITY {
        assert!(
            with_code(compilation, code).is_empty(),
            "{code}: {:#?}",
            compilation.warnings
        );
    }
}

#[test]
fn a_plausible_model_raises_none() {
    let compilation = compiled(
        &box_obj([40.0, 40.0, 40.0]),
        &project("", "pose \"p\" { stand\n suspend 0 0 40.5 }"),
    );
    assert_none(&compilation);
}

#[test]
fn no_bundled_example_raises_one() {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut checked = 0;
    for entry in fs::read_dir(&folder).unwrap() {
        let path = entry.unwrap().path();
        let name = path.to_string_lossy().into_owned();
        if !name.ends_with(".kdl") || name.ends_with(".solution.kdl") {
            continue;
        }
        let source = fs::read_to_string(&path).unwrap();
        let compilation = compile(&source, &path).unwrap_or_else(|p| panic!("{name}: {p:#?}"));
        assert_none(&compilation);
        checked += 1;
    }
    assert!(checked >= 6, "{checked} examples");
}

#[test]
fn a_metres_mesh_read_as_millimetres_is_too_small_and_the_help_names_the_unit() {
    // A 40 × 20 × 60 mm box written in metres, read in the project's millimetres.
    let compilation = compiled(&box_obj([0.04, 0.02, 0.06]), &project("", "pose \"p\""));
    let found = with_code(&compilation, "ballast::model::size");
    assert_eq!(found.len(), 1, "{:#?}", compilation.warnings);
    let warning = found[0];
    assert!(warning.message.contains("too small"), "{}", warning.message);
    assert!(!warning.labels.is_empty());
    let help = warning.help.as_deref().unwrap();
    assert!(
        help.contains("`mesh-units=m` makes it 60.0 mm across"),
        "{help}"
    );
    // Its mass is implausible for the same reason: said once.
    assert!(with_code(&compilation, "ballast::model::mass").is_empty());
    // Read in metres, it is fine.
    let fixed = compiled(
        &box_obj([0.04, 0.02, 0.06]),
        &project(" mesh-units=m", "pose \"p\""),
    );
    assert_none(&fixed);
}

#[test]
fn a_model_over_a_metre_is_too_large() {
    let compilation = compiled(&box_obj([1200.0, 100.0, 100.0]), &project("", "pose \"p\""));
    let found = with_code(&compilation, "ballast::model::size");
    assert_eq!(found.len(), 1, "{:#?}", compilation.warnings);
    assert!(
        found[0].message.contains("too large"),
        "{}",
        found[0].message
    );
    assert!(found[0].help.is_some());
}

#[test]
fn a_model_under_half_a_gram_is_implausibly_light() {
    // 20 × 20 × 0.5 mm at 1.25 g/cm³: 0.25 g, though 20 mm across.
    let light = compiled(&box_obj([20.0, 20.0, 0.5]), &project("", "pose \"p\""));
    let found = with_code(&light, "ballast::model::mass");
    assert_eq!(found.len(), 1, "{:#?}", light.warnings);
    assert!(found[0].message.contains("0.250 g"), "{}", found[0].message);
    assert!(found[0].help.is_some() && !found[0].labels.is_empty());
    assert!(with_code(&light, "ballast::model::size").is_empty());
    // Twice as thick: 0.5 g, plausible.
    let enough = compiled(&box_obj([20.0, 20.0, 1.0]), &project("", "pose \"p\""));
    assert!(with_code(&enough, "ballast::model::mass").is_empty());
}

#[test]
fn a_suspension_point_far_outside_the_model_is_flagged() {
    // The box is 40 mm across: the limit is 2 mm from its surface (its top at z = 40).
    let far = compiled(
        &box_obj([40.0, 40.0, 40.0]),
        &project("", "pose \"p\" { suspend 0 0 50 }"),
    );
    let found = with_code(&far, "ballast::goal::suspend_far");
    assert_eq!(found.len(), 1, "{:#?}", far.warnings);
    assert!(
        found[0]
            .message
            .contains("10.0 mm outside component `part`"),
        "{}",
        found[0].message
    );
    assert_eq!(found[0].labels.len(), 1);
    assert!(found[0].help.is_some());
    for near in ["0 0 41.5", "0 0 20", "30 0 0"] {
        let near_source = project("", &format!("pose \"p\" {{ suspend {near} }}"));
        let compilation = compiled(&box_obj([40.0, 40.0, 40.0]), &near_source);
        let found = with_code(&compilation, "ballast::goal::suspend_far");
        // (30, 0, 0) is 10 mm beside the box's side.
        assert_eq!(found.len(), usize::from(near == "30 0 0"), "{near}");
    }
}

#[test]
fn a_stand_on_a_tiny_facet_is_flagged() {
    // An upside-down pyramid frustum 40 mm wide on a 1 mm square foot: the 1 mm² facet is under
    // (5% of 40 mm)² = 4 mm².
    let compilation = compiled(
        &frustum_obj([1.0, 1.0], [40.0, 40.0], 40.0),
        &project("", "pose \"on its foot\" { stand }"),
    );
    let found = with_code(&compilation, "ballast::goal::small_support");
    assert_eq!(found.len(), 1, "{:#?}", compilation.warnings);
    assert!(
        found[0]
            .message
            .contains("a facet of 1.00 mm², tiny beside the model"),
        "{}",
        found[0].message
    );
    assert!(found[0].help.as_deref().unwrap().contains("ballast poses"));
    // On a 3 mm foot (9 mm²), it is a small base but not tiny.
    let wider = compiled(
        &frustum_obj([3.0, 3.0], [40.0, 40.0], 40.0),
        &project("", "pose \"on its foot\" { stand }"),
    );
    assert!(with_code(&wider, "ballast::goal::small_support").is_empty());
}

#[test]
fn a_stand_on_a_sliver_is_flagged() {
    // A wall 60 mm long and 1 mm thick standing on its edge: narrower than 2% of 60 mm.
    let compilation = compiled(
        &box_obj([60.0, 1.0, 40.0]),
        &project("", "pose \"on edge\" { stand }"),
    );
    let found = with_code(&compilation, "ballast::goal::small_support");
    assert_eq!(found.len(), 1, "{:#?}", compilation.warnings);
    assert!(
        found[0].message.contains("a sliver 1.00 mm wide"),
        "{}",
        found[0].message
    );
    // Twice as thick is past the limit of 1.2 mm.
    let thicker = compiled(
        &box_obj([60.0, 2.0, 40.0]),
        &project("", "pose \"on edge\" { stand }"),
    );
    assert!(with_code(&thicker, "ballast::goal::small_support").is_empty());
}

/// OBJ text of the closed mesh with `vertices` and triangles `faces` (indices from 0,
/// counter-clockwise seen from outside).
fn obj(vertices: &[[f64; 3]], faces: &[[usize; 3]]) -> String {
    let mut text = String::new();
    for [x, y, z] in vertices {
        text += &format!("v {x} {y} {z}\n");
    }
    for [a, b, c] in faces {
        text += &format!("f {} {} {}\n", a + 1, b + 1, c + 1);
    }
    text
}

#[test]
fn a_stand_on_a_single_point_is_flagged_with_a_span_and_a_hint() {
    // An upside-down square pyramid, 40 mm wide and tall, on its apex at the origin.
    let pyramid = obj(
        &[
            [0.0, 0.0, 0.0],
            [-20.0, -20.0, 40.0],
            [20.0, -20.0, 40.0],
            [20.0, 20.0, 40.0],
            [-20.0, 20.0, 40.0],
        ],
        &[
            [1, 2, 3],
            [1, 3, 4],
            [0, 2, 1],
            [0, 3, 2],
            [0, 4, 3],
            [0, 1, 4],
        ],
    );
    let source = project("", "pose \"on its tip\" { stand }");
    let compilation = compiled(&pyramid, &source);
    let found = with_code(&compilation, "ballast::goal::small_support");
    assert_eq!(found.len(), 1, "{:#?}", compilation.warnings);
    assert!(
        found[0]
            .message
            .contains("in pose `on its tip`, the model stands on a single point"),
        "{}",
        found[0].message
    );
    assert_stand_label(found[0], &source);
    assert!(found[0].help.as_deref().unwrap().contains("ballast poses"));
    // The same pyramid on its base is a plain base.
    let on_base = compiled(
        &pyramid,
        &project("", "pose \"on its base\" { rotate 180 0 0; stand }"),
    );
    assert!(
        with_code(&on_base, "ballast::goal::small_support").is_empty(),
        "{:#?}",
        on_base.warnings
    );
}

#[test]
fn a_stand_on_an_edge_is_flagged_with_a_span_and_a_hint() {
    // A wedge 60 mm long on its ridge along x at z = 0, 40 mm wide at its top (z = 40).
    let wedge = obj(
        &[
            [-30.0, 0.0, 0.0],
            [30.0, 0.0, 0.0],
            [-30.0, -20.0, 40.0],
            [30.0, -20.0, 40.0],
            [30.0, 20.0, 40.0],
            [-30.0, 20.0, 40.0],
        ],
        &[
            [2, 3, 4],
            [2, 4, 5],
            [0, 1, 3],
            [0, 3, 2],
            [0, 5, 4],
            [0, 4, 1],
            [0, 2, 5],
            [1, 4, 3],
        ],
    );
    let source = project("", "pose \"on its ridge\" { stand }");
    let compilation = compiled(&wedge, &source);
    let found = with_code(&compilation, "ballast::goal::small_support");
    assert_eq!(found.len(), 1, "{:#?}", compilation.warnings);
    assert!(
        found[0]
            .message
            .contains("in pose `on its ridge`, the model stands on an edge"),
        "{}",
        found[0].message
    );
    assert_stand_label(found[0], &source);
    assert!(found[0].help.as_deref().unwrap().contains("`down`"));
}

/// The warning's one label points at the `stand` goal in `source`.
fn assert_stand_label(warning: &Problem, source: &str) {
    assert_eq!(warning.labels.len(), 1, "{warning:#?}");
    let span = warning.labels[0].0;
    let labelled = &source[span.offset()..span.offset() + span.len()];
    assert!(labelled.starts_with("stand"), "{labelled:?}");
}
