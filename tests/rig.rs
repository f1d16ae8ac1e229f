//! A rig: components from a glTF file's mesh nodes, poses from its animations. A project read
//! from a rig must give the report of the same project written by hand (components by `node=`,
//! each pose's part moved by a `component` block about its joint); its mistakes are diagnostics
//! with spans.

mod glb_support;
mod rig_support;

use std::fs;
use std::path::Path;

use ballast::compile::{compile, Compilation, Report};
use rig_support::{
    figure, figure_animations, rig_glb, scenes_glb, turn, Animation, Channel, Joint,
};

fn compiled(folder: &Path, source: &str) -> Result<Compilation, Vec<ballast::diagnostic::Problem>> {
    let path = folder.join("model.kdl");
    fs::write(&path, source).unwrap();
    compile(source, &path)
}

/// The components' names, in project order.
fn component_names(compilation: &Compilation) -> Vec<&str> {
    compilation
        .project
        .components
        .iter()
        .map(|c| c.name.value.as_str())
        .collect()
}

fn report(folder: &Path, compilation: &Compilation) -> serde_json::Value {
    serde_json::from_str(&Report::new(compilation, &folder.join("model.kdl")).to_json()).unwrap()
}

/// Whether two reports agree: the same keys, strings and flags, and numbers within `1e-6` of
/// their size (the rig's turns are 32-bit floats, the hand-written ones 64-bit).
fn agree(a: &serde_json::Value, b: &serde_json::Value, at: &str) -> Result<(), String> {
    use serde_json::Value;
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            if (x - y).abs() <= 1e-6 * (1.0 + x.abs().max(y.abs())) {
                Ok(())
            } else {
                Err(format!("{at}: {x} against {y}"))
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .try_for_each(|(i, (x, y))| agree(x, y, &format!("{at}[{i}]"))),
        (Value::Object(x), Value::Object(y)) if x.len() == y.len() => {
            x.iter().try_for_each(|(k, v)| {
                let other = y.get(k).ok_or(format!("{at}.{k}: missing"))?;
                agree(v, other, &format!("{at}.{k}"))
            })
        }
        _ if a == b => Ok(()),
        _ => Err(format!("{at}: {a} against {b}")),
    }
}

const HEADER: &str = r#"units mm
up z
material "PLA" density=1.24
print model="uniform"
ball { diameters 8; }
capsule "weight" component="Torso" radius=4.2 {
    from -10 0 62
    to 10 0 70
}
"#;

/// The figure's rig project: its six parts from the rig, four poses from its animations.
const RIG_POSES: &str = r#"rig "figure.glb"
pose "stand" { stand margin=1 }
pose "wave" animation="Wave" time=1 { stand margin=1; }
pose "half wave" animation="Wave" time=0.5 { stand margin=1; }
pose "reach" animation="Reach" { stand margin=1; }
"#;

/// The same by hand: the joints at their rest positions in the project's frame (glTF's
/// `(x, y, z)` metres is `(1000 x, −1000 z, 1000 y)` here), a turn about glTF's +Z is one about
/// −Y here, about +X one about +X.
const HAND_POSES: &str = r#"component "Torso" mesh="figure.glb" node="Torso"
component "Head" mesh="figure.glb" node="Head"
component "Arm.L" mesh="figure.glb" node="Arm.L"
component "Arm.R" mesh="figure.glb" node="Arm.R"
component "Leg.L" mesh="figure.glb" node="Leg.L"
component "Leg.R" mesh="figure.glb" node="Leg.R"
pose "stand" { stand margin=1 }
pose "wave" {
    component "Arm.R" {
        pivot -20 0 85
        rotate 0 150 0
    }
    stand margin=1
}
pose "half wave" {
    component "Arm.R" {
        pivot -20 0 85
        rotate 0 75 0
    }
    stand margin=1
}
pose "reach" {
    component "Arm.L" {
        pivot 20 0 85
        rotate -90 0 0
    }
    component "Arm.R" {
        pivot -20 0 85
        rotate -90 0 0
    }
    stand margin=1
}
"#;

