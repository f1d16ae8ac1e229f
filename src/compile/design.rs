//! The hand-placed capsules of a project turned into a [`Design`], and the fabrication stage's
//! findings turned into diagnostics on the capsules' nodes.

use crate::design::{Design, PlacedCapsule};
use crate::diagnostic::Problem;
use crate::fabrication::{check_design, CapsuleIssue, PrintSetup};
use crate::geometry::TriMesh;
use crate::spec::model::{Capsule, Project};
use miette::Severity;

/// The design the project file describes: its capsules, each with the ball that fits it, and the
/// project's infill. A capsule no ball fits is reported and left out.
pub fn hand_placed_design(project: &Project) -> (Design, Vec<Problem>) {
    let mut problems = Vec::new();
    let mut capsules = Vec::with_capacity(project.capsules.len());
    for capsule in &project.capsules {
        match placed(project, capsule) {
            Some(placed) => capsules.push(placed),
            None => problems.push(no_ball_problem(project, capsule.radius, capsule.span)),
        }
    }
    let design = Design {
        capsules,
        infill: project.infill.value,
    };
    (design, problems)
}

/// The widest gap beyond the clearance between a written capsule's wall and its ball that passes
/// without a warning, millimetres: half a millimetre, about two steps of the metric stock sizes
/// below 8 mm (`docs/format.md`, `ballast::capsule::ball_gap`).
pub const BALL_GAP_MM: f64 = 0.5;

/// A warning for every written capsule whose radius leaves more than [`BALL_GAP_MM`] beyond the
/// clearance around the largest listed ball that fits it (only when balls come from a list): the
/// void is wider than its ball needs, so the ball rattles off the axis, and the radius is not
/// what the stock ball asks for.
pub fn ball_gap_warnings(project: &Project, written: &Design) -> Vec<Problem> {
    let ball = &project.ball;
    if !ball.is_listed() {
        return Vec::new();
    }
    let units = project.units.keyword();
    let limit = project.units.from_millimetres(BALL_GAP_MM);
    let mut warnings = Vec::new();
    for node in &project.capsules {
        let Some(capsule) = written.capsules.iter().find(|c| c.name == node.name.value) else {
            continue;
        };
        let gap = capsule.radius - capsule.ball_radius;
        let extra = gap - ball.clearance;
        // A gap at the limit but for rounding passes.
        if extra <= limit * (1.0 + 1e-9) {
            continue;
        }
        let diameter = 2.0 * capsule.ball_radius;
        let snug = round(capsule.ball_radius + ball.clearance);
        let mut help = format!(
            "a radius of {snug} {units} holds the {} {units} ball with the clearance",
            round(diameter)
        );
        if let Some(larger) = ball.next_larger(capsule.ball_radius) {
            help.push_str(&format!(
                "; {} {units} holds the next larger one, {} {units}",
                round(larger + ball.clearance),
                round(2.0 * larger)
            ));
        }
        warnings.push(
            Problem::warning(
                "ballast::capsule::ball_gap",
                format!(
                    "capsule `{}` (radius {} {units}) holds a {} {units} ball, the largest listed that fits: it leaves {} {units} between ball and wall, {} {units} more than the clearance",
                    capsule.name,
                    round(capsule.radius),
                    round(diameter),
                    round(gap),
                    round(extra)
                ),
            )
            .with_label(node.span, "this capsule")
            .with_help(help),
        );
    }
    warnings
}

/// The capsules known before any optimizing, which the print orientation is chosen for: every
/// written capsule of `written` without `optimize`, the pinned ones with it.
pub fn fixed_capsules(project: &Project, written: &Design) -> Design {
    let pinned = |name: &str| {
        project
            .capsules
            .iter()
            .any(|node| node.name.value == name && node.pinned)
    };
    Design {
        capsules: written
            .capsules
            .iter()
            .filter(|c| project.optimize.is_none() || pinned(&c.name))
            .cloned()
            .collect(),
        infill: written.infill,
    }
}

