//! One problem found in a project, pointed at its source span: the unit every stage reports in.
//!
//! Stages collect a `Vec<Problem>` and keep going, so the user sees every mistake at once. A
//! [`Problem`] is a [`miette::Diagnostic`]; the driver attaches the project source when rendering.

use std::fmt;

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

/// Renders `problems` against `source` (named `source_name` in the output), or against their own
/// [`file`](Problem::file) when they have one, with `handler`, a blank line between problems.
pub fn render(
    handler: &GraphicalReportHandler,
    problems: &[Problem],
    source_name: &str,
    source: &str,
) -> String {
    let mut out = String::new();
    for (index, problem) in problems.iter().enumerate() {
        if index > 0 {
            out.push('\n');
        }
        let named = match &problem.file {
            Some(file) => NamedSource::new(&file.name, file.text.to_string()),
            None => NamedSource::new(source_name, source.to_owned()),
        };
        let report = miette::Report::new(problem.clone()).with_source_code(named);
        let mut rendered = String::new();
        if handler
            .render_report(&mut rendered, report.as_ref())
            .is_err()
        {
            // A span outside the source cannot be drawn; the message still can.
            rendered = format!("{}: {}\n", problem.code, problem.message);
        }
        out.push_str(&rendered);
    }
    out
}