fn figure_folder() -> tempfile::TempDir {
    let folder = tempfile::tempdir().unwrap();
    fs::write(
        folder.path().join("figure.glb"),
        rig_glb(&figure(), &figure_animations()),
    )
    .unwrap();
    folder
}

#[test]
fn a_rig_with_animated_poses_reports_as_the_project_written_by_hand() {
    let rigged_folder = figure_folder();
    let hand_folder = figure_folder();
    let rigged = compiled(rigged_folder.path(), &format!("{HEADER}{RIG_POSES}")).unwrap();
    let hand = compiled(hand_folder.path(), &format!("{HEADER}{HAND_POSES}")).unwrap();
    let names = component_names(&rigged);
    assert_eq!(names, ["Torso", "Head", "Arm.L", "Arm.R", "Leg.L", "Leg.R"]);
    // The poses differ: the arms move the centre of mass.
    let com = |c: &Compilation, pose: usize| c.poses[pose].centre_of_mass;
    assert!((com(&rigged, 0)[2] - com(&rigged, 1)[2]).abs() > 0.5);
    assert!((com(&rigged, 0)[1] - com(&rigged, 3)[1]).abs() > 0.5);
    agree(
        &report(rigged_folder.path(), &rigged),
        &report(hand_folder.path(), &hand),
        "report",
    )
    .unwrap();
}

/// A copy of the figure's joints, each name followed by `suffix` (as Blender names copies), its
/// parents numbered from `first`, and the joints `turns` names turned.
fn figure_copy(suffix: &str, first: usize, turns: &[(usize, [f32; 4])]) -> Vec<Joint> {
    let mut joints = figure();
    for (index, joint) in joints.iter_mut().enumerate() {
        joint.name = Box::leak(format!("{}{suffix}", joint.name).into_boxed_str());
        joint.parent = joint.parent.map(|parent| parent + first);
        if let Some((_, rotation)) = turns.iter().find(|(turned, _)| *turned == index) {
            joint.rotation = *rotation;
        }
    }
    joints
}

/// The figure (joints 0 to 11) with posed copies: `.001` waving (joints 12 to 23), `.002`
/// reaching (24 to 35), and a right arm `Arm.R.003` alone (36); the scenes `Rest` (the figure,
/// the default), `Wave`, `Reach`, `Twice` (both copies) and `Arm` (the lone arm).
fn scenes_folder() -> tempfile::TempDir {
    let mut joints = figure();
    joints.extend(figure_copy(
        ".001",
        12,
        &[(6, turn([0.0, 0.0, 1.0], -150.0))],
    ));
    let forward = turn([1.0, 0.0, 0.0], -90.0);
    joints.extend(figure_copy(".002", 24, &[(4, forward), (6, forward)]));
    joints.push(Joint::new(
        "Arm.R.003",
        None,
        [0.0, 0.0, 0.0],
        Some([[-0.01, -0.036, -0.005], [0.0, 0.0, 0.005]]),
    ));
    let scenes = [
        ("Rest", vec![0]),
        ("Wave", vec![12]),
        ("Reach", vec![24]),
        ("Twice", vec![12, 24]),
        ("Arm", vec![36]),
    ];
    let folder = tempfile::tempdir().unwrap();
    fs::write(
        folder.path().join("figure.glb"),
        scenes_glb(&joints, &[], &scenes),
    )
    .unwrap();
    folder
}

