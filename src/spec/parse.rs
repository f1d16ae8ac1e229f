//! The front end's entry point: project-file text to a [`Project`] and every problem in it.
//!
//! Reading goes in stages, each in its own module: [`syntax`] parses the KDL text
//! (stopping there on syntax errors), [`check`](super::check) checks every node against the
//! vocabulary, and [`resolve`](super::resolve) builds the project and checks the rules that span
//! several nodes. Every stage reports all it finds, so one run shows every mistake.

use std::path::{Path, PathBuf};

use kdl::KdlDocument;

use super::check::check_document;
use super::codes::TOO_MANY_PROBLEMS;
use super::model::{Project, Units};
use super::resolve::resolve;
use super::syntax;
use super::vocabulary;
use crate::diagnostic::Problem;
use crate::geometry::ReadPolicy;

/// The outcome of reading a project file: the project when there were no errors, and every
/// problem found.
#[derive(Debug, Clone)]
pub struct Parsed {
    /// The project; `Some` exactly when `problems` holds no error (warnings may accompany it).
    pub project: Option<Project>,
    /// Every problem found, in source order (problems without a location last).
    pub problems: Vec<Problem>,
    /// The `rig` file the project names, resolved against its folder, whether or not it could
    /// be read (so that watch mode follows it while it is broken).
    pub rig: Option<PathBuf>,
}

/// Reads the project file `source`, found at `project_path` (against whose folder its relative
/// paths are resolved). Mesh files are not opened; a `rig` file is read (for its nodes and
/// animations) from inside the project's folder, within the default mesh limits. Never panics,
/// whatever the text.
pub fn parse_project(source: &str, project_path: &Path) -> Parsed {
    parse_project_with(
        source,
        project_path,
        &ReadPolicy::within(folder_of(project_path)),
    )
}

/// The folder of the project file (`.` for a bare file name).
fn folder_of(project_path: &Path) -> &Path {
    match project_path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder,
        _ => Path::new("."),
    }
}

/// [`parse_project`], reading a `rig` file only as `policy` allows.
pub fn parse_project_with(source: &str, project_path: &Path, policy: &ReadPolicy) -> Parsed {
    let document = match syntax::read(source) {
        Ok(document) => document,
        Err(mut problems) => {
            keep_at_most_max(&mut problems);
            return Parsed {
                project: None,
                problems,
                rig: None,
            };
        }
    };
    let units = declared_units(&document);
    let mut problems = Vec::new();
    let nodes = check_document(
        &document,
        source,
        vocabulary::DOCUMENT,
        units,
        &mut problems,
    );
    let project = resolve(&nodes, units, project_path, policy, &mut problems);
    problems.sort_by_key(|problem| {
        problem
            .labels
            .first()
            .map_or(usize::MAX, |(span, _)| span.offset())
    });
    keep_at_most_max(&mut problems);
    let project = (!problems.iter().any(Problem::is_error)).then_some(project);
    let rig = nodes
        .iter()
        .find(|node| node.name == "rig")
        .and_then(|node| node.text_arg())
        .map(|path| folder_of(project_path).join(path.value));
    Parsed {
        project,
        problems,
        rig,
    }
}

/// The most problems one file's reading keeps; the rest are counted in one last problem.
pub const MAX_PROBLEMS: usize = 200;

/// Keeps the first [`MAX_PROBLEMS`] of `problems` and, when there were more, adds one saying how
/// many were left out, so a file that is all mistakes costs bounded memory and output.
pub(super) fn keep_at_most_max(problems: &mut Vec<Problem>) {
    if problems.len() <= MAX_PROBLEMS {
        return;
    }
    let left_out = problems.len() - MAX_PROBLEMS;
    let errors = problems[MAX_PROBLEMS..]
        .iter()
        .filter(|p| p.is_error())
        .count();
    problems.truncate(MAX_PROBLEMS);
    let message = format!(
        "{left_out} more problems ({errors} of them errors) were left out: at most {MAX_PROBLEMS} \
         are kept"
    );
    let help = "fix these and check again (docs/limits.md, \"Project and solution files\")";
    problems.push(if errors > 0 {
        Problem::error(TOO_MANY_PROBLEMS, message).with_help(help)
    } else {
        Problem::warning(TOO_MANY_PROBLEMS, message).with_help(help)
    });
}

/// The units the file declares (its first `units` node), which every length is converted to,
/// wherever in the file that node is written. Millimetres when there is none or it is bad (the
/// checker reports a bad one).
fn declared_units(document: &KdlDocument) -> Units {
    document
        .nodes()
        .iter()
        .find(|node| node.name().value() == "units")
        .and_then(|node| node.entries().first())
        .filter(|entry| entry.name().is_none())
        .and_then(|entry| entry.value().as_string())
        .and_then(Units::from_keyword)
        .unwrap_or(Units::Millimetre)
}
