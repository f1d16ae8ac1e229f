//! One problem found in a project, pointed at its source span: the unit every stage reports in.
//!
//! Stages collect a `Vec<Problem>` and keep going, so the user sees every mistake at once. A
//! [`Problem`] is a [`miette::Diagnostic`]; the driver attaches the project source when rendering.

use std::fmt;
use std::sync::Arc;

use miette::{
    GraphicalReportHandler, GraphicalTheme, LabeledSpan, NamedSource, Severity, SourceSpan,
};

/// A diagnostic: a stable code, a one-line message, labelled spans and an optional hint.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Stable machine-readable code, e.g. `ballast::pose::unknown_component`.
    pub code: &'static str,
    /// Error (the project is invalid) or warning (it is valid but suspicious).
    pub severity: Severity,
    /// What is wrong, in one line.
    pub message: String,
    /// The places in the source the problem concerns; the first is the primary one.
    pub labels: Vec<(SourceSpan, String)>,
    /// How to fix it, when there is something useful to say.
    pub help: Option<String>,
    /// The file the spans point into, when it is not the project file (a solution file).
    pub file: Option<SourceFile>,
}

/// A file other than the project file, which a problem's spans point into.
#[derive(Debug, Clone, PartialEq)]
pub struct SourceFile {
    /// Its name, as shown in the output.
    pub name: String,
    /// Its text.
    pub text: std::sync::Arc<str>,
}

impl Problem {
    /// An error with `code` and `message` and no labels yet.
    pub fn error(code: &'static str, message: impl Into<String>) -> Problem {
        Problem {
            code,
            severity: Severity::Error,
            message: message.into(),
            labels: Vec::new(),
            help: None,
            file: None,
        }
    }

    /// A warning with `code` and `message` and no labels yet.
    pub fn warning(code: &'static str, message: impl Into<String>) -> Problem {
        Problem {
            severity: Severity::Warning,
            ..Problem::error(code, message)
        }
    }

    /// Adds a labelled span.
    pub fn with_label(mut self, span: SourceSpan, label: impl Into<String>) -> Problem {
        self.labels.push((span, label.into()));
        self
    }

    /// Sets the hint.
    pub fn with_help(mut self, help: impl Into<String>) -> Problem {
        self.help = Some(help.into());
        self
    }

    /// Says that the spans point into `file` rather than the project file.
    pub fn in_file(mut self, file: SourceFile) -> Problem {
        self.file = Some(file);
        self
    }

    /// Whether this problem makes the project invalid.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Problem {}

impl miette::Diagnostic for Problem {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new(self.code))
    }

    fn severity(&self) -> Option<Severity> {
        Some(self.severity)
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help
            .as_ref()
            .map(|help| Box::new(help) as Box<dyn fmt::Display>)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        if self.labels.is_empty() {
            return None;
        }
        Some(Box::new(self.labels.iter().enumerate().map(
            |(index, (span, label))| {
                let text = (!label.is_empty()).then(|| label.clone());
                if index == 0 {
                    LabeledSpan::new_primary_with_span(text, *span)
                } else {
                    LabeledSpan::new_with_span(text, *span)
                }
            },
        )))
    }
}

/// Width, in columns, of the text [`render_plain`] produces.
const PLAIN_WIDTH: usize = 100;

/// Renders `problems` against `source` (named `source_name` in the output) as plain Unicode text
/// without colours, at a fixed width: for piped output and snapshot tests.
pub fn render_plain(problems: &[Problem], source_name: &str, source: &str) -> String {
    let handler = GraphicalReportHandler::new_themed(GraphicalTheme::unicode_nocolor())
        .with_width(PLAIN_WIDTH)
        .with_links(false);
    render(&handler, problems, source_name, source)
}

/// The most problems [`render`] draws; a line at the end counts the others.
pub const MAX_RENDERED_PROBLEMS: usize = 50;
/// The longest line [`render`] draws (in characters) with its source: a problem on a longer
/// line (or whose drawing would hold more than [`MAX_DRAWN_BYTES`]) is shown by its line and
/// column instead, so a long line is never printed once per problem.
pub const MAX_DRAWN_LINE: usize = 400;
/// The most source text one problem's drawing may hold.
pub const MAX_DRAWN_BYTES: usize = 8 << 10;

/// Renders `problems` against `source` (named `source_name` in the output), or against their own
/// [`file`](Problem::file) when they have one, with `handler`, a blank line between problems.
/// At most [`MAX_RENDERED_PROBLEMS`] are drawn, each within [`MAX_DRAWN_BYTES`] of source.
pub fn render(
    handler: &GraphicalReportHandler,
    problems: &[Problem],
    source_name: &str,
    source: &str,
) -> String {
    let project: Arc<str> = Arc::from(drawable_source(source));
    let mut out = String::new();
    for (index, problem) in problems.iter().take(MAX_RENDERED_PROBLEMS).enumerate() {
        if index > 0 {
            out.push('\n');
        }
        let problem = &printable_problem(problem);
        let (name, text) = match &problem.file {
            Some(file) => (file.name.as_str(), file.text.clone()),
            None => (source_name, project.clone()),
        };
        if !drawable(problem, &text) {
            out.push_str(&located(problem, name, &text));
            continue;
        }
        let named = NamedSource::new(name, text.clone());
        let report = miette::Report::new(problem.clone()).with_source_code(named);
        let mut rendered = String::new();
        if handler
            .render_report(&mut rendered, report.as_ref())
            .is_err()
        {
            // A span outside the source cannot be drawn; the message still can.
            rendered = located(problem, name, &text);
        }
        out.push_str(&rendered);
    }
    if problems.len() > MAX_RENDERED_PROBLEMS {
        let errors = problems[MAX_RENDERED_PROBLEMS..]
            .iter()
            .filter(|p| p.is_error())
            .count();
        out.push_str(&format!(
            "\n... and {} more problems ({errors} of them errors) were left out: at most \
             {MAX_RENDERED_PROBLEMS} are shown (docs/limits.md); fix these and check again\n",
            problems.len() - MAX_RENDERED_PROBLEMS
        ));
    }
    out
}