#[test]
fn a_rig_with_poses_from_scenes_reports_as_the_project_written_by_hand() {
    let rigged_folder = scenes_folder();
    let hand_folder = figure_folder();
    let rig = r#"rig "figure.glb"
pose "stand" scene="Rest" { stand margin=1 }
pose "wave" scene="Wave" { stand margin=1; }
pose "reach" scene="Reach" { stand margin=1; }
pose "reach one" scene="Reach" {
    component "Arm.L" { }
    stand
}
"#;
    let hand = r#"rig "figure.glb"
pose "stand" { stand margin=1 }
pose "wave" {
    component "Arm.R" {
        pivot -20 0 85
        rotate 0 150 0
    }
    stand margin=1
}
pose "reach" {
    component "Arm.L" {
        pivot 20 0 85
        rotate -90 0 0
    }
    component "Arm.R" {
        pivot -20 0 85
        rotate -90 0 0
    }
    stand margin=1
}
pose "reach one" {
    component "Arm.R" {
        pivot -20 0 85
        rotate -90 0 0
    }
    stand
}
"#;
    let rigged = compiled(rigged_folder.path(), &format!("{HEADER}{rig}")).unwrap();
    let by_hand = compiled(hand_folder.path(), &format!("{HEADER}{hand}")).unwrap();
    // The parts are the default scene's, not the copies'.
    let names = component_names(&rigged);
    assert_eq!(names, ["Torso", "Head", "Arm.L", "Arm.R", "Leg.L", "Leg.R"]);
    let com = |c: &Compilation, pose: usize| c.poses[pose].centre_of_mass;
    assert!((com(&rigged, 0)[2] - com(&rigged, 1)[2]).abs() > 0.5);
    assert!((com(&rigged, 0)[1] - com(&rigged, 2)[1]).abs() > 0.5);
    agree(
        &report(rigged_folder.path(), &rigged),
        &report(hand_folder.path(), &by_hand),
        "report",
    )
    .unwrap();
}

#[test]
fn unknown_scenes_missing_parts_and_two_sources_are_diagnostics() {
    let folder = scenes_folder();
    let source = r#"rig "figure.glb" { nodes "Torso" "Arm.R"; }
pose "a" scene="Wvae" { stand; }
pose "b" scene="Twice" { stand; }
pose "c" scene="Arm" { stand; }
pose "d" scene="Wave" animation="Wave" { stand; }
pose "e" scene="Nothing like it" { stand; }
"#;
    let found = problems(folder.path(), source);
    let expect = [
        (
            "ballast::rig::unknown_scene",
            "\"Wvae\"",
            "did you mean `Wave`?",
        ),
        ("ballast::rig::ambiguous_node", "\"Twice\"", ""),
        ("ballast::rig::ambiguous_node", "\"Twice\"", ""),
        ("ballast::rig::not_in_scene", "\"Arm\"", "every part"),
        ("ballast::rig::two_sources", "\"Wave\"", "keep one"),
        (
            "ballast::rig::unknown_scene",
            "\"Nothing like it\"",
            "the rig's scenes are `Rest`, `Wave`, `Reach`, `Twice` and `Arm`",
        ),
    ];
    assert_eq!(found.len(), expect.len(), "{found:#?}");
    for ((code, text, help), (want_code, want_text, want_help)) in found.iter().zip(expect) {
        assert_eq!((code.as_str(), text.as_str()), (want_code, want_text));
        assert!(help.starts_with(want_help), "{help}");
    }
    let without_rig = tempfile::tempdir().unwrap();
    let found = problems(
        without_rig.path(),
        "component \"a\" mesh=\"a.obj\"\npose \"p\" scene=\"Wave\"\n",
    );
    assert!(found
        .iter()
        .any(|(code, text, _)| code == "ballast::rig::missing" && text == "\"Wave\""));
}

#[test]
fn a_rig_in_metres_weighs_its_boxes_in_a_millimetre_project() {
    let folder = figure_folder();
    let source = "units mm\nmaterial \"PLA\" density=1.25\nprint model=\"uniform\"\n\
                  rig \"figure.glb\" { nodes \"Torso\" \"Head\"; }\npose \"p\"\n";
    let compilation = compiled(folder.path(), source).unwrap();
    // Closed form: 40 × 40 × 24 mm and 24 × 24 × 24 mm of 1.25 g/cm³.
    let expected = 1.25 * (40.0 * 40.0 * 24.0 + 24.0 * 24.0 * 24.0) / 1000.0;
    let mass = compilation.poses[0].mass;
    assert!(
        (mass - expected).abs() < 1e-6 * expected,
        "{mass} g, not {expected} g"
    );
    assert_eq!(compilation.project.components.len(), 2);
}

