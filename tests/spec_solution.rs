//! Solution files: the optimizer's capsules read back against their project, with the project
//! file's grammar, units and component names.

use std::path::Path;

use ballast::spec::model::{Capsule, Project, Spanned};
use ballast::spec::{codes, parse_project, parse_solution};
use nalgebra::Point3;

/// A project in `units` with components `body` and `arm`, and `infill`.
fn project(units: &str, infill: &str) -> Project {
    let source = format!(
        "units {units}\n{infill}\ncomponent \"body\" mesh=\"b.obj\"\ncomponent \"arm\" mesh=\"a.obj\"\npose \"p\" {{ stand }}\noptimize"
    );
    let parsed = parse_project(&source, Path::new("/projects/teddy.kdl"));
    assert!(parsed.problems.is_empty(), "{:#?}", parsed.problems);
    parsed.project.unwrap()
}

fn span() -> miette::SourceSpan {
    (0, 0).into()
}

fn capsule(name: &str, component: usize, from: [f64; 3], to: [f64; 3], radius: f64) -> Capsule {
    Capsule {
        name: Spanned::new(name.to_owned(), span()),
        component: Spanned::new(component, span()),
        from: Point3::from(from),
        to: Point3::from(to),
        radius,
        pinned: false,
        span: span(),
    }
}

const SOLUTION: &str = r#"// Written by ballast for teddy.kdl.
infill 0.25

capsule "nose" component="body" radius=4 pinned=#true {
    from 0 30 5
    to 0 36 5
}
/- capsule "discarded" component="arm" radius=1 {
    from 0 0 0
    to 0 0 1
}
capsule "keel" component="arm" radius=(cm)0.55 pinned=#false {
    from 0 -18 7.5
    to (in)1 21 8
}
"#;

#[test]
fn a_solution_reads_back_as_its_capsules() {
    let project = project("mm", "infill min=0.2 max=0.6");
    let parsed = parse_solution(SOLUTION, Path::new("teddy.solution.kdl"), &project);
    assert!(parsed.problems.is_empty(), "{:#?}", parsed.problems);
    let mut nose = capsule("nose", 0, [0.0, 30.0, 5.0], [0.0, 36.0, 5.0], 4.0);
    nose.pinned = true;
    let keel = capsule("keel", 1, [0.0, -18.0, 7.5], [25.4, 21.0, 8.0], 5.5);
    let capsules = parsed.capsules.unwrap();
    assert_eq!(capsules.len(), 2);
    assert_eq!(capsules[0], nose);
    assert_eq!(capsules[1].name, keel.name);
    assert_eq!(capsules[1].component, keel.component);
    assert!((capsules[1].radius - 5.5).abs() < 1e-12);
    assert!((capsules[1].to - keel.to).norm() < 1e-12);
    assert!(!capsules[1].pinned);
    assert_eq!(parsed.infill, Some(0.25));
}

#[test]
fn spans_point_into_the_solution_file() {
    let project = project("mm", "infill min=0.2 max=0.6");
    let parsed = parse_solution(SOLUTION, Path::new("teddy.solution.kdl"), &project);
    let capsules = parsed.capsules.unwrap();
    let text = |span: miette::SourceSpan| &SOLUTION[span.offset()..span.offset() + span.len()];
    assert_eq!(text(capsules[0].name.span), "\"nose\"");
    assert_eq!(text(capsules[1].component.span), "\"arm\"");
    assert!(text(capsules[1].span).starts_with("capsule \"keel\""));
}

#[test]
fn lengths_convert_to_the_project_units() {
    let project = project("cm", "");
    let source = "capsule \"c\" component=\"body\" radius=(mm)5 {\n from 0 0 1\n to 0 0 (mm)30\n}";
    let parsed = parse_solution(source, Path::new("s.kdl"), &project);
    let capsules = parsed.capsules.unwrap();
    assert!((capsules[0].radius - 0.5).abs() < 1e-12);
    assert!((capsules[0].from.z - 1.0).abs() < 1e-12);
    assert!((capsules[0].to.z - 3.0).abs() < 1e-12);
    assert_eq!(parsed.infill, None);
}

#[test]
fn an_empty_solution_has_no_capsules() {
    let project = project("mm", "");
    for source in ["", "// nothing yet\n", "/- capsule \"c\""] {
        let parsed = parse_solution(source, Path::new("s.kdl"), &project);
        assert!(parsed.problems.is_empty(), "{:#?}", parsed.problems);
        assert_eq!(parsed.capsules, Some(Vec::new()));
        assert_eq!(parsed.infill, None);
    }
}

#[test]
fn a_fixed_infill_may_only_be_repeated() {
    let project = project("mm", "infill 0.3");
    let same = parse_solution("infill 0.3", Path::new("s.kdl"), &project);
    assert!(same.problems.is_empty(), "{:#?}", same.problems);
    assert_eq!(same.infill, Some(0.3));
    let other = parse_solution("infill 0.5", Path::new("s.kdl"), &project);
    let found: Vec<(&str, &str)> = other
        .problems
        .iter()
        .map(|problem| (problem.code, problem.message.as_str()))
        .collect();
    assert_eq!(
        found,
        [(
            codes::SOLUTION_INFILL,
            "the project fixes the infill at 0.3, but the solution chooses 0.5"
        )]
    );
    assert_eq!(other.capsules, None);
    assert_eq!(other.infill, None);
}

