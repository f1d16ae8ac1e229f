//! Meshes a slicer prints though they are not clean solids: shells that cross a little are taken
//! as their union with a warning that says how much they overlap; shells that overlap much are
//! refused with that measure.

use std::fs;

use ballast::compile::compile;

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
        Ok(compiled) => (listed(&compiled.warnings), true),
        Err(problems) => (listed(&problems), false),
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
fn shells_that_overlap_much_are_refused_with_the_measure() {
    let obj = boxes(&[
        ([0.0, 0.0, 0.0], [40.0, 30.0, 20.0]),
        ([20.0, 12.0, 0.0], [60.0, 42.0, 20.0]),
    ]);
    let (problems, compiled) = problems(&obj);
    assert!(!compiled);
    let (_, message) = problems
        .iter()
        .find(|(code, _)| code == "ballast::mesh::self_intersecting")
        .unwrap_or_else(|| panic!("{problems:#?}"));
    // 7,200 of 40,800 mm³ in common: 17.6 %.
    assert!(message.contains("overlap by 17."), "{message}");
    assert!(message.contains("more than the 0.10 %"), "{message}");
}