#[test]
fn a_transform_written_in_a_pose_overrides_the_animation() {
    let rigged_folder = figure_folder();
    let hand_folder = figure_folder();
    let rig = r#"rig "figure.glb"
pose "reach one" animation="Reach" {
    component "Arm.L" { }
    stand
}
"#;
    let hand = r#"rig "figure.glb"
pose "reach one" {
    component "Arm.R" {
        pivot -20 0 85
        rotate -90 0 0
    }
    stand
}
"#;
    let rigged = compiled(rigged_folder.path(), &format!("{HEADER}{rig}")).unwrap();
    let by_hand = compiled(hand_folder.path(), &format!("{HEADER}{hand}")).unwrap();
    agree(
        &report(rigged_folder.path(), &rigged),
        &report(hand_folder.path(), &by_hand),
        "report",
    )
    .unwrap();
}

/// The codes of the problems `source` gives, with the text each first label points at.
fn problems(folder: &Path, source: &str) -> Vec<(String, String, String)> {
    let problems = compiled(folder, source).expect_err("the project is invalid");
    problems
        .iter()
        .map(|problem| {
            let text = problem.labels.first().map_or(String::new(), |(span, _)| {
                source[span.offset()..span.offset() + span.len()].to_owned()
            });
            (
                problem.code.to_string(),
                text,
                problem.help.clone().unwrap_or_default(),
            )
        })
        .collect()
}

#[test]
fn unknown_names_and_times_are_diagnostics_on_their_text() {
    let folder = figure_folder();
    let source = r#"rig "figure.glb" { nodes "Torso" "Haed"; }
pose "a" animation="Wvae" time=0.5 { stand; }
pose "b" animation="Wave" time=3 { stand; }
pose "c" animation="Wave" { stand; }
pose "d" time=1 { stand; }
"#;
    let found = problems(folder.path(), source);
    let expect = [
        (
            "ballast::rig::unknown_node",
            "\"Haed\"",
            "did you mean `Head`?",
        ),
        (
            "ballast::rig::unknown_animation",
            "\"Wvae\"",
            "did you mean `Wave`?",
        ),
        (
            "ballast::rig::time_outside",
            "3",
            "give a time from 0 to 1 (seconds)",
        ),
        ("ballast::rig::time_needed", "\"Wave\"", ""),
        ("ballast::missing_property", "1", ""),
    ];
    assert_eq!(found.len(), expect.len(), "{found:#?}");
    for ((code, text, help), (want_code, want_text, want_help)) in found.iter().zip(expect) {
        assert_eq!((code.as_str(), text.as_str()), (want_code, want_text));
        assert!(help.starts_with(want_help), "{help}");
    }
}

#[test]
fn an_animation_without_a_rig_and_a_missing_rig_file_are_diagnostics() {
    let folder = tempfile::tempdir().unwrap();
    let found = problems(
        folder.path(),
        "component \"a\" mesh=\"a.obj\"\npose \"p\" animation=\"Wave\"\n",
    );
    assert!(found
        .iter()
        .any(|(code, text, _)| code == "ballast::rig::missing" && text == "\"Wave\""));
    let found = problems(folder.path(), "rig \"none.glb\"\npose \"p\"\n");
    assert_eq!(found[0].0, "ballast::rig::unreadable");
    assert_eq!(found[0].1, "\"none.glb\"");
}

