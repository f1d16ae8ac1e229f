//! Solution files: the optimizer's capsules, written as the project file's `capsule` nodes (and
//! the infill it chose when the project gives a range), for a user to commit, diff and check.
//!
//! A solution file is read in the same stages as a project file, with the same capsule grammar
//! and the same checks: [`vocabulary::SOLUTION`] lists its nodes, lengths are converted to the
//! project's units, and component names resolve against the project's components.

use std::path::Path;

use super::check::check_document;
use super::model::{Capsule, Project};
use super::parse::keep_at_most_max;
use super::resolve::resolve_solution;
use super::syntax;
use super::vocabulary;
use crate::diagnostic::Problem;

/// The outcome of reading a solution file: its capsules and infill when there were no errors,
/// and every problem found.
#[derive(Debug, Clone)]
pub struct ParsedSolution {
    /// The capsules, in file order; `Some` exactly when `problems` holds no error.
    pub capsules: Option<Vec<Capsule>>,
    /// The infill the solution chose, when it gives one and there were no errors.
    pub infill: Option<f64>,
    /// Every problem found, in source order (problems without a location last); spans point
    /// into the solution file's text.
    pub problems: Vec<Problem>,
}

/// Reads the solution file `source` of `project`. Lengths are converted to the project's units
/// and component names resolve against its components. `path` names the file for the caller's
/// messages; nothing is read from it. Never panics, whatever the text.
pub fn parse_solution(source: &str, path: &Path, project: &Project) -> ParsedSolution {
    let _ = path;
    let document = match syntax::read(source) {
        Ok(document) => document,
        Err(mut problems) => {
            keep_at_most_max(&mut problems);
            return ParsedSolution {
                capsules: None,
                infill: None,
                problems,
            };
        }
    };
    let mut problems = Vec::new();
    let nodes = check_document(
        &document,
        source,
        vocabulary::SOLUTION,
        project.units,
        &mut problems,
    );
    let (capsules, infill) = resolve_solution(&nodes, project, &mut problems);
    problems.sort_by_key(|problem| {
        problem
            .labels
            .first()
            .map_or(usize::MAX, |(span, _)| span.offset())
    });
    keep_at_most_max(&mut problems);
    let valid = !problems.iter().any(Problem::is_error);
    ParsedSolution {
        capsules: valid.then_some(capsules),
        infill: infill.filter(|_| valid),
        problems,
    }
}
