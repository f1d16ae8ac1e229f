//! `ballast check`: what the design does in every pose, as a table or as the JSON report.

use std::path::Path;

use serde::Serialize;

use super::diagnostics::JsonDiagnostic;
use super::{
    compile_file, file_name, goals_status, say, table, MessageFormat, NotCompiled, EXIT_INVALID,
};
use crate::compile::{CompileOptions, Report, Workspace};

/// What `check --json` prints instead of the report when the project is invalid.
#[derive(Serialize)]
struct InvalidProject {
    /// Always `false`: no report could be made.
    valid: bool,
    /// The project file, as named on the command line.
    file: String,
    /// Every problem found, warnings too, as `--message-format json` prints them.
    diagnostics: Vec<JsonDiagnostic>,
}

/// Checks the project at `path`; prints the summary table, or the report when `json`, and the
/// diagnostics as `format` says.
pub fn run(path: &Path, json: bool, format: MessageFormat, options: &CompileOptions) -> i32 {
    let compilation = match compile_file(path, options, &mut Workspace::new(), format) {
        Ok(compilation) => compilation,
        Err(NotCompiled::Invalid(invalid)) => {
            if json {
                let document = InvalidProject {
                    valid: false,
                    file: invalid.name.clone(),
                    diagnostics: invalid
                        .problems
                        .iter()
                        .map(|problem| JsonDiagnostic::new(problem, &invalid.name, &invalid.source))
                        .collect(),
                };
                print_json(format, &document);
            }
            return EXIT_INVALID;
        }
        Err(NotCompiled::Cancelled) => return EXIT_INVALID,
    };
    if json {
        print_json(format, &Report::new(&compilation, path));
    } else {
        say(format, &table::summary(&compilation, &file_name(path)));
    }
    goals_status(&compilation)
}

/// Prints `value` on standard output: pretty, or on one line among JSON diagnostics.
fn print_json(format: MessageFormat, value: &impl Serialize) {
    let text = match format {
        MessageFormat::Human => serde_json::to_string_pretty(value),
        MessageFormat::Json => serde_json::to_string(value),
    };
    println!("{}", text.expect("plain, finite data"));
}
