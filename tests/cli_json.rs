//! `--message-format json` and `check --json` on an invalid project: diagnostics as JSON objects
//! on standard output, with spans that point at the right text.

mod cli_support;

use std::fs;
use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use cli_support::{ballast, scratch_folder, stderr, stdout, ARM};
use serde_json::Value;

/// A project in a fresh folder, with the example mesh next to it.
fn scratch_project(text: &str) -> (tempfile::TempDir, PathBuf) {
    let (folder, project) = scratch_folder("", &["hinged_arm.obj"]);
    fs::write(&project, text).unwrap();
    (folder, project)
}

/// Every line of `text` as a JSON value; panics on a line that is not one.
fn json_lines(text: &str) -> Vec<Value> {
    text.lines()
        .map(|line| {
            serde_json::from_str(line).unwrap_or_else(|e| panic!("not JSON ({e}): {line:?}"))
        })
        .collect()
}

/// The diagnostic with `code` among `lines`.
fn find<'a>(lines: &'a [Value], code: &str) -> &'a Value {
    lines
        .iter()
        .find(|d| d["code"] == code)
        .unwrap_or_else(|| panic!("no {code} among {lines:?}"))
}

/// The 1-based line and column (in characters) of the first `needle` in `text`, found line by line.
fn position_of(text: &str, needle: &str) -> (usize, usize) {
    for (index, line) in text.split('\n').enumerate() {
        if let Some(byte) = line.find(needle) {
            return (index + 1, line[..byte].chars().count() + 1);
        }
    }
    panic!("{needle} is not in the text");
}

/// The broken arm project: a misspelt goal (`stnad`), with a non-ASCII comment before it so that
/// columns in characters and in bytes differ.
fn broken() -> String {
    ARM.replace(
        "pose \"out\" { stand }",
        "/* bras articulé */ pose \"out\" { stnad }",
    )
}

/// The checks every diagnostic object must pass against the `text` its spans point into.
fn assert_well_formed(diagnostic: &Value, file: &str, text: &str) {
    assert_eq!(diagnostic["reason"], "diagnostic");
    assert!(diagnostic["code"]
        .as_str()
        .unwrap()
        .starts_with("ballast::"));
    assert!(["error", "warning"].contains(&diagnostic["severity"].as_str().unwrap()));
    assert!(!diagnostic["message"].as_str().unwrap().is_empty());
    assert_eq!(diagnostic["file"], file);
    assert!(diagnostic["help"].is_null() || diagnostic["help"].is_string());
    // The drawing wraps long messages; it names the code on one line.
    assert!(diagnostic["rendered"]
        .as_str()
        .unwrap()
        .contains(diagnostic["code"].as_str().unwrap()));
    let labels = diagnostic["labels"].as_array().unwrap();
    assert_eq!(diagnostic["span"].is_null(), labels.is_empty());
    if let Some(first) = labels.first() {
        assert_eq!(&diagnostic["span"], first);
        assert_eq!(first["primary"], true);
    }
    for label in labels {
        let start = label["byte_start"].as_u64().unwrap() as usize;
        let end = label["byte_end"].as_u64().unwrap() as usize;
        assert!(start <= end && end <= text.len(), "{label}");
        // The span's own text may occur earlier; only check when this is its first occurrence.
        let spanned = &text[start..end];
        let one_line = !spanned.is_empty() && !spanned.contains('\n');
        if one_line && text.find(spanned) == Some(start) {
            let (line, column) = position_of(text, spanned);
            assert_eq!(label["line_start"], line, "{label}");
            assert_eq!(label["column_start"], column, "{label}");
        }
    }
}

#[test]
fn check_prints_one_json_object_per_diagnostic_on_stdout() {
    let text = broken();
    let (_folder, project) = scratch_project(&text);
    let path = project.to_str().unwrap();
    let output = ballast(&["check", path, "--message-format", "json"]);
    assert_eq!(output.status.code(), Some(2));
    let lines = json_lines(&stdout(&output));
    assert!(!lines.is_empty());
    for diagnostic in &lines {
        assert_well_formed(diagnostic, path, &text);
    }
    let unknown = find(&lines, "ballast::unknown_node");
    assert_eq!(unknown["severity"], "error");
    assert!(unknown["help"]
        .as_str()
        .unwrap()
        .contains("did you mean `stand`?"));
    let span = &unknown["span"];
    let (start, end) = (
        span["byte_start"].as_u64().unwrap() as usize,
        span["byte_end"].as_u64().unwrap() as usize,
    );
    assert_eq!(&text[start..end], "stnad");
    // `é` is two bytes and one column.
    let (line, column) = position_of(&text, "stnad");
    assert_eq!(
        (span["line_start"].clone(), span["column_start"].clone()),
        (line.into(), column.into())
    );
    assert_eq!(span["line_end"], line);
    assert_eq!(span["column_end"], column + 5);
    let byte_in_line = text
        .split('\n')
        .nth(line - 1)
        .unwrap()
        .find("stnad")
        .unwrap();
    assert_eq!(column, byte_in_line, "one two-byte character before it");
    // Nothing drawn for people on stdout; the summary line is on stderr.
    assert!(stderr(&output).contains("is invalid"));
    assert!(!stderr(&output).contains("did you mean"));
}

