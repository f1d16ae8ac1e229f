//! The front end on broken project files: every mistake reported at once, with the right code, at
//! the right span. Each `tests/data/spec/err/<case>.kdl` has its rendering in `<case>.txt`; run
//! with `BALLAST_BLESS=1` to rewrite those files after a deliberate change.

use std::path::{Path, PathBuf};

use ballast::diagnostic::{render_plain, Problem};
use ballast::spec::{parse_project, parse_solution};

const ERR: &str = "tests/data/spec/err";

/// Every case and the codes of its problems, in the order they are reported.
const CASES: &[(&str, &[&str])] = &[
    (
        "annotation",
        &["ballast::annotation", "ballast::annotation"],
    ),
    (
        "argument_count",
        &[
            "ballast::argument_count",
            "ballast::argument_count",
            "ballast::argument_count",
            "ballast::argument_count",
            "ballast::argument_count",
            "ballast::argument_count",
            "ballast::argument_count",
        ],
    ),
    (
        "print_orientation",
        &[
            "ballast::component::zero_down",
            "ballast::component::down_with_rotate",
        ],
    ),
    (
        "conflicting_properties",
        &["ballast::conflicting_properties"],
    ),
    (
        "duplicate_name",
        &[
            "ballast::duplicate_name",
            "ballast::duplicate_name",
            "ballast::duplicate_name",
            "ballast::duplicate_name",
        ],
    ),
    (
        "duplicate_node",
        &[
            "ballast::duplicate_node",
            "ballast::duplicate_node",
            "ballast::duplicate_node",
            "ballast::duplicate_node",
        ],
    ),
    (
        "duplicate_property",
        &["ballast::duplicate_property", "ballast::duplicate_property"],
    ),
    ("empty", &["ballast::missing_node", "ballast::missing_node"]),
    ("infill", &["ballast::out_of_range"]),
    ("infill_half_range", &["ballast::missing_property"]),
    ("infill_inverted", &["ballast::out_of_range"]),
    ("infill_range", &["ballast::out_of_range"]),
    (
        "many_mistakes",
        &[
            "ballast::unknown_keyword",
            "ballast::unknown_node",
            "ballast::wrong_type",
            "ballast::out_of_range",
            "ballast::missing_property",
            "ballast::unit",
            "ballast::conflicting_properties",
            "ballast::duplicate_name",
            "ballast::unknown_property",
            "ballast::argument_count",
            "ballast::unknown_component",
            "ballast::unit",
            "ballast::wrong_type",
            "ballast::duplicate_name",
            "ballast::missing_property",
            "ballast::missing_node",
            "ballast::unknown_component",
            "ballast::out_of_range",
        ],
    ),
    (
        "missing_node",
        &[
            "ballast::missing_node",
            "ballast::missing_node",
            "ballast::missing_node",
        ],
    ),
    (
        "missing_property",
        &[
            "ballast::missing_property",
            "ballast::missing_property",
            "ballast::missing_property",
            "ballast::missing_property",
            "ballast::missing_property",
        ],
    ),
    (
        "no_component_no_pose",
        &["ballast::missing_node", "ballast::missing_node"],
    ),
    (
        "not_finite",
        &[
            "ballast::not_finite",
            "ballast::not_finite",
            "ballast::not_finite",
            "ballast::not_finite",
            "ballast::not_finite",
        ],
    ),
    (
        "optimize",
        &[
            "ballast::wrong_type",
            "ballast::out_of_range",
            "ballast::wrong_type",
            "ballast::out_of_range",
            "ballast::unknown_property",
        ],
    ),
    (
        "pinned",
        &[
            "ballast::wrong_type",
            "ballast::wrong_type",
            "ballast::unknown_property",
            "ballast::unit",
        ],
    ),
    ("too_few_capsules", &["ballast::optimize::too_few_capsules"]),
    (
        "out_of_range",
        &[
            "ballast::out_of_range",
            "ballast::out_of_range",
            "ballast::out_of_range",
            "ballast::out_of_range",
            "ballast::out_of_range",
            "ballast::out_of_range",
            "ballast::out_of_range",
            "ballast::out_of_range",
            "ballast::out_of_range",
            "ballast::out_of_range",
            "ballast::out_of_range",
        ],
    ),
    ("syntax_binary", &["ballast::syntax"; 3]),
    ("syntax_too_deep", &["ballast::syntax"]),
    ("syntax_unclosed", &["ballast::syntax"; 4]),
    ("syntax_unmatched_close", &["ballast::syntax"]),
    ("syntax_big_integer", &["ballast::syntax"]),
    ("syntax_float", &["ballast::syntax"]),
    ("syntax_unterminated_string", &["ballast::syntax"]),
    (
        "unexpected_children",
        &[
            "ballast::unexpected_children",
            "ballast::unexpected_children",
            "ballast::unexpected_children",
        ],
    ),
    (
        "unit",
        &[
            "ballast::unit",
            "ballast::unit",
            "ballast::unit",
            "ballast::unit",
            "ballast::unit",
            "ballast::unit",
        ],
    ),
    (
        "unknown_component",
        &[
            "ballast::unknown_component",
            "ballast::unknown_component",
            "ballast::unknown_component",
        ],
    ),
    (
        "unknown_keyword",
        &["ballast::unknown_keyword", "ballast::unknown_keyword"],
    ),
    (
        "unknown_keyword_far",
        &["ballast::unknown_keyword", "ballast::unknown_keyword"],
    ),
    (
        "unknown_node",
        &[
            "ballast::unknown_node",
            "ballast::unknown_node",
            "ballast::unknown_node",
            "ballast::unknown_node",
            "ballast::unknown_node",
        ],
    ),
    (
        "unknown_property",
        &[
            "ballast::unknown_property",
            "ballast::unknown_property",
            "ballast::unknown_property",
            "ballast::unknown_property",
            "ballast::unknown_property",
        ],
    ),
    (
        "wrong_type",
        &[
            "ballast::wrong_type",
            "ballast::wrong_type",
            "ballast::wrong_type",
            "ballast::wrong_type",
            "ballast::wrong_type",
            "ballast::wrong_type",
            "ballast::wrong_type",
            "ballast::wrong_type",
        ],
    ),
];