#[test]
fn a_scaling_animation_and_a_skinned_part_are_refused() {
    let folder = tempfile::tempdir().unwrap();
    let mut joints = vec![
        Joint::new("Base", None, [0.0, 0.0, 0.0], Some([[0.0; 3], [0.02; 3]])),
        Joint::new("Skin", None, [0.05, 0.0, 0.0], Some([[0.0; 3], [0.02; 3]])),
    ];
    joints[1].skinned = true;
    let animations = [
        Animation {
            name: "Grow",
            channels: vec![Channel {
                joint: 0,
                path: "scale",
                interpolation: "STEP",
                times: vec![0.0],
                values: vec![2.0, 2.0, 2.0],
            }],
        },
        Animation {
            name: "Spin",
            channels: vec![Channel {
                joint: 0,
                path: "rotation",
                interpolation: "STEP",
                times: vec![0.0],
                values: turn([0.0, 1.0, 0.0], 90.0).to_vec(),
            }],
        },
    ];
    fs::write(folder.path().join("r.glb"), rig_glb(&joints, &animations)).unwrap();
    let found = problems(
        folder.path(),
        "rig \"r.glb\"\npose \"grow\" animation=\"Grow\"\npose \"spin\" animation=\"Spin\"\n",
    );
    let codes: Vec<(&str, &str)> = found
        .iter()
        .map(|(code, text, _)| (code.as_str(), text.as_str()))
        .collect();
    assert_eq!(
        codes,
        [
            ("ballast::rig::skinned", "\"r.glb\""),
            ("ballast::rig::not_rigid", "\"Grow\""),
        ]
    );
    // The skinned node is refused by name too, as a rig's `nodes` entry and as a component's
    // `node=`, and the message says why.
    let found = problems(
        folder.path(),
        "rig \"r.glb\" { nodes \"Base\" \"Skin\"; }\npose \"p\"\n",
    );
    assert_eq!(found.len(), 1, "{found:#?}");
    assert_eq!(
        (found[0].0.as_str(), found[0].1.as_str()),
        ("ballast::rig::skinned", "\"Skin\"")
    );
    let source = "component \"s\" mesh=\"r.glb\" node=\"Skin\"\npose \"p\"\n";
    let refused = compiled(folder.path(), source).expect_err("a skinned node is refused");
    assert_eq!(refused.len(), 1, "{refused:#?}");
    assert_eq!(refused[0].code.to_string(), "ballast::mesh::skinned");
    assert!(
        refused[0].message.contains("node `Skin`"),
        "{}",
        refused[0].message
    );
    assert!(
        refused[0].message.contains("skinned mesh"),
        "{}",
        refused[0].message
    );
}

#[test]
fn a_part_named_as_a_component_is_a_duplicate_name() {
    let folder = figure_folder();
    fs::write(folder.path().join("a.obj"), "").unwrap();
    let found = problems(
        folder.path(),
        "component \"Head\" mesh=\"a.obj\"\nrig \"figure.glb\"\npose \"p\"\n",
    );
    assert_eq!(found[0].0, "ballast::duplicate_name");
}

#[test]
fn the_example_figure_is_the_rig_the_tests_build() {
    // `examples/meshes/figure.glb` is written by this test with `BALLAST_BLESS` set.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes/figure.glb");
    let built = rig_glb(&figure(), &figure_animations());
    if std::env::var_os("BALLAST_BLESS").is_some() {
        fs::write(&path, &built).unwrap();
    }
    assert!(
        fs::read(&path).unwrap() == built,
        "run with BALLAST_BLESS=1 to rewrite it"
    );
}

#[test]
fn a_rig_part_takes_a_print_block_as_a_component_does() {
    use ballast::fabrication::OrientationChoice;
    let rigged_folder = figure_folder();
    let hand_folder = figure_folder();
    let rig = r#"rig "figure.glb" {
    part "Torso" {
        print { down 1 0 0; }
    }
}
pose "stand" { stand margin=1; }
"#;
    let hand = r#"component "Torso" mesh="figure.glb" node="Torso" {
    print { down 1 0 0; }
}
component "Head" mesh="figure.glb" node="Head"
component "Arm.L" mesh="figure.glb" node="Arm.L"
component "Arm.R" mesh="figure.glb" node="Arm.R"
component "Leg.L" mesh="figure.glb" node="Leg.L"
component "Leg.R" mesh="figure.glb" node="Leg.R"
pose "stand" { stand margin=1; }
"#;
    let rigged = compiled(rigged_folder.path(), &format!("{HEADER}{rig}")).unwrap();
    let by_hand = compiled(hand_folder.path(), &format!("{HEADER}{hand}")).unwrap();
    let torso = &rigged.orientations[0];
    assert_eq!(torso.choice, OrientationChoice::Declared);
    assert!(
        (torso.down - nalgebra::Vector3::x()).norm() < 1e-12,
        "{}",
        torso.down
    );
    let hand_torso = &by_hand.orientations[0];
    assert!((torso.to_print.matrix() - hand_torso.to_print.matrix()).norm() < 1e-9);
    // The parts without a block are chosen, as they are without any.
    assert!(matches!(
        rigged.orientations[1].choice,
        OrientationChoice::Chosen { .. }
    ));
    agree(
        &report(rigged_folder.path(), &rigged),
        &report(hand_folder.path(), &by_hand),
        "report",
    )
    .unwrap();
}

