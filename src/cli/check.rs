//! `ballast check`: what the design does in every pose, as a table or as the JSON report.

use std::path::Path;

use super::{compile_file, file_name, goals_status, table, EXIT_INVALID};
use crate::compile::{CompileOptions, Report, Workspace};

/// Checks the project at `path`; prints the summary table, or the report when `json`.
pub fn run(path: &Path, json: bool, options: &CompileOptions) -> i32 {
    let Ok(compilation) = compile_file(path, options, &mut Workspace::new()) else {
        return EXIT_INVALID;
    };
    if json {
        print!("{}", Report::new(&compilation, path).to_json());
    } else {
        print!("{}", table::summary(&compilation, &file_name(path)));
    }
    goals_status(&compilation)
}