/// The text of a case: files are read as bytes so that binary garbage reaches the parser too.
fn source(case: &str) -> String {
    let bytes = std::fs::read(Path::new(ERR).join(format!("{case}.kdl"))).unwrap();
    String::from_utf8_lossy(&bytes).into_owned()
}

/// Parses one case, checks its codes and returns a description of any mismatch.
fn check(case: &str, expected_codes: &[&str]) -> Option<String> {
    let source = source(case);
    let parsed = parse_project(&source, Path::new("project.kdl"));
    let returned = parsed.project.is_some().then_some("a project");
    mismatches(
        ERR,
        case,
        &source,
        &parsed.problems,
        expected_codes,
        returned,
    )
}

/// What is wrong with the `problems` found in case `case` of `folder` (its text `source`): a
/// result `returned` despite errors, codes other than `expected_codes`, a rendering other than
/// the snapshot `<case>.txt` (written instead with `BALLAST_BLESS` set). `None` when all agree.
fn mismatches(
    folder: &str,
    case: &str,
    source: &str,
    problems: &[Problem],
    expected_codes: &[&str],
    returned: Option<&str>,
) -> Option<String> {
    let mut failures = Vec::new();
    if let Some(what) = returned {
        failures.push(format!("{what} was returned despite errors"));
    }
    let codes: Vec<&str> = problems.iter().map(|problem| problem.code).collect();
    if codes != expected_codes {
        failures.push(format!("codes {codes:?}, expected {expected_codes:?}"));
    }
    let rendered = render_plain(problems, &format!("{case}.kdl"), source);
    let snapshot = PathBuf::from(folder).join(format!("{case}.txt"));
    if std::env::var_os("BALLAST_BLESS").is_some() {
        std::fs::write(&snapshot, &rendered).unwrap();
    } else {
        match std::fs::read_to_string(&snapshot) {
            Ok(expected) if expected == rendered => {}
            Ok(_) => failures.push(format!(
                "rendering differs from {}:\n{rendered}",
                snapshot.display()
            )),
            Err(_) => failures.push(format!("{} is missing", snapshot.display())),
        }
    }
    (!failures.is_empty()).then(|| format!("{case}: {}", failures.join("\n")))
}