#[test]
fn an_infill_range_admits_its_ends() {
    let project = project("mm", "infill min=0.2 max=0.6");
    for (text, fraction) in [("infill 0.2", 0.2), ("infill 0.6", 0.6)] {
        let parsed = parse_solution(text, Path::new("s.kdl"), &project);
        assert!(parsed.problems.is_empty(), "{:#?}", parsed.problems);
        assert_eq!(parsed.infill, Some(fraction));
    }
    let below = parse_solution("infill 0.1", Path::new("s.kdl"), &project);
    assert_eq!(below.problems[0].code, codes::SOLUTION_INFILL);
}

#[test]
fn unknown_components_get_a_did_you_mean() {
    let project = project("mm", "");
    let source = "capsule \"c\" component=\"amr\" radius=2 {\n from 0 0 0\n to 0 0 5\n}";
    let parsed = parse_solution(source, Path::new("s.kdl"), &project);
    assert_eq!(parsed.capsules, None);
    assert_eq!(parsed.problems.len(), 1);
    assert_eq!(parsed.problems[0].code, codes::UNKNOWN_COMPONENT);
    assert_eq!(
        parsed.problems[0].help.as_deref(),
        Some("did you mean `arm`?")
    );
}

#[test]
fn project_nodes_do_not_belong_in_a_solution() {
    let project = project("mm", "");
    let parsed = parse_solution("pose \"p\" { stand }\nwall 2", Path::new("s.kdl"), &project);
    let found: Vec<&str> = parsed.problems.iter().map(|p| p.code).collect();
    assert_eq!(found, [codes::UNKNOWN_NODE, codes::UNKNOWN_NODE]);
    assert_eq!(
        parsed.problems[0].help.as_deref(),
        Some("allowed at the top level: `capsule` and `infill`")
    );
}

/// Every prefix of a valid solution, and the solution with bytes replaced, reads without a
/// panic, and capsules come back exactly when there is no error.
#[test]
fn truncated_and_mangled_solutions_never_panic() {
    let project = project("mm", "infill min=0.2 max=0.6");
    let mut texts: Vec<String> = (0..=SOLUTION.len())
        .filter(|&end| SOLUTION.is_char_boundary(end))
        .map(|end| SOLUTION[..end].to_owned())
        .collect();
    for (at, _) in SOLUTION.char_indices() {
        for replacement in ["{", "}", "\"", "=", "#", "/-", "(mm)", "-", ".", "\u{0}"] {
            let mut text = SOLUTION.to_owned();
            let end = at + text[at..].chars().next().map_or(0, char::len_utf8);
            text.replace_range(at..end, replacement);
            texts.push(text);
        }
    }
    texts.push("infill 99999999999999999999999999999999999999999".to_owned());
    texts.push("capsule".repeat(1000));
    texts.push(" ".repeat(1 << 20));
    for text in &texts {
        let parsed = parse_solution(text, Path::new("s.kdl"), &project);
        let has_error = parsed.problems.iter().any(|problem| problem.is_error());
        assert_eq!(parsed.capsules.is_some(), !has_error, "{text}");
        if has_error {
            assert_eq!(parsed.infill, None);
        }
        let _ = ballast::diagnostic::render_plain(&parsed.problems, "s.kdl", text);
    }
}

#[test]
fn an_unreadable_solution_file_has_its_own_code_apart_from_the_project_files() {
    let folder = tempfile::tempdir().unwrap();
    // Not UTF-8: the file is there but cannot be read as text.
    let bytes = b"capsule \"a\" \xff\xfe\n";
    let solution = folder.path().join("teddy.solution.kdl");
    std::fs::write(&solution, bytes).unwrap();
    let project = project("mm", "");
    // No component: no print direction to check insertion along.
    let print = ballast::fabrication::PrintSetup::from_rotations(
        &[],
        ballast::compile::layer_grid(&project),
    );
    let problems = ballast::compile::read_solution(&project, &solution, &[], &print)
        .expect_err("an unreadable solution file is an error");
    assert_eq!(problems.len(), 1, "{problems:#?}");
    assert_eq!(problems[0].code, codes::SOLUTION_UNREADABLE);
    assert_eq!(problems[0].code, "ballast::solution::unreadable");
    assert!(
        problems[0]
            .message
            .contains("cannot read the solution file"),
        "{}",
        problems[0].message
    );

    let project_file = folder.path().join("teddy.kdl");
    std::fs::write(&project_file, bytes).unwrap();
    let problem = ballast::spec::read_source(&project_file, "project file")
        .expect_err("an unreadable project file is an error");
    assert_eq!(problem.code, "ballast::file::unreadable");
}