#[test]
fn check_json_on_an_invalid_project_prints_the_diagnostics_as_a_document() {
    let text = broken();
    let (_folder, project) = scratch_project(&text);
    let path = project.to_str().unwrap();
    let output = ballast(&["check", path, "--json"]);
    assert_eq!(output.status.code(), Some(2));
    let document: Value = serde_json::from_str(&stdout(&output)).expect("one JSON document");
    assert_eq!(document["valid"], false);
    assert_eq!(document["file"], path);
    let diagnostics = document["diagnostics"].as_array().unwrap();
    for diagnostic in diagnostics {
        assert_well_formed(diagnostic, path, &text);
    }
    find(diagnostics, "ballast::unknown_node");
    // People still get the drawing on stderr.
    assert!(stderr(&output).contains("did you mean `stand`?"));

    // With JSON diagnostics too: the lines, then the document on one more line.
    let output = ballast(&["check", path, "--json", "--message-format", "json"]);
    let lines = json_lines(&stdout(&output));
    let (last, diagnostics) = lines.split_last().unwrap();
    assert_eq!(last["valid"], false);
    assert_eq!(last["diagnostics"].as_array().unwrap(), diagnostics);
}

#[test]
fn warnings_of_a_valid_project_are_json_and_the_table_goes_to_stderr() {
    let text = format!(
        "{ARM}\ncapsule \"weight\" component=\"base\" radius=5 {{\n    from -10 0 10\n    to 10 0 10\n}}\n"
    );
    let (_folder, project) = scratch_project(&text);
    let path = project.to_str().unwrap();
    let output = ballast(&["check", path, "--message-format", "json"]);
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    let lines = json_lines(&stdout(&output));
    let warning = find(&lines, "ballast::capsule::undetermined");
    assert_eq!(warning["severity"], "warning");
    assert_well_formed(warning, path, &text);
    assert!(stderr(&output).contains("undetermined (axis too close to horizontal)"));

    // And `check --json`: the diagnostics, then the report, each on one line.
    let output = ballast(&["check", path, "--json", "--message-format", "json"]);
    let lines = json_lines(&stdout(&output));
    let report = lines.last().unwrap();
    assert_eq!(report["all_goals_met"], true);
    find(&lines, "ballast::capsule::undetermined");
}

#[test]
fn a_missing_project_is_a_diagnostic_without_a_span() {
    let output = ballast(&[
        "check",
        "/nonexistent/ballast/project.kdl",
        "--message-format",
        "json",
    ]);
    assert_eq!(output.status.code(), Some(2));
    let lines = json_lines(&stdout(&output));
    assert_eq!(lines.len(), 1);
    assert_eq!(lines[0]["code"], "ballast::file::unreadable");
    assert!(lines[0]["span"].is_null());
    assert_eq!(lines[0]["file"], "/nonexistent/ballast/project.kdl");
}

#[test]
fn build_prints_json_diagnostics_and_writes_nothing() {
    let (folder, project) = scratch_project(&broken());
    let output = ballast(&[
        "build",
        project.to_str().unwrap(),
        "--message-format",
        "json",
    ]);
    assert_eq!(output.status.code(), Some(2));
    find(&json_lines(&stdout(&output)), "ballast::unknown_node");
    assert!(!folder.path().join("build").exists());

    // A good build: standard output holds no line that is not JSON.
    fs::write(&project, ARM).unwrap();
    let output = ballast(&[
        "build",
        project.to_str().unwrap(),
        "--message-format",
        "json",
    ]);
    assert_eq!(output.status.code(), Some(0), "stderr: {}", stderr(&output));
    json_lines(&stdout(&output));
    assert!(stderr(&output).contains("wrote "));
}

#[test]
fn watch_prints_json_diagnostics() {
    let (_folder, project) = scratch_project(&broken());
    let mut child = Command::new(env!("CARGO_BIN_EXE_ballast"))
        .args([
            "watch",
            project.to_str().unwrap(),
            "--message-format",
            "json",
        ])
        .env("NO_COLOR", "1")
        .env("BALLAST_CACHE_DIR", "off")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("the ballast binary starts");
    let (lines, received) = mpsc::channel();
    let out = child.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            if lines.send(line).is_err() {
                break;
            }
        }
    });
    let line = received.recv_timeout(Duration::from_secs(120));
    let _ = child.kill();
    let _ = child.wait();
    let line = line.expect("watch printed a line within two minutes");
    let diagnostic: Value = serde_json::from_str(&line).expect("the first stdout line is JSON");
    assert_eq!(diagnostic["reason"], "diagnostic");
}