/// The capsules written in the project file as a design ([`hand_placed_design`]) with their
/// problems, fabrication ones too once the meshes and their print setup are known (`checks`). A problem that concerns only seeds
/// (unpinned capsules of a project that optimizes) does not make the project invalid: when
/// `optimizing`, it is left out (the optimizer moves the seed to a valid place and says so);
/// otherwise it is a warning that says the build will. Pinned capsules, and every capsule of a
/// project that does not optimize, must be valid as written.
pub fn written_design(
    project: &Project,
    checks: Option<(&[TriMesh], &PrintSetup)>,
    optimizing: bool,
) -> (Design, Vec<Problem>) {
    let seed = |name: &str| {
        project.optimize.is_some()
            && project
                .capsules
                .iter()
                .any(|c| !c.pinned && c.name.value == name)
    };
    let lenient =
        |problem: Problem, name: &str| (!optimizing).then(|| as_seed_warning(problem, name));
    let mut problems = Vec::new();
    let mut capsules = Vec::with_capacity(project.capsules.len());
    for capsule in &project.capsules {
        let Some(placed) = placed(project, capsule) else {
            let problem = no_ball_problem(project, capsule.radius, capsule.span);
            if seed(&capsule.name.value) {
                problems.extend(lenient(problem, &capsule.name.value));
            } else {
                problems.push(problem);
            }
            continue;
        };
        capsules.push(placed);
    }
    let design = Design {
        capsules,
        infill: project.infill.value,
    };
    if let Some((meshes, print)) = checks {
        let issues = check_design(meshes, &design, project.wall, project.ball.clearance, print);
        for issue in &issues {
            let Some(problem) = issue_problem(project, &design, issue) else {
                continue;
            };
            let name = |i: usize| design.capsules.get(i).map_or("", |c| c.name.as_str());
            let involved = match *issue {
                CapsuleIssue::Overlap { first, second, .. } => vec![name(first), name(second)],
                _ => vec![name(issue.capsule())],
            };
            // A seed moves: an overlap with a pinned capsule is the seed's to resolve.
            match involved.iter().find(|n| seed(n)) {
                Some(&first_seed) => problems.extend(lenient(problem, first_seed)),
                None => problems.push(problem),
            }
        }
    }
    (design, problems)
}

/// The design capsule `capsule` describes, with the ball that fits it; `None` when no ball does.
fn placed(project: &Project, capsule: &Capsule) -> Option<PlacedCapsule> {
    let ball_radius = project.ball.radius_for(capsule.radius)?;
    Some(PlacedCapsule {
        name: capsule.name.value.clone(),
        component: capsule.component.value,
        from: capsule.from,
        to: capsule.to,
        radius: capsule.radius,
        ball_radius,
    })
}

/// `problem`, found on the seed `name`, as a warning that the build moves the seed.
fn as_seed_warning(mut problem: Problem, name: &str) -> Problem {
    problem.severity = Severity::Warning;
    problem.help = Some(format!(
        "`{name}` is a seed, only where the optimizer starts: `ballast build` moves it to the nearest valid place first. Write `pinned=#true` to keep a capsule exactly as written (it must then be valid)"
    ));
    problem
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

/// The fabrication stage's findings on `design`, its components printed as `print` says, as
/// errors on the capsules' nodes. A capsule without an insertion window is no error here: the
/// design can still be evaluated, and the driver warns of it with the print plan
/// (`ballast::capsule::no_insertion_window`).
pub fn fabrication_problems(
    project: &Project,
    meshes: &[TriMesh],
    design: &Design,
    print: &PrintSetup,
) -> Vec<Problem> {
    let issues = check_design(meshes, design, project.wall, project.ball.clearance, print);
    issues
        .iter()
        .filter_map(|issue| issue_problem(project, design, issue))
        .collect()
}

/// The error `issue` is on its capsule's node; `None` for a missing insertion window (a warning
/// the driver gives).
fn issue_problem(project: &Project, design: &Design, issue: &CapsuleIssue) -> Option<Problem> {
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
    let problem = match *issue {
        CapsuleIssue::NoInsertionWindow { .. } => return None,
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
    };
    Some(problem)
}
