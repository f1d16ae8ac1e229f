//! A mutation fuzzer for the front end (project text -> parse, check, resolve -> diagnostics
//! drawn) and the solution reader, on stable Rust within a time budget: `BALLAST_FUZZ_SECONDS`
//! (20 by default; `.ci/run` gives it more). Inputs grow from the examples, the diagnostic cases
//! and the hostile files that once broke the front end; mutations insert, repeat, delete and
//! splice the tokens that matter to the lexer. Every input must give its problems without a
//! panic and within a second or two; the input being read is written to
//! `fuzz-front-end-input.kdl` in the test's temporary folder first, so one that aborts the process
//! (a stack overflow) is kept. Every crash found becomes a case in `tests/front_end_limits.rs`.

use std::path::Path;
use std::time::{Duration, Instant};

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

/// xorshift64*: reproducible from its seed, independent of the platform.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
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
    let budget = std::env::var("BALLAST_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20.0);
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
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let start = Instant::now();
    let (mut runs, mut slowest) = (0usize, Duration::ZERO);
    let mut slow = Vec::new();
    while start.elapsed().as_secs_f64() < budget {
        // The seeds themselves first, then mutations of mutations.
        let input = if runs < seeds.len() {
            seeds[runs].clone()
        } else {
            let base = &seeds[rng.below(seeds.len())];
            let once = mutate(&mut rng, base, &seeds);
            if rng.below(3) == 0 {
                mutate(&mut rng, &once, &seeds)
            } else {
                once
            }
        };
        std::fs::write(&kept, &input).unwrap();
        let took = Instant::now();
        let parsed = parse_project(&input, &project_path);
        let drawn = render_plain(&parsed.problems, "fuzz.kdl", &input);
        let solution = parse_solution(&input, Path::new("fuzz.solution.kdl"), &project);
        let drawn_solution = render_plain(&solution.problems, "fuzz.solution.kdl", &input);
        let took = took.elapsed();
        assert_eq!(
            parsed.project.is_some(),
            !parsed.problems.iter().any(|p| p.is_error())
        );
        assert!(
            drawn.len() + drawn_solution.len() < 4 << 20,
            "{} bytes drawn",
            drawn.len()
        );
        slowest = slowest.max(took);
        if took > Duration::from_secs(3) {
            slow.push(format!("{took:?}: {:?}", &input[..boundary(&input, 300)]));
        }
        runs += 1;
    }
    eprintln!(
        "{runs} inputs in {:?}, the slowest {slowest:?}",
        start.elapsed()
    );
    assert!(runs > seeds.len(), "the budget did not cover the seeds");
    assert!(slow.is_empty(), "slow inputs:\n{}", slow.join("\n"));
}
