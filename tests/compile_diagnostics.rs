//! Snapshots of the problems found after parsing: meshes that cannot be used and capsules that
//! cannot be printed where they are.
//!
//! Each `tests/data/compile/err/<case>.kdl` has a `<case>.txt` with the rendered diagnostics. Run
//! with `BALLAST_BLESS=1` to rewrite the snapshots after an intended change.

use std::path::{Path, PathBuf};

use ballast::compile::compile;
use ballast::diagnostic::render_plain;

fn cases() -> Vec<PathBuf> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/compile/err");
    let mut cases: Vec<PathBuf> = std::fs::read_dir(folder)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "kdl"))
        .collect();
    cases.sort();
    cases
}

fn render(case: &Path) -> (Vec<&'static str>, String) {
    let source = std::fs::read_to_string(case).unwrap();
    let problems = match compile(&source, case) {
        Ok(_) => panic!("{} compiled without errors", case.display()),
        Err(problems) => problems,
    };
    let name = case.file_name().unwrap().to_string_lossy().into_owned();
    let codes = problems.iter().map(|problem| problem.code).collect();
    (codes, render_plain(&problems, &name, &source))
}

#[test]
fn every_case_matches_its_snapshot() {
    let cases = cases();
    assert!(cases.len() >= 3, "found only {} cases", cases.len());
    let bless = std::env::var_os("BALLAST_BLESS").is_some();
    let mut mismatches = Vec::new();
    for case in &cases {
        let (_, rendered) = render(case);
        let snapshot = case.with_extension("txt");
        if bless {
            std::fs::write(&snapshot, &rendered).unwrap();
            continue;
        }
        let expected = std::fs::read_to_string(&snapshot).unwrap_or_default();
        if expected != rendered {
            mismatches.push(format!(
                "{}:\n--- expected\n{expected}\n--- got\n{rendered}",
                case.display()
            ));
        }
    }
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
}

#[test]
fn every_mesh_problem_is_reported_at_once() {
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/compile/err/meshes.kdl");
    let (codes, _) = render(&case);
    assert_eq!(
        codes,
        [
            "ballast::mesh::not_found",
            "ballast::mesh::unreadable",
            "ballast::mesh::open",
            "ballast::mesh::inverted",
            "ballast::mesh::flipped",
            "ballast::mesh::degenerate",
            "ballast::mesh::unreadable",
            "ballast::mesh::unknown_part",
            "ballast::mesh::crossing",
            "ballast::mesh::nested_shells",
            "ballast::mesh::not_finite",
            "ballast::mesh::outside_project",
            "ballast::mesh::short_face",
        ]
    );
}

#[test]
fn every_capsule_problem_is_reported_at_once() {
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/compile/err/capsules.kdl");
    let (codes, _) = render(&case);
    for code in [
        "ballast::capsule::overlap",
        "ballast::capsule::thin_wall",
        "ballast::capsule::outside",
        "ballast::capsule::too_short",
        "ballast::capsule::no_ball",
    ] {
        assert!(codes.contains(&code), "{code} missing from {codes:?}");
    }
}

#[test]
fn a_capsule_in_the_wrong_component_names_the_right_one() {
    let case =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/compile/err/wrong_component.kdl");
    let (codes, rendered) = render(&case);
    assert_eq!(codes, ["ballast::capsule::wrong_component"]);
    assert!(rendered.contains("write component=\"base\""), "{rendered}");
}