#[test]
fn a_part_block_for_no_part_or_twice_is_a_diagnostic() {
    let folder = figure_folder();
    let source = r#"rig "figure.glb" {
    nodes "Torso" "Head"
    part "Haed" { print { down 0 0 -1; } }
    part "Arm.L" { print { down 0 0 -1; } }
    part "Torso" { print { down 0 0 -1; } }
    part "Torso" { print { down 1 0 0; } }
}
pose "a" { stand; }
"#;
    let found = problems(folder.path(), source);
    let codes: Vec<(&str, &str, &str)> = found
        .iter()
        .map(|(code, text, help)| (code.as_str(), text.as_str(), help.as_str()))
        .collect();
    assert_eq!(
        codes,
        [
            (
                "ballast::rig::unknown_part",
                "\"Haed\"",
                "did you mean `Head`?"
            ),
            (
                "ballast::rig::unknown_part",
                "\"Arm.L\"",
                "the rig's parts are `Torso`, `Head`"
            ),
            (
                "ballast::duplicate_name",
                "\"Torso\"",
                "put the part's settings in one `part` block"
            ),
        ]
    );
}

/// The JSON and binary chunks of a GLB file.
fn glb_chunks(bytes: &[u8]) -> (serde_json::Value, Vec<u8>) {
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let json_length = word(12);
    let json = serde_json::from_slice(&bytes[20..20 + json_length]).unwrap();
    let bin_at = 20 + json_length;
    let bin = bytes[bin_at + 8..bin_at + 8 + word(bin_at)].to_vec();
    (json, bin)
}

