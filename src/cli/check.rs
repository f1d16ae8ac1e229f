//! `ballast check`: what the design does in every pose, as a table or as the JSON report.

use std::path::Path;

use super::{compile_file, file_name, goals_status, table, EXIT_INVALID};
use crate::compile::Report;

/// Checks the project at `path`; prints the summary table, or the report when `json`.
pub fn run(path: &Path, json: bool) -> i32 {
    let Some(compilation) = compile_file(path) else {
        return EXIT_INVALID;
    };
    if json {
        print!("{}", Report::new(&compilation, path).to_json());
    } else {
        print!("{}", table::summary(&compilation, &file_name(path)));
    }
    goals_status(&compilation)
}
