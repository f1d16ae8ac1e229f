//! A project's insertion plan, through the driver and into the report: a vertical capsule in a
//! 20 mm box printed along +z (declared) on PrusaSlicer's default layers (0.35 mm, then 0.3 mm),
//! its ball of any size (the capsule radius less the clearance).

use std::path::Path;

use ballast::compile::{compile, Report};

const PROJECT: &str = r#"
component "box" mesh="meshes/box.obj" {
    print { down 0 0 -1 }
}
wall 1
ball clearance=0.2 any-size=#true
pose "rest" { stand }
capsule "weight" component="box" radius=4 {
    from 10 10 6
    to 10 10 14
}
"#;

#[test]
fn a_vertical_capsule_gets_one_pause_in_the_middle_of_its_window() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/compile/err/insertion.kdl");
    let compilation = compile(PROJECT, &path).expect("compiles");
    // The ball (3.8) tops out at 6 − 4 + 7.6 = 9.6 on the void's smooth end; one layer (0.3)
    // for the stepped floor and the pause clearance (0.2) put the window's low end at 10.1. The
    // opening closes at 14 + 0.2. The layer tops in [10.1, 14.2] are those of layers 34 (10.25)
    // to 47 (14.15); the middle is layer 40, whose top is 0.35 + 39 × 0.3 = 12.05.
    let report: serde_json::Value =
        serde_json::from_str(&Report::new(&compilation, &path).to_json()).unwrap();
    let plan = &report["insertion"][0];
    assert_eq!(plan["component"], "box");
    assert_eq!(plan["up"], serde_json::json!([0.0, 0.0, 1.0]));
    let window = plan["capsules"][0]["window"].as_array().unwrap();
    assert!(
        (window[0].as_f64().unwrap() - 10.1).abs() < 1e-9,
        "{window:?}"
    );
    assert!(
        (window[1].as_f64().unwrap() - 14.2).abs() < 1e-9,
        "{window:?}"
    );
    assert_eq!(plan["capsules"][0]["pause"], 0);
    let bridge = plan["capsules"][0]["ceiling_bridge"].as_f64().unwrap();
    assert!((bridge - 4.0 * 2f64.sqrt()).abs() < 1e-9);
    let pauses = plan["pauses"].as_array().unwrap();
    assert_eq!(pauses.len(), 1);
    assert_eq!(pauses[0]["layers_done"], 40);
    assert!((pauses[0]["height"].as_f64().unwrap() - 12.05).abs() < 1e-9);
    assert!((pauses[0]["resume_height"].as_f64().unwrap() - 12.35).abs() < 1e-9);
    assert_eq!(pauses[0]["capsules"], serde_json::json!(["weight"]));
    assert_eq!(
        pauses[0]["message"],
        "Insert one 7.6 mm steel ball into capsule `weight`"
    );
    // A 5.66 mm ceiling is within the bridge limit: no warning.
    assert!(compilation
        .warnings
        .iter()
        .all(|w| w.code != "ballast::capsule::ceiling_bridge"));
}

#[test]
fn a_wide_void_warns_about_its_ceiling() {
    // The same box read in centimetres (20 cm), the capsule 0.75 cm wide: a ceiling of
    // √2 × 0.75 = 1.0607 cm, past the 10 mm limit. The message gives both units.
    let wide = format!(
        "units \"cm\"\n{}",
        PROJECT
            .replace("wall 1", "wall 0.1")
            .replace("clearance=0.2", "clearance=0.02")
            .replace("radius=4", "radius=0.75")
    );
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/compile/err/insertion.kdl");
    let compilation = compile(&wide, &path).expect("compiles");
    let warning = compilation
        .warnings
        .iter()
        .find(|w| w.code == "ballast::capsule::ceiling_bridge")
        .expect("a ceiling warning");
    assert!(!warning.is_error());
    assert!(
        warning.message.contains("1.0607 cm (10.61 mm)"),
        "{}",
        warning.message
    );
    // The pause message names the ball in centimetres and millimetres: 2 × (0.75 − 0.02).
    let pause = &compilation.print_plan.components[0].pauses[0];
    assert_eq!(
        pause.message,
        "Insert one 1.46 cm (14.6 mm) steel ball into capsule `weight`"
    );
}

/// The box with one capsule of radius `radius` along x, `print` and `ball` as given.
fn lying(print: &str, ball: &str, radius: f64) -> String {
    format!(
        r#"
component "box" mesh="meshes/box.obj" {{
    {print}
}}
wall 1
{ball}
pose "rest" {{ stand }}
capsule "weight" component="box" radius={radius} {{
    from 6 10 10
    to 14 10 10
}}
"#
    )
}

#[test]
fn a_written_capsule_chooses_the_facet_that_lets_its_ball_in() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/compile/err/insertion.kdl");
    let any = "ball clearance=0.2 any-size=#true";
    // Printed on its bottom face, the axis along x does not rise: no window, and a warning.
    let flat = compile(&lying("print { down 0 0 -1 }", any, 4.0), &path).expect("compiles");
    assert!(flat
        .warnings
        .iter()
        .any(|w| w.code == "ballast::capsule::no_insertion_window"));
    assert_eq!(flat.print_plan.components[0].capsules[0].pause, None);
    // Left to choose among the cube's six equal faces, ballast stands it on one across x, where
    // the axis rises 8 along the print direction: the ball goes in.
    let chosen = compile(&lying("", any, 4.0), &path).expect("compiles");
    assert!(
        chosen.orientations[0].down.x.abs() > 0.999_999,
        "{:?}",
        chosen.orientations[0].down
    );
    assert!(chosen
        .warnings
        .iter()
        .all(|w| w.code != "ballast::capsule::no_insertion_window"));
    assert_eq!(chosen.print_plan.components[0].capsules[0].pause, Some(0));
}

#[test]
fn a_radius_far_from_every_listed_ball_warns_of_the_gap() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/compile/err/insertion.kdl");
    let listed = "ball clearance=0.2 {\n    diameters 6 8\n}";
    let gap = |radius: f64| {
        compile(&lying("", listed, radius), &path)
            .expect("compiles")
            .warnings
            .into_iter()
            .filter(|w| w.code == "ballast::capsule::ball_gap")
            .collect::<Vec<_>>()
    };
    // Radius 4.2 holds the 8 mm ball with exactly the clearance.
    assert!(gap(4.2).is_empty());
    // 4.7 still holds only the 8 mm ball: 0.7 between ball and wall, 0.5 beyond the clearance,
    // just at the limit.
    assert!(gap(4.7).is_empty());
    // 4.75 leaves 0.55 beyond the clearance: a warning, with the snug radius in its help.
    let warnings = gap(4.75);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let text = format!("{:?}", warnings[0]);
    assert!(text.contains("0.55 mm more than the clearance"), "{text}");
    assert!(
        text.contains("a radius of 4.2 mm holds the 8 mm ball"),
        "{text}"
    );
}
