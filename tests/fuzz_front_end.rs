//! A mutation fuzzer for the front end (project text -> parse, check, resolve -> diagnostics
//! drawn) and the solution reader, on stable Rust within a time budget: `BALLAST_FUZZ_SECONDS`
//! (20 by default; `.ci/run` gives it more). Inputs grow from the examples, the diagnostic cases
//! and the hostile files that once broke the front end; mutations insert, repeat, delete and
//! splice the tokens that matter to the lexer. Every input must give its problems without a
//! panic and within a second or two; the input being read is written to
//! `fuzz-front-end-input.kdl` in the test's temporary folder first, so one that aborts the process
//! (a stack overflow) is kept. Every crash found becomes a case in `tests/front_end_limits.rs`.

mod fuzz_support;

use std::path::Path;
use std::time::Duration;

use fuzz_support::{budget, campaign, Rng};

use ballast::diagnostic::render_plain;
use ballast::spec::{parse_project, parse_solution};

/// Tokens that change how the text is lexed.
const TOKENS: &[&str] = &[
    "{",
    "}",
    "\"",
    "#\"",
    "\"#",
    "##\"",
    "\"\"\"\n",
    "/-",
    "/*",
    "*/",
    "//",
    ";",
    "=",
    "(",
    ")",
    "\\",
    "\\\n",
    "\\u{2028}",
    "\\q",
    "\n",
    "\r\n",
    "\u{2028}",
    "\u{2029}",
    "\u{85}",
    "\u{0B}",
    "\u{0C}",
    "\u{A0}",
    "\u{3000}",
    "\u{200E}",
    "\u{FEFF}",
    "\u{0}",
    " ",
    "\t",
    "#true",
    "true",
    "#null",
    "#inf",
    "#nan",
    "1e200",
    "-1e308",
    "2.",
    "0x",
    "1_000",
    "(mm)",
    "pose",
    "component",
    "capsule",
    "stand",
    "margin=",
    "optimize",
    "grid-cell=",
    "capsules=",
    "output",
    "gltf \"\"",
    "a",
    "é",
    "9999999999999999999999999",
];

/// The hostile files of the issue that made this fuzzer, besides the examples.
fn hostile() -> Vec<String> {
    let deep = "a{".repeat(25_000) + &"}".repeat(25_000);
    vec![
        format!("//\u{2028}{deep}"),
        format!("\"{deep}"),
        format!("\"\n{deep}"),
        format!("units mm\nwall 1\n{}wall \"x\"\n", " ".repeat(70_000)),
        "\"".repeat(50_000),
        "/-\u{A0}".repeat(2000),
        "wall 1;".repeat(3000),
        "optimize grid-cell=0.001 capsules=1000\n".to_owned(),
        "capsule \"c\" component=\"T\" radius=1 pinned=true { from 0 0 1e200; to 0 0 -1e200 }\n"
            .to_owned(),
        "pose \"p\" { stand margin=2. }\n/* open\n".to_owned(),
        "output { gltf \"\" }\n".to_owned(),
    ]
}

/// Every seed: the examples, the project and solution cases of the diagnostic tests, the hostile
/// files.
fn seeds() -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut seeds = Vec::new();
    for folder in [
        "examples",
        "tests/data/spec/err",
        "tests/data/spec/solution_err",
    ] {
        let Ok(entries) = std::fs::read_dir(root.join(folder)) else {
            continue;
        };
        let mut paths: Vec<_> = entries.map(|e| e.unwrap().path()).collect();
        paths.sort();
        for path in paths {
            if path.extension().is_some_and(|e| e == "kdl") {
                seeds.push(String::from_utf8_lossy(&std::fs::read(path).unwrap()).into_owned());
            }
        }
    }
    seeds.extend(hostile());
    seeds
}

/// The char boundary at or before `at`.
fn boundary(text: &str, at: usize) -> usize {
    let mut at = at.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

/// One to four mutations of `text`, keeping it under 64 KiB.
fn mutate(rng: &mut Rng, text: &str, seeds: &[String]) -> String {
    let mut text = text.to_owned();
    for _ in 0..1 + rng.below(4) {
        let at = boundary(&text, rng.below(text.len() + 1));
        match rng.below(6) {
            0 | 1 => text.insert_str(at, TOKENS[rng.below(TOKENS.len())]),
            2 => {
                let token = TOKENS[rng.below(TOKENS.len())];
                let times = [2, 10, 40, 300, 3000][rng.below(5)];
                text.insert_str(at, &token.repeat(times));
            }
            3 => {
                let end = boundary(&text, at + rng.below(64));
                text.replace_range(at..end, "");
            }
            4 => {
                let end = boundary(&text, at + rng.below(32));
                let piece = text[at..end].repeat(1 + rng.below(200));
                text.insert_str(at, &piece);
            }
            _ => {
                let other = &seeds[rng.below(seeds.len())];
                let from = boundary(other, rng.below(other.len() + 1));
                let to = boundary(other, from + rng.below(400));
                text.insert_str(at, &other[from..to]);
            }
        }
        if text.len() > 64 << 10 {
            text.truncate(boundary(&text, 64 << 10));
        }
    }
    text
}

#[test]
fn the_front_end_survives_mutated_projects_and_solutions() {
    let seeds = seeds();
    let project_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/t_shape.kdl");
    let project = parse_project(&seeds[0], &project_path)
        .project
        .or_else(|| {
            let text = std::fs::read_to_string(&project_path).unwrap();
            parse_project(&text, &project_path).project
        })
        .unwrap();
    let kept = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-front-end-input.kdl");
    let mut rng = Rng::from_env();
    // Mutations, and now and then mutations of mutations.
    let mutate = |rng: &mut Rng, base: &String, seeds: &[String]| {
        let once = mutate(rng, base, seeds);
        if rng.below(3) == 0 {
            mutate(rng, &once, seeds)
        } else {
            once
        }
    };
    let done = campaign(&seeds, budget(20.0), &mut rng, mutate, |input| {
        std::fs::write(&kept, input).unwrap();
        let parsed = parse_project(input, &project_path);
        let drawn = render_plain(&parsed.problems, "fuzz.kdl", input);
        let solution = parse_solution(input, Path::new("fuzz.solution.kdl"), &project);
        let drawn_solution = render_plain(&solution.problems, "fuzz.solution.kdl", input);
        assert_eq!(
            parsed.project.is_some(),
            !parsed.problems.iter().any(|p| p.is_error())
        );
        assert!(
            drawn.len() + drawn_solution.len() < 4 << 20,
            "{} bytes drawn",
            drawn.len()
        );
        false
    });
    let (slowest, input) = &done.slowest;
    eprintln!(
        "{} inputs in {:?}, the slowest {slowest:?}",
        done.runs, done.elapsed
    );
    assert!(
        done.runs > seeds.len(),
        "the budget did not cover the seeds"
    );
    let input = input.as_deref().unwrap_or_default();
    assert!(
        *slowest <= Duration::from_secs(3),
        "a slow input ({slowest:?}): {:?}",
        &input[..boundary(input, 300)]
    );
}