/// The floats of accessor `index` (tightly packed 32-bit floats).
fn floats(json: &serde_json::Value, bin: &[u8], index: usize) -> Vec<f32> {
    let accessor = &json["accessors"][index];
    assert_eq!(accessor["componentType"], 5126);
    let view = &json["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
        + accessor["byteOffset"].as_u64().unwrap_or(0) as usize;
    let width = match accessor["type"].as_str().unwrap() {
        "SCALAR" => 1,
        "VEC3" => 3,
        "VEC4" => 4,
        other => panic!("accessor type {other}"),
    };
    let count = accessor["count"].as_u64().unwrap() as usize * width;
    (0..count)
        .map(|k| f32::from_le_bytes(bin[start + 4 * k..start + 4 * k + 4].try_into().unwrap()))
        .collect()
}

#[test]
fn a_rig_blender_exported_reports_as_the_project_written_by_hand_from_its_raw_data() {
    // tests/data/blender/figure_blender.glb is written by Blender's own glTF exporter: keys at
    // frame / 24 s, every frame sampled, joints as empties with the parts' meshes under them.
    let source =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/blender/figure_blender.glb");
    let bytes = fs::read(&source).unwrap();
    let (json, bin) = glb_chunks(&bytes);
    let node = |name: &str| {
        json["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .position(|node| node["name"] == name)
            .unwrap()
    };
    // glTF metres, +Y up, into the project's millimetres, +Z up: (x, y, z) -> 1000 (x, -z, y).
    let to_project = nalgebra::Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
    let translation = |index: usize| {
        let t = &json["nodes"][index]["translation"];
        nalgebra::Vector3::new(
            t[0].as_f64().unwrap(),
            t[1].as_f64().unwrap(),
            t[2].as_f64().unwrap(),
        )
    };
    // Every joint hangs, unturned, under `Hips`, which is only moved.
    let hips = node("Hips");
    assert!(json["nodes"][hips].get("rotation").is_none());
    let pivot = |joint: &str| {
        let joint = node(joint);
        assert!(json["nodes"][joint].get("rotation").is_none());
        to_project * (translation(hips) + translation(joint)) * 1000.0
    };
    // The last key of the animation `name` for `joint`: its time, the joint's turn then and at
    // the first key, as extrinsic X, Y, Z Euler angles in the project's frame, and the count of
    // keys.
    let last_key = |name: &str, joint: &str| {
        let animation = json["animations"]
            .as_array()
            .unwrap()
            .iter()
            .find(|animation| animation["name"] == name)
            .unwrap();
        let joint = node(joint);
        let channel = animation["channels"]
            .as_array()
            .unwrap()
            .iter()
            .find(|channel| channel["target"]["node"] == joint)
            .unwrap();
        assert_eq!(channel["target"]["path"], "rotation");
        let sampler = &animation["samplers"][channel["sampler"].as_u64().unwrap() as usize];
        let times = floats(&json, &bin, sampler["input"].as_u64().unwrap() as usize);
        let values = floats(&json, &bin, sampler["output"].as_u64().unwrap() as usize);
        let degrees = |q: &[f32]| {
            let turn = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                f64::from(q[3]),
                f64::from(q[0]),
                f64::from(q[1]),
                f64::from(q[2]),
            ));
            let in_project = nalgebra::Rotation3::from_matrix_unchecked(
                to_project * turn.to_rotation_matrix().matrix() * to_project.transpose(),
            );
            let (x, y, z) = in_project.euler_angles();
            [x.to_degrees(), y.to_degrees(), z.to_degrees()]
        };
        (
            f64::from(*times.last().unwrap()),
            degrees(&values[values.len() - 4..]),
            degrees(&values[..4]),
            times.len(),
        )
    };
    let (wave_end, wave, wave_start, wave_keys) = last_key("Wave", "Shoulder.R");
    assert!(wave_keys > 2, "Blender samples every frame");
    let (_, reach_left, _, reach_keys) = last_key("Reach", "Shoulder.L");
    let (_, reach_right, _, _) = last_key("Reach", "Shoulder.R");
    assert_eq!(reach_keys, 1, "a single STEP key");
    let moved = |part: &str, joint: &str, [x, y, z]: [f64; 3]| {
        let p = pivot(joint);
        format!(
            "    component \"{part}\" {{\n        pivot {} {} {}\n        rotate {x} {y} {z}\n    }}\n",
            p.x, p.y, p.z
        )
    };

    let header = "units mm\nup z\nmaterial \"PLA\" density=1.24\nprint model=\"uniform\"\n";
    let rigged = format!(
        "{header}rig \"figure.glb\"\npose \"stand\" {{ stand; }}\n\
         pose \"wave\" animation=\"Wave\" time={wave_end} {{ stand; }}\n\
         pose \"wave start\" animation=\"Wave\" time=0 {{ stand; }}\n\
         pose \"reach\" animation=\"Reach\" {{ stand; }}\n"
    );
    // The rig reads its parts in its node order, which the project by hand repeats.
    let parts = ["Leg.L", "Leg.R", "Head", "Arm.L", "Arm.R", "Torso"];
    let mut by_hand = header.to_owned();
    for part in parts {
        by_hand += &format!("component \"{part}\" mesh=\"figure.glb\" node=\"{part}\"\n");
    }
    by_hand += "pose \"stand\" { stand; }\n";
    by_hand += &format!(
        "pose \"wave\" {{\n{}    stand\n}}\n",
        moved("Arm.R", "Shoulder.R", wave)
    );
    // Before the first key (at 1/24 s) the joint holds the first key's turn.
    by_hand += &format!(
        "pose \"wave start\" {{\n{}    stand\n}}\n",
        moved("Arm.R", "Shoulder.R", wave_start)
    );
    by_hand += &format!(
        "pose \"reach\" {{\n{}{}    stand\n}}\n",
        moved("Arm.L", "Shoulder.L", reach_left),
        moved("Arm.R", "Shoulder.R", reach_right)
    );

    let compile_in = |text: &str| {
        let folder = tempfile::tempdir().unwrap();
        fs::copy(&source, folder.path().join("figure.glb")).unwrap();
        let compilation = compiled(folder.path(), text).unwrap_or_else(|p| panic!("{p:#?}"));
        let report = report(folder.path(), &compilation);
        (compilation, report)
    };
    let (rig, rig_report) = compile_in(&rigged);
    let (_, hand_report) = compile_in(&by_hand);
    let names = component_names(&rig);
    assert_eq!(names, parts);
    // The waving arm moves the centre of mass.
    let com = |pose: usize| rig.poses[pose].centre_of_mass;
    assert!(
        (com(0)[0] - com(1)[0]).abs() > 0.5,
        "{:?} {:?}",
        com(0),
        com(1)
    );
    agree(&rig_report, &hand_report, "report").unwrap();
}

