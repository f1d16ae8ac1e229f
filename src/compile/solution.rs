//! The solution file: the optimizer's design written as capsule nodes, and read back by `check`.

use std::path::Path;
use std::sync::Arc;

use super::design::{fabrication_problems, hand_placed_design};
use super::optimize::length_decimals;
use crate::cancel::Interruption;
use crate::design::Design;
use crate::diagnostic::{Problem, SourceFile};
use crate::emit::{write_solution, Solution, SolutionCapsule};
use crate::fabrication::PrintSetup;
use crate::geometry::TriMesh;
use crate::spec::model::Project;
use crate::spec::{parse_solution, read_solution_source};

/// The solution file's text for `design`: a header naming the project, then the infill when the
/// project lets the optimizer choose it, then the capsules. Lengths carry [`length_decimals`]
/// digits; the design is rounded to them before it is evaluated, so reading the file back gives
/// the same design.
pub fn solution_text(
    project: &Project,
    project_name: &str,
    meshes: &[TriMesh],
    design: &Design,
) -> String {
    solution_text_after(project, project_name, meshes, design, None)
}

/// [`solution_text`] for a design the optimizer found before `interrupted` stopped its search:
/// the header says that it is the best found by then, not the finished search's. The same design
/// stopped the same way gives the same text (no time or date is written).
pub fn interrupted_solution_text(
    project: &Project,
    project_name: &str,
    meshes: &[TriMesh],
    design: &Design,
    interrupted: Interruption,
) -> String {
    solution_text_after(project, project_name, meshes, design, Some(interrupted))
}

/// [`solution_text`], its header saying whether the search was `interrupted`.
fn solution_text_after(
    project: &Project,
    project_name: &str,
    meshes: &[TriMesh],
    design: &Design,
    interrupted: Option<Interruption>,
) -> String {
    let capsules = design
        .capsules
        .iter()
        .map(|c| SolutionCapsule {
            name: c.name.clone(),
            component: project.component_name(c.component).to_string(),
            from: c.from.coords.into(),
            to: c.to.coords.into(),
            radius: c.radius,
            pinned: project
                .capsules
                .iter()
                .any(|w| w.pinned && w.name.value == c.name),
        })
        .collect();
    write_solution(&Solution {
        header: header(project, project_name, interrupted),
        infill: project.infill.range.map(|_| design.infill),
        capsules,
        decimals: length_decimals(meshes),
    })
}

/// The solution file's comment lines: what the capsules are, in which units, and what reads and
/// writes the file.
fn header(project: &Project, project_name: &str, interrupted: Option<Interruption>) -> Vec<String> {
    let units = project.units.keyword();
    match interrupted {
        None => vec![
            format!(
                "The capsules ballast chose for {project_name}; lengths in the project's units ({units})."
            ),
            "`ballast check` evaluates them; `ballast build` writes this file anew.".to_string(),
        ],
        Some(why) => vec![
            format!(
                "INTERRUPTED: the search for {project_name} was stopped by {} before it ended.",
                why.cause()
            ),
            format!(
                "These are the best capsules found before the interruption, not the finished search's; lengths in the project's units ({units})."
            ),
            "`ballast check` evaluates them; a `ballast build` that runs to the end writes this file anew.".to_string(),
        ],
    }
}

/// The design in the solution file at `path`: `Ok(None)` when there is no such file; every
/// problem in it otherwise, its spans pointing into that file. The components are printed as
/// `print` says.
pub fn read_solution(
    project: &Project,
    path: &Path,
    meshes: &[TriMesh],
    print: &PrintSetup,
) -> Result<Option<Design>, Vec<Problem>> {
    let text = match read_solution_source(path) {
        Ok(Some(text)) => text,
        Ok(None) => return Ok(None),
        Err(problem) => return Err(vec![*problem]),
    };
    let file = SourceFile {
        name: path.display().to_string(),
        text: Arc::from(text.as_str()),
    };
    let parsed = parse_solution(&text, path, project);
    let mut problems: Vec<Problem> = parsed
        .problems
        .into_iter()
        .map(|p| p.in_file(file.clone()))
        .collect();
    let Some(capsules) = parsed.capsules else {
        return Err(problems);
    };
    let mut solved = project.clone();
    solved.capsules = capsules;
    if let Some(infill) = parsed.infill {
        solved.infill.value = infill;
    }
    let (design, design_problems) = hand_placed_design(&solved);
    problems.extend(design_problems.into_iter().map(|p| p.in_file(file.clone())));
    problems.extend(
        fabrication_problems(&solved, meshes, &design, print)
            .into_iter()
            .map(|p| p.in_file(file.clone())),
    );
    if problems.iter().any(Problem::is_error) {
        return Err(problems);
    }
    Ok(Some(design))
}

/// The warning for a project with `optimize` whose solution file does not exist yet.
pub fn missing(path: &Path) -> Problem {
    Problem::warning(
        "ballast::solution::missing",
        format!(
            "there is no solution file at {} yet: evaluating the capsules written in the project",
            path.display()
        ),
    )
    .with_help("run `ballast build` to optimize the capsules and write the solution file")
}