/// Whether `problem`'s labels lie in `text` on lines short enough to draw, with their context
/// lines, within [`MAX_DRAWN_BYTES`].
fn drawable(problem: &Problem, text: &str) -> bool {
    let mut drawn = 0usize;
    for (span, _) in &problem.labels {
        let (start, end) = (span.offset(), span.offset() + span.len());
        if end > text.len() || !text.is_char_boundary(start) || !text.is_char_boundary(end) {
            return false;
        }
        // The labelled lines and one line either side (miette's context).
        let first = text[..start].rfind('\n').map_or(0, |at| at + 1);
        let before = text[..first.saturating_sub(1)]
            .rfind('\n')
            .map_or(0, |at| at + 1);
        let last = text[end..].find('\n').map_or(text.len(), |at| end + at);
        let after = text[(last + 1).min(text.len())..]
            .find('\n')
            .map_or(text.len(), |at| last + 1 + at);
        let lines = &text[before..after];
        drawn += lines.len();
        if drawn > MAX_DRAWN_BYTES
            || lines
                .split([
                    '\n', '\r', '\u{2028}', '\u{2029}', '\u{85}', '\u{0B}', '\u{0C}',
                ])
                .any(|line| line.chars().count() > MAX_DRAWN_LINE)
        {
            return false;
        }
    }
    true
}

/// `problem` without its source drawn: its code, message, each label's line and column, and
/// its hint.
fn located(problem: &Problem, name: &str, text: &str) -> String {
    let mut out = format!("{}\n\n  × {}\n", problem.code, problem.message);
    for (span, label) in &problem.labels {
        let offset = span.offset().min(text.len());
        let before = text.get(..offset).unwrap_or("");
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        out.push_str(&format!("  at {name}:{line}:{column}"));
        if !label.is_empty() {
            out.push_str(&format!(": {label}"));
        }
        out.push('\n');
    }
    if let Some(help) = &problem.help {
        out.push_str(&format!("  help: {help}\n"));
    }
    out
}

/// `problem` with its message, labels, help, file name and file text fit for a terminal: the
/// texts through [`printable`], the file's text through [`drawable_source`] (names and text a
/// file supplied, such as a calibration file's, may hold escape sequences).
fn printable_problem(problem: &Problem) -> Problem {
    let mut problem = problem.clone();
    problem.message = printable(&problem.message).into_owned();
    problem.help = problem.help.map(|help| printable(&help).into_owned());
    for (_, label) in &mut problem.labels {
        *label = printable(label).into_owned();
    }
    if let Some(file) = &mut problem.file {
        file.name = printable(&file.name).into_owned();
        file.text = Arc::from(drawable_source(&file.text));
    }
    problem
}

/// `text` with every control character but line ends and tabs replaced by `?` of the same length
/// in bytes, so spans into it still hold and none of it drives the terminal.
pub fn drawable_source(text: &str) -> std::borrow::Cow<'_, str> {
    let unsafe_char = |c: char| c.is_control() && !matches!(c, '\n' | '\r' | '\t');
    if !text.chars().any(unsafe_char) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if unsafe_char(c) {
            out.extend(std::iter::repeat_n('?', c.len_utf8()));
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

/// `text` from a file (a G-code object label or `M117` message, a component name from a
/// calibration file), fit to print on a terminal: every control character (C0, line ends and
/// tabs included, DEL and C1, so ESC and the escape sequences it starts) is written as a
/// visible escape such as `\u{1b}`, so no file can move the cursor, clear the screen or set the
/// terminal's title. Borrowed when there is nothing to replace.
pub fn printable(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.chars().any(char::is_control) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    std::borrow::Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::printable;

    #[test]
    fn control_characters_are_printed_as_escapes() {
        assert!(matches!(
            printable("keel «ü» 8 mm"),
            std::borrow::Cow::Borrowed("keel «ü» 8 mm")
        ));
        assert_eq!(
            printable("\u{1b}]0;title\u{7}T\u{1b}[31m"),
            "\\u{1b}]0;title\\u{7}T\\u{1b}[31m"
        );
        assert_eq!(
            printable("a\tb\nc\r\u{7f}\u{9b}2J"),
            "a\\u{9}b\\u{a}c\\u{d}\\u{7f}\\u{9b}2J"
        );
    }
}
