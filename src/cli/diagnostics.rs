//! Printing diagnostics: graphical with colour on a terminal, plain when piped or `NO_COLOR` is set.

use std::io::IsTerminal;

use miette::{GraphicalReportHandler, GraphicalTheme};

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
