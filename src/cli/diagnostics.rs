//! Printing diagnostics: graphical with colour on a terminal, plain when piped or `NO_COLOR` is set.

use std::io::IsTerminal;

use miette::{GraphicalReportHandler, GraphicalTheme, NamedSource};

use crate::diagnostic::{render_plain, Problem};

/// Renders `problems` against the project `source` for standard error.
pub fn render(problems: &[Problem], source_name: &str, source: &str) -> String {
    let colour = std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none();
    if !colour {
        return render_plain(problems, source_name, source);
    }
    let handler = GraphicalReportHandler::new_themed(GraphicalTheme::unicode());
    let mut out = String::new();
    for problem in problems {
        let report = miette::Report::new(problem.clone())
            .with_source_code(NamedSource::new(source_name, source.to_string()));
        // Writing into a String cannot fail.
        let _ = handler.render_report(&mut out, report.as_ref());
        out.push('\n');
    }
    out
}