#[test]
fn blender_keys_of_location_and_scale_pose_the_rig_as_its_rotation_keys_do() {
    // Blender's default keying set keys location, rotation and scale; its exporter then writes a
    // translation and a scale channel beside every rotation, the scales decomposed from the
    // sampled matrices (1 or 0.99999994). They move nothing more than the rotation keys do.
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/blender");
    let project = "units mm\nup z\nmaterial \"PLA\" density=1.24\nprint model=\"uniform\"\n\
                   rig \"figure.glb\"\npose \"stand\" { stand; }\n\
                   pose \"wave\" animation=\"Wave\" time=1 { stand; }\n\
                   pose \"reach\" animation=\"Reach\" { stand; }\n\
                   pose \"kick\" animation=\"Kick\" time=0.5 { imbalance; }\n";
    let report_of = |file: &str| {
        let folder = tempfile::tempdir().unwrap();
        fs::copy(data.join(file), folder.path().join("figure.glb")).unwrap();
        let compilation = compiled(folder.path(), project).unwrap_or_else(|p| panic!("{p:#?}"));
        report(folder.path(), &compilation)
    };
    agree(
        &report_of("figure_blender_locrotscale.glb"),
        &report_of("figure_blender.glb"),
        "report",
    )
    .unwrap();
}

/// A `.gltf` file of the GLB `bytes`, its binary chunk as a data URI, with `edit` applied to its
/// JSON.
fn as_gltf(bytes: &[u8], edit: impl FnOnce(&mut serde_json::Value)) -> String {
    use base64::Engine;
    let (mut json, bin) = glb_chunks(bytes);
    json["buffers"][0]["uri"] = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bin)
    )
    .into();
    edit(&mut json);
    json.to_string()
}

#[test]
fn a_channel_moving_no_node_or_no_property_is_a_diagnostic_not_a_panic() {
    let folder = tempfile::tempdir().unwrap();
    let bytes = rig_glb(&figure(), &figure_animations());
    let first = figure_animations()[0].name;
    for (edit, said) in [
        (
            serde_json::json!({"node": 999, "path": "rotation"}),
            "node 999, which does not exist",
        ),
        (
            serde_json::json!({"node": 0, "path": "bogus"}),
            "a property glTF does not have",
        ),
    ] {
        let text = as_gltf(&bytes, |json| {
            // The last animation, which no pose below uses.
            let last = json["animations"].as_array().unwrap().len() - 1;
            json["animations"][last]["channels"][0]["target"] = edit.clone();
        });
        fs::write(folder.path().join("r.gltf"), text).unwrap();
        let source = format!("rig \"r.gltf\"\npose \"p\" animation=\"{first}\"\n");
        let refused = compiled(folder.path(), &source).expect_err("a broken channel is refused");
        assert_eq!(refused.len(), 1, "{refused:#?}");
        assert_eq!(refused[0].code.to_string(), "ballast::rig::unreadable");
        assert!(refused[0].message.contains(said), "{}", refused[0].message);
    }
}

#[test]
fn a_rig_of_thousands_of_parts_is_read_as_one_file() {
    // 2000 boxes of 4 mm in one file: each part is a component of the one mesh file, which is
    // parsed once (and its buffers looked up once), not once per part.
    let folder = tempfile::tempdir().unwrap();
    let joints: Vec<Joint> = (0..2000)
        .map(|i| {
            let name: &'static str = Box::leak(format!("part{i}").into_boxed_str());
            let at = [0.01 * (i % 50) as f32, 0.01 * (i / 50) as f32, 0.0];
            Joint::new(name, None, at, Some([[0.0; 3], [0.004; 3]]))
        })
        .collect();
    fs::write(folder.path().join("r.glb"), rig_glb(&joints, &[])).unwrap();
    let compilation = compiled(folder.path(), "rig \"r.glb\"\npose \"rest\" { stand; }\n")
        .unwrap_or_else(|problems| panic!("{problems:#?}"));
    assert_eq!(compilation.project.components.len(), 2000);
    assert_eq!(component_names(&compilation)[1999], "part1999");
}
