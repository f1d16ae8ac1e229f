//! Printing diagnostics: graphical with colour on a terminal, plain when piped or `NO_COLOR` is set,
//! or as JSON objects for editors and pipelines (`--message-format json`).

use std::io::IsTerminal;

use miette::{GraphicalReportHandler, GraphicalTheme, Severity};
use serde::Serialize;

use crate::diagnostic::{render, render_plain, Problem};

/// Renders `problems` against the project `source` for standard error.
pub fn render_for_terminal(problems: &[Problem], source_name: &str, source: &str) -> String {
    let colour = std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none();
    if !colour {
        return render_plain(problems, source_name, source);
    }
    let handler = GraphicalReportHandler::new_themed(GraphicalTheme::unicode());
    render(&handler, problems, source_name, source)
}

/// One diagnostic as `--message-format json` prints it: one object per line, after cargo's
/// convention. Spans point into `file` (the project file unless the problem names another).
#[derive(Debug, Serialize)]
pub struct JsonDiagnostic {
    /// Always `diagnostic`, so a reader can tell these lines from others.
    pub reason: &'static str,
    /// The stable code, e.g. `ballast::pose::unknown_component`.
    pub code: &'static str,
    /// `error` or `warning`.
    pub severity: &'static str,
    /// What is wrong, in one line.
    pub message: String,
    /// The file the spans point into, as named on the command line.
    pub file: String,
    /// The primary span (the first label's), or `null` when the problem points nowhere.
    pub span: Option<JsonSpan>,
    /// Every labelled span, the primary one first.
    pub labels: Vec<JsonSpan>,
    /// How to fix it, or `null`.
    pub help: Option<String>,
    /// The diagnostic as the plain text rendering draws it.
    pub rendered: String,
}

/// A span of source: byte offsets, and 1-based lines and columns (columns count characters).
#[derive(Debug, Serialize)]
pub struct JsonSpan {
    /// The label's text (may be empty).
    pub label: String,
    /// Whether this is the problem's primary span.
    pub primary: bool,
    /// Offset of the first byte.
    pub byte_start: usize,
    /// Offset one past the last byte.
    pub byte_end: usize,
    /// Line of the first byte.
    pub line_start: usize,
    /// Column of the first byte.
    pub column_start: usize,
    /// Line of the end of the span.
    pub line_end: usize,
    /// Column of the end of the span (one past its last character).
    pub column_end: usize,
}

impl JsonDiagnostic {
    /// `problem` against the project `source` named `source_name` (or against its own file).
    pub fn new(problem: &Problem, source_name: &str, source: &str) -> JsonDiagnostic {
        let (file, text): (&str, &str) = match &problem.file {
            Some(file) => (&file.name, &file.text),
            None => (source_name, source),
        };
        let labels: Vec<JsonSpan> = problem
            .labels
            .iter()
            .enumerate()
            .map(|(index, (span, label))| {
                let start = span.offset();
                let end = start.saturating_add(span.len());
                let (line_start, column_start) = line_column(text, start);
                let (line_end, column_end) = line_column(text, end);
                JsonSpan {
                    label: label.clone(),
                    primary: index == 0,
                    byte_start: start,
                    byte_end: end,
                    line_start,
                    column_start,
                    line_end,
                    column_end,
                }
            })
            .collect();
        let span = labels.first().map(|primary| JsonSpan {
            label: primary.label.clone(),
            ..*primary
        });
        JsonDiagnostic {
            reason: "diagnostic",
            code: problem.code,
            severity: match problem.severity {
                Severity::Error => "error",
                Severity::Warning => "warning",
                Severity::Advice => "advice",
            },
            message: problem.message.clone(),
            file: file.to_owned(),
            span,
            labels,
            help: problem.help.clone(),
            rendered: render_plain(std::slice::from_ref(problem), source_name, source),
        }
    }

    /// The diagnostic as one line of JSON (no newline).
    pub fn to_line(&self) -> String {
        serde_json::to_string(self).expect("a diagnostic is plain data")
    }
}

/// Every problem as one line of JSON each, newline-terminated.
pub fn render_json_lines(problems: &[Problem], source_name: &str, source: &str) -> String {
    problems
        .iter()
        .map(|problem| JsonDiagnostic::new(problem, source_name, source).to_line() + "\n")
        .collect()
}

/// The 1-based line and column (in characters) of byte `offset` in `text`; an offset past the end
/// or inside a character counts from the character boundary before it.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |newline| newline + 1);
    (line, before[line_start..].chars().count() + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_and_columns_are_one_based_and_count_characters() {
        let text = "ab\nçd\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 2), (1, 3));
        assert_eq!(line_column(text, 3), (2, 1));
        // `ç` is two bytes: `d` is the second character of line 2.
        assert_eq!(line_column(text, 5), (2, 2));
        // Inside `ç`, and past the end.
        assert_eq!(line_column(text, 4), (2, 1));
        assert_eq!(line_column(text, 99), (3, 1));
    }
}