/// Asserts that every file in `folder` is a case of `cases` (the table named `table`).
fn assert_every_file_is_a_case(folder: &str, cases: &[(&str, &[&str])], table: &str) {
    for entry in std::fs::read_dir(folder).unwrap() {
        let path = entry.unwrap().path();
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        assert!(
            cases.iter().any(|(case, _)| *case == stem),
            "{} has no entry in {table}",
            path.display()
        );
    }
}

#[test]
fn every_case_matches_its_codes_and_snapshot() {
    let failures: Vec<String> = CASES
        .iter()
        .filter_map(|(case, codes)| check(case, codes))
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn every_file_is_a_case() {
    assert_every_file_is_a_case(ERR, CASES, "CASES");
}

#[test]
fn every_code_is_exercised() {
    use ballast::spec::codes::*;
    for code in [
        SYNTAX,
        UNKNOWN_NODE,
        UNKNOWN_PROPERTY,
        ARGUMENT_COUNT,
        WRONG_TYPE,
        NOT_FINITE,
        OUT_OF_RANGE,
        UNKNOWN_KEYWORD,
        MISSING_PROPERTY,
        MISSING_NODE,
        DUPLICATE_NODE,
        DUPLICATE_PROPERTY,
        UNEXPECTED_CHILDREN,
        ANNOTATION,
        UNIT,
        DUPLICATE_NAME,
        UNKNOWN_COMPONENT,
        CONFLICTING_PROPERTIES,
        ZERO_PRINT_DOWN,
        PRINT_DOWN_WITH_ROTATE,
        TOO_FEW_CAPSULES,
        SOLUTION_INFILL,
    ] {
        assert!(
            CASES
                .iter()
                .chain(SOLUTION_CASES)
                .any(|(_, codes)| codes.contains(&code)),
            "no case reports {code}"
        );
    }
}

/// Every prefix of a valid file, and the file with each byte replaced, reads without a panic, and
/// a project comes back exactly when there is no error.
#[test]
fn truncated_and_mangled_files_never_panic() {
    let source = std::fs::read_to_string("tests/data/spec/ok/full.kdl").unwrap();
    let project_path = Path::new("project.kdl");
    let mut texts: Vec<String> = (0..=source.len())
        .filter(|&end| source.is_char_boundary(end))
        .map(|end| source[..end].to_owned())
        .collect();
    for (at, _) in source.char_indices().step_by(3) {
        for replacement in ["{", "}", "\"", "=", "#", "/-", "(mm)", "\u{0}", "é"] {
            let mut text = source.clone();
            let end = at + text[at..].chars().next().map_or(0, char::len_utf8);
            text.replace_range(at..end, replacement);
            texts.push(text);
        }
    }
    for text in &texts {
        let parsed = parse_project(text, project_path);
        let has_error = parsed.problems.iter().any(|problem| problem.is_error());
        assert_eq!(parsed.project.is_some(), !has_error, "{text}");
        let _ = render_plain(&parsed.problems, "project.kdl", text);
    }
}

#[test]
fn hostile_inputs_are_refused_without_crashing() {
    let deep = "a {".repeat(10_000);
    let closers = "}".repeat(10_000);
    let chain = "/- ".repeat(10_000) + "a";
    let comment = format!("/*{}*/", "* /* ".repeat(10_000));
    let garbage = "= ) ( ".repeat(10_000);
    let huge_number = format!("wall {}", "9".repeat(400));
    let too_long = " ".repeat(1 << 20);
    for text in [
        &deep,
        &closers,
        &chain,
        &comment,
        &garbage,
        &huge_number,
        &too_long,
    ] {
        let parsed = parse_project(text, Path::new("project.kdl"));
        assert!(parsed.project.is_none());
        assert!(!parsed.problems.is_empty());
    }
}

/// The problems of a one-component, one-pose project with `extra` appended, as (code, message,
/// help).
fn problems_with(extra: &str) -> Vec<(&'static str, String, Option<String>)> {
    let source = format!("component \"body\" mesh=\"b.obj\"\npose \"p\" {{ stand }}\n{extra}");
    let parsed = parse_project(&source, Path::new("project.kdl"));
    assert!(parsed.project.is_none() || parsed.problems.is_empty());
    parsed
        .problems
        .into_iter()
        .map(|problem| (problem.code, problem.message, problem.help))
        .collect()
}

#[test]
fn whole_numbers_are_whole_and_not_negative() {
    use ballast::spec::codes::*;
    let cases: &[(&str, &str, &str, Option<&str>)] = &[
        (
            "capsules=1.5",
            WRONG_TYPE,
            "expected a whole number, found 1.5",
            Some("write a whole number, such as `1` or `2`"),
        ),
        (
            "capsules=3.0",
            WRONG_TYPE,
            "expected a whole number, found 3.0",
            Some("write it without a decimal point: `3`"),
        ),
        (
            "capsules=-0.0",
            WRONG_TYPE,
            "expected a whole number, found -0.0",
            Some("write it without a decimal point: `0`"),
        ),
        (
            "capsules=-1",
            OUT_OF_RANGE,
            "`capsules` must be zero or more, found -1",
            None,
        ),
        (
            "capsules=-0.5",
            WRONG_TYPE,
            "expected a whole number, found -0.5",
            Some("write a whole number, zero or more"),
        ),
        (
            "capsules=\"3\"",
            WRONG_TYPE,
            "expected a whole number, found a string",
            Some("remove the quotes: `3`"),
        ),
        (
            "capsules=#inf",
            NOT_FINITE,
            "`capsules` must be a whole number",
            None,
        ),
        (
            "seed=18446744073709551616",
            OUT_OF_RANGE,
            "`seed` must be at most 18446744073709551615, found 18446744073709551616",
            None,
        ),
        (
            "seed=#true",
            WRONG_TYPE,
            "expected a whole number, found `#true`",
            None,
        ),
        (
            "seed=(mm)2",
            UNIT,
            "`seed` is not a length, so it takes no unit",
            Some("remove the annotation"),
        ),
        (
            "tolerance=-1",
            OUT_OF_RANGE,
            "`tolerance` must be zero or more, found -1",
            None,
        ),
        (
            "grid-cell=-0.5",
            OUT_OF_RANGE,
            "`grid-cell` must be greater than zero, found -0.5",
            None,
        ),
        (
            "seeds=1",
            UNKNOWN_PROPERTY,
            "unknown property `seeds` on `optimize`",
            Some("did you mean `seed`?"),
        ),
    ];
    for (written, code, message, help) in cases {
        let expected = vec![(*code, message.to_string(), help.map(str::to_owned))];
        assert_eq!(
            problems_with(&format!("optimize {written}")),
            expected,
            "{written}"
        );
    }
}

#[test]
fn optimize_takes_no_arguments_and_appears_once() {
    use ballast::spec::codes::*;
    let codes = |extra: &str| -> Vec<&str> {
        problems_with(extra)
            .into_iter()
            .map(|(code, ..)| code)
            .collect()
    };
    assert_eq!(codes("optimize 3"), [ARGUMENT_COUNT]);
    assert_eq!(codes("optimize\noptimize"), [DUPLICATE_NODE]);
    assert_eq!(codes("optimize { capsules 3 }"), [UNEXPECTED_CHILDREN]);
}

#[test]
fn pinned_is_a_boolean() {
    use ballast::spec::codes::*;
    let capsule = |pinned: &str| {
        problems_with(&format!(
            "capsule \"c\" component=\"body\" radius=2 {pinned} {{\n from 0 0 0\n to 0 0 5\n}}"
        ))
    };
    let wrong = |found: &str, help: &str| {
        vec![(
            WRONG_TYPE,
            format!("expected `#true` or `#false`, found {found}"),
            Some(help.to_owned()),
        )]
    };
    assert_eq!(capsule("pinned=#true"), []);
    assert_eq!(capsule("pinned=#false"), []);
    assert_eq!(
        capsule("pinned=\"yes\""),
        wrong("a string", "write `#true`")
    );
    assert_eq!(
        capsule("pinned=\"false\""),
        wrong("a string", "write `#false`")
    );
    assert_eq!(capsule("pinned=0"), wrong("a number", "write `#false`"));
    assert_eq!(
        capsule("pinned=#null"),
        wrong("`#null`", "write `#true` or `#false`")
    );
    assert_eq!(
        capsule("pinnd=#true"),
        vec![(
            UNKNOWN_PROPERTY,
            "unknown property `pinnd` on `capsule`".to_owned(),
            Some("did you mean `pinned`?".to_owned()),
        )]
    );
}

const SOLUTION_ERR: &str = "tests/data/spec/solution_err";

/// The project the solution cases belong to: components `body` and `arm`, an infill range.
const SOLUTION_PROJECT: &str = r#"
component "body" mesh="body.obj"
component "arm" mesh="arm.obj"
pose "rest" { stand }
infill min=0.2 max=0.6
optimize
"#;

/// Every solution case and the codes of its problems, in the order they are reported.
const SOLUTION_CASES: &[(&str, &[&str])] = &[
    ("infill", &["ballast::solution::infill"]),
    ("infill_more_than_solid", &["ballast::out_of_range"]),
    (
        "nodes",
        &[
            "ballast::unknown_node",
            "ballast::unknown_node",
            "ballast::unknown_property",
            "ballast::duplicate_node",
            "ballast::missing_node",
            "ballast::wrong_type",
            "ballast::unknown_node",
            "ballast::duplicate_name",
            "ballast::wrong_type",
            "ballast::unit",
        ],
    ),
    ("syntax", &["ballast::syntax"; 2]),
    (
        "unknown_component",
        &["ballast::unknown_component", "ballast::unknown_component"],
    ),
];

/// Parses one solution case, checks its codes and snapshot, and describes any mismatch.
fn check_solution(case: &str, expected_codes: &[&str]) -> Option<String> {
    let project = parse_project(SOLUTION_PROJECT, Path::new("project.kdl"))
        .project
        .expect("the solution cases' project is valid");
    let path = Path::new(SOLUTION_ERR).join(format!("{case}.kdl"));
    let source = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
    let parsed = parse_solution(&source, &path, &project);
    let returned = (parsed.capsules.is_some() || parsed.infill.is_some()).then_some("a solution");
    mismatches(
        SOLUTION_ERR,
        case,
        &source,
        &parsed.problems,
        expected_codes,
        returned,
    )
}

#[test]
fn every_solution_case_matches_its_codes_and_snapshot() {
    let failures: Vec<String> = SOLUTION_CASES
        .iter()
        .filter_map(|(case, codes)| check_solution(case, codes))
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn every_solution_file_is_a_case() {
    assert_every_file_is_a_case(SOLUTION_ERR, SOLUTION_CASES, "SOLUTION_CASES");
}
