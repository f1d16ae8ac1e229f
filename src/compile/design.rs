//! The hand-placed capsules of a project turned into a [`Design`], and the fabrication stage's
//! findings turned into diagnostics on the capsules' nodes.

use crate::design::{Design, PlacedCapsule};
use crate::diagnostic::Problem;
use crate::fabrication::{check_design, CapsuleIssue};
use crate::geometry::TriMesh;
use crate::spec::model::Project;

/// The design the project file describes: its capsules, each with the ball that fits it, and the
/// project's infill. A capsule no ball fits is reported and left out.
pub fn hand_placed_design(project: &Project) -> (Design, Vec<Problem>) {
    let mut problems = Vec::new();
    let mut capsules = Vec::with_capacity(project.capsules.len());
    for capsule in &project.capsules {
        let Some(ball_radius) = project.ball.radius_for(capsule.radius) else {
            problems.push(no_ball_problem(project, capsule.radius, capsule.span));
            continue;
        };
        capsules.push(PlacedCapsule {
            name: capsule.name.value.clone(),
            component: capsule.component.value,
            from: capsule.from,
            to: capsule.to,
            radius: capsule.radius,
            ball_radius,
        });
    }
    let design = Design {
        capsules,
        infill: project.infill.value,
    };
    (design, problems)
}

fn no_ball_problem(project: &Project, radius: f64, span: miette::SourceSpan) -> Problem {
    let units = project.units.keyword();
    let ball = &project.ball;
    let largest = 2.0 * (radius - ball.clearance);
    let message = if ball.diameters.is_empty() || largest <= 0.0 {
        format!(
            "no ball fits a capsule of radius {radius} {units} with a clearance of {} {units}",
            ball.clearance
        )
    } else {
        format!(
            "none of the listed ball diameters fits a capsule of radius {radius} {units}: the largest that fits is {} {units}",
            round(largest)
        )
    };
    Problem::error("ballast::capsule::no_ball", message)
        .with_label(span, "this capsule")
        .with_help("make the capsule wider, or list a smaller ball in `ball { diameters ... }`")
}

/// Rounds to 4 decimals, for numbers shown in messages.
pub(crate) fn round(value: f64) -> f64 {
    (value * 1e4).round() / 1e4
}

/// The fabrication stage's findings on `design` as diagnostics on the capsules' nodes.
pub fn fabrication_problems(
    project: &Project,
    meshes: &[TriMesh],
    design: &Design,
) -> Vec<Problem> {
    let issues = check_design(meshes, design, project.wall, project.ball.clearance);
    issues
        .iter()
        .map(|issue| issue_problem(project, design, issue))
        .collect()
}

fn issue_problem(project: &Project, design: &Design, issue: &CapsuleIssue) -> Problem {
    let units = project.units.keyword();
    let capsule = |index: usize| {
        let name = design
            .capsules
            .get(index)
            .map(|c| c.name.as_str())
            .unwrap_or("?");
        let node = project.capsules.iter().find(|c| c.name.value == name);
        (name.to_string(), node)
    };
    let component = |index: usize| {
        project
            .components
            .get(index)
            .map(|c| c.name.value.clone())
            .unwrap_or_else(|| format!("#{index}"))
    };
    let (name, node) = capsule(issue.capsule());
    let span = node.map(|n| n.span).unwrap_or_else(|| (0, 0).into());
    let component_span = node.map(|n| n.component.span).unwrap_or(span);
    match *issue {
        CapsuleIssue::TooShort { length, radius, .. } => Problem::error(
            "ballast::capsule::too_short",
            format!(
                "capsule `{name}` is shorter than its radius: its axis is {} {units} long, its radius {radius} {units}",
                round(length)
            ),
        )
        .with_label(span, "this capsule")
        .with_help("move `from` and `to` apart: the print is paused to drop the ball in, and the void must be long enough to close over it"),
        CapsuleIssue::BallDoesNotFit { ball_radius, max, .. } => Problem::error(
            "ballast::capsule::no_ball",
            format!(
                "the ball of capsule `{name}` (radius {} {units}) does not fit; at most {} {units} does",
                round(ball_radius),
                round(max)
            ),
        )
        .with_label(span, "this capsule"),
        CapsuleIssue::UnknownComponent { component: index, .. } => Problem::error(
            "ballast::capsule::unknown_component",
            format!("capsule `{name}` names component #{index}, which does not exist"),
        )
        .with_label(component_span, "this component"),
        CapsuleIssue::Outside { component: index, .. } => Problem::error(
            "ballast::capsule::outside",
            format!(
                "capsule `{name}` is outside its component `{}` and every other component",
                component(index)
            ),
        )
        .with_label(span, "the middle of this capsule's axis is outside the model")
        .with_help("capsule coordinates are in the rest frame, the coordinates the meshes are written in"),
        CapsuleIssue::InOtherComponent { assigned, actual, .. } => Problem::error(
            "ballast::capsule::wrong_component",
            format!(
                "capsule `{name}` is assigned to `{}` but lies inside `{}`",
                component(assigned),
                component(actual)
            ),
        )
        .with_label(component_span, format!("it is inside `{}`", component(actual)))
        .with_help(format!("write component=\"{}\", or move the capsule", component(actual))),
        CapsuleIssue::TooCloseToSurface {
            component: index,
            distance,
            required,
            ..
        } => Problem::error(
            "ballast::capsule::thin_wall",
            format!(
                "capsule `{name}` comes within {} {units} of the surface of `{}`; its radius plus the wall needs {} {units}",
                round(distance),
                component(index),
                round(required)
            ),
        )
        .with_label(span, "this capsule")
        .with_help("move it further inside, shorten it or make it narrower"),
        CapsuleIssue::Overlap {
            second,
            distance,
            required,
            ..
        } => {
            let (other, other_node) = capsule(second);
            let mut problem = Problem::error(
                "ballast::capsule::overlap",
                format!(
                    "capsules `{name}` and `{other}` are {} {units} apart; their radii plus the wall need {} {units}",
                    round(distance),
                    round(required)
                ),
            )
            .with_label(span, "this capsule");
            if let Some(other_node) = other_node {
                problem = problem.with_label(other_node.span, "and this one");
            }
            problem.with_help("move them apart or make them narrower")
        }
    }
}
