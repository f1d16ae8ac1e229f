//! What the optimizer makes of the project's own capsules and poses: written seeds that break a
//! rule are moved (pinned capsules are not), optimized capsules are named after where they are
//! and say which seed they came from, and a pose without goals does not steer the search.

use std::path::{Path, PathBuf};

use ballast::compile::{
    compile_with, solution_text, Compilation, CompileOptions, Failure, OptimizeOptions, Workspace,
};

/// A project file path in `examples/`, so that `meshes/t_shape.obj` resolves (nothing is
/// written: `compile_with` writes no file).
fn path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name)
}

fn compiled(source: &str, optimize: bool) -> Result<Compilation, Failure> {
    let options = CompileOptions {
        out_dir: None,
        optimize: optimize.then(OptimizeOptions::default),
        ..CompileOptions::default()
    };
    compile_with(
        source,
        &path("seeds_test.kdl"),
        &options,
        &mut Workspace::new(),
    )
}

const T: &str = r#"
ball clearance=0.2
infill 0.15
wall 1.2
component "T" mesh="meshes/t_shape.obj"
pose "upright" { stand margin=2 }
pose "on its right side" {
    rotate 0 36.8699 0
    stand margin=2
}
"#;

#[test]
fn a_pose_without_goals_leaves_the_design_unchanged() {
    let plain = format!("{T}optimize capsules=2\n");
    let shown = format!("{plain}pose \"shown\" {{ rotate 30 20 0 }}\n");
    let a = compiled(&plain, true).unwrap();
    let b = compiled(&shown, true).unwrap();
    assert_eq!(a.design, b.design);
    let objectives = |c: &Compilation| {
        c.optimization
            .as_ref()
            .unwrap()
            .candidates
            .iter()
            .map(|k| (k.capsules, k.objective))
            .collect::<Vec<_>>()
    };
    assert_eq!(objectives(&a), objectives(&b));
    // The shown pose is still evaluated and reported.
    assert_eq!(b.poses.len(), 3);
    assert!(b.poses[2].goals.is_empty());
}

/// The T with a pinned capsule in its stem and two seeds: `head` poking out of the top of the
/// bar, `crowd` overlapping the pinned one.
const SEEDED: &str = r#"
optimize capsules=3
capsule "keel" component="T" radius=3 pinned=#true {
    from -10 0 10
    to 10 0 10
}
capsule "head" component="T" radius=3 {
    from 30 0 38
    to 50 0 38
}
capsule "crowd" component="T" radius=3 {
    from -10 0 12
    to 10 0 12
}
"#;

#[test]
fn bad_seeds_are_moved_with_a_warning_each_and_check_only_warns() {
    let source = format!("{T}{SEEDED}");
    let built = compiled(&source, true).unwrap_or_else(|f| panic!("{f:?}"));
    let moved: Vec<_> = built
        .warnings
        .iter()
        .filter(|w| w.code == "ballast::capsule::seed_moved")
        .collect();
    assert_eq!(moved.len(), 2, "{:#?}", built.warnings);
    for (warning, seed) in moved.iter().zip(["head", "crowd"]) {
        assert!(!warning.is_error());
        assert!(
            warning.message.contains(&format!("seed `{seed}`")),
            "{}",
            warning.message
        );
        let span = warning.labels[0].0;
        let text = &source[span.offset()..span.offset() + span.len()];
        assert!(text.starts_with(&format!("capsule \"{seed}\"")), "{text}");
    }
    assert!(moved[0].message.contains("surface"), "{}", moved[0].message);
    assert!(moved[1].message.contains("`keel`"), "{}", moved[1].message);

    // `check` (no optimizer) reports the same seeds as warnings, and the project stays valid.
    let checked = compiled(&source, false).unwrap_or_else(|f| panic!("{f:?}"));
    let codes: Vec<&str> = checked
        .warnings
        .iter()
        .filter(|w| w.help.as_deref().is_some_and(|h| h.contains("is a seed")))
        .map(|w| w.code)
        .collect();
    assert_eq!(
        codes,
        ["ballast::capsule::overlap", "ballast::capsule::thin_wall"]
    );
}

#[test]
fn a_bad_pinned_capsule_is_still_an_error() {
    let source = format!(
        "{T}{}",
        SEEDED.replace(
            "capsule \"head\" component=\"T\" radius=3 {",
            "capsule \"head\" component=\"T\" radius=3 pinned=#true {",
        )
    );
    let Err(Failure::Invalid(problems)) = compiled(&source, true) else {
        panic!("a pinned capsule too close to the surface must make the project invalid");
    };
    let errors: Vec<&str> = problems
        .iter()
        .filter(|p| p.is_error())
        .map(|p| p.code)
        .collect();
    assert_eq!(errors, ["ballast::capsule::thin_wall"]);
}

#[test]
fn optimized_capsules_are_named_where_they_are_and_say_which_seed_they_came_from() {
    let source = format!("{T}{SEEDED}");
    let built = compiled(&source, true).unwrap();
    let names: Vec<&str> = built
        .design
        .capsules
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    assert_eq!(names, ["keel", "T 1", "T 2"]);
    let origins = &built.optimization.as_ref().unwrap().origins;
    let seeds: Vec<(&str, &str, Option<&str>)> = origins
        .iter()
        .map(|o| (o.capsule.as_str(), o.seed, o.seed_name.as_deref()))
        .collect();
    assert_eq!(
        seeds,
        [
            ("keel", "pinned", Some("keel")),
            ("T 1", "written", Some("head")),
            ("T 2", "written", Some("crowd")),
        ]
    );
    let report = ballast::compile::Report::new(&built, &path("seeds_test.kdl")).to_json();
    assert!(report.contains("\"seed_name\": \"head\""), "{report}");

    // The solution file round-trips the names: `check` reads back the same design.
    let folder = tempfile::tempdir().unwrap();
    let text = solution_text(
        &built.project,
        "seeds_test.kdl",
        &built.meshes,
        &built.design,
    );
    std::fs::write(folder.path().join("seeds_test.solution.kdl"), &text).unwrap();
    let options = CompileOptions {
        out_dir: Some(folder.path().to_path_buf()),
        optimize: None,
        ..CompileOptions::default()
    };
    let checked = compile_with(
        &source,
        &path("seeds_test.kdl"),
        &options,
        &mut Workspace::new(),
    )
    .unwrap_or_else(|f| panic!("{f:?}"));
    assert_eq!(checked.design, built.design);
}

#[test]
fn skeleton_seeds_name_their_site() {
    let built = compiled(&format!("{T}optimize capsules=2\n"), true).unwrap();
    let optimization = built.optimization.as_ref().unwrap();
    let mut names: Vec<&str> = Vec::new();
    for (capsule, origin) in built.design.capsules.iter().zip(&optimization.origins) {
        assert_eq!(origin.capsule, capsule.name);
        assert_eq!(origin.seed, "skeleton");
        let site = origin.site.unwrap();
        assert!(optimization.seeds[site].seeded);
        names.push(&capsule.name);
    }
    assert_eq!(names, ["T 1", "T 2"]);
}
