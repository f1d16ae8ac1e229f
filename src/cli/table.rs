//! The human-readable summary `ballast check` and `ballast build` print: per pose, the centre of
//! mass, the support, where the balls went and each goal with its measured value.

use std::fmt::Write;

use crate::balance::{BallRest, GoalOutcome, PoseEvaluation};
use crate::compile::{direction_words, Compilation};
use crate::design::PlacedCapsule;
use crate::fabrication::{ComponentPlan, OrientationChoice};
use crate::spec::model::{FrameSource, Units};

/// The summary of `compilation`, ending with a line counting the goals met, and one more when
/// some capsule cannot take its ball at any pause.
pub fn summary(compilation: &Compilation, project_name: &str) -> String {
    let project = &compilation.project;
    let units = project.units;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{project_name}: {} component{}, {} capsule{}, {} pose{}; lengths in {}, masses in grams, angles in degrees",
        project.components.len(),
        plural(project.components.len()),
        compilation.design.capsules.len(),
        plural(compilation.design.capsules.len()),
        project.poses.len(),
        plural(project.poses.len()),
        unit_name(units),
    );
    mesh_section(&mut out, compilation);
    balls_section(&mut out, compilation);
    print_section(&mut out, compilation);
    let (mut total, mut met) = (0, 0);
    for evaluation in &compilation.poses {
        out.push('\n');
        pose_section(&mut out, evaluation, units);
        total += evaluation.goals.len();
        met += evaluation.goals.iter().filter(|goal| goal.met).count();
    }
    for plan in &compilation.print_plan.components {
        out.push('\n');
        insertion_section(&mut out, compilation, plan);
    }
    let _ = writeln!(out, "\n{met} of {total} goal{} met.", plural(total));
    let shut = compilation
        .print_plan
        .components
        .iter()
        .flat_map(|plan| &plan.capsules)
        .filter(|capsule| capsule.pause.is_none())
        .count();
    if shut > 0 {
        let _ = writeln!(
            out,
            "Not printable as planned: {shut} capsule{} cannot take {} ball at any pause.",
            plural(shut),
            if shut == 1 { "its" } else { "their" }
        );
    }
    if let Some(optimization) = compilation.optimization.as_ref().filter(|o| !o.meets_goals) {
        let _ = writeln!(
            out,
            "No design the optimizer tried meets every goal; the chosen one ({} capsule{}) has the lowest objective.",
            optimization.chosen,
            plural(optimization.chosen)
        );
    }
    if !compilation.solid_goals_lost.is_empty() {
        let goals: Vec<String> = compilation
            .solid_goals_lost
            .iter()
            .map(|g| format!("`{}` in pose \"{}\"", g.kind, g.pose))
            .collect();
        let _ = writeln!(
            out,
            "Without capsules, the model meets {} that this design does not: {}.",
            if goals.len() == 1 { "a goal" } else { "goals" },
            goals.join(", ")
        );
    }
    out
}

/// One line per component: its mesh file, how its coordinates were read (unit, up axis, scale)
/// and its size in the rest frame.
fn mesh_section(out: &mut String, compilation: &Compilation) {
    let project = &compilation.project;
    let units = project.units;
    let _ = writeln!(out, "\nmeshes");
    for (component, mesh) in project.components.iter().zip(&compilation.meshes) {
        let frame = &component.frame;
        let file = component
            .mesh
            .value
            .file_name()
            .map_or_else(String::new, |name| name.to_string_lossy().into_owned());
        let from = |source: FrameSource| match source {
            FrameSource::Gltf => " (glTF)",
            FrameSource::ThreeMf => " (3MF)",
            FrameSource::Written | FrameSource::Project => "",
        };
        let mut read = vec![format!(
            "in {}{}",
            unit_name(frame.units),
            from(frame.units_from)
        )];
        if frame.up != project.up || frame.up_from != FrameSource::Project {
            read.push(format!("+{} up{}", frame.up.keyword(), from(frame.up_from)));
        }
        if frame.scale != 1.0 {
            read.push(format!("scale {}", significant(frame.scale)));
        }
        let factor = frame.factor(units);
        if factor == 1.0 {
            read.push("used as written".to_string());
        } else {
            read.push(format!(
                "× {} into {}",
                significant(factor),
                unit_name(units)
            ));
        }
        if frame.up != project.up {
            read.push(format!(
                "turned +{} to +{}",
                frame.up.keyword(),
                project.up.keyword()
            ));
        }
        let size = mesh.bounding_box().map_or_else(String::new, |(lo, hi)| {
            let extent = hi - lo;
            format!(
                "; {} × {} × {} {}",
                format_length(extent.x, units),
                format_length(extent.y, units),
                format_length(extent.z, units),
                units.keyword()
            )
        });
        let _ = writeln!(
            out,
            "  {}: {file}, {}{size}",
            component.name.value,
            read.join(", ")
        );
    }
}

/// One line per component: how it lies on the bed.
fn print_section(out: &mut String, compilation: &Compilation) {
    let units = compilation.project.units;
    let _ = writeln!(out, "\nprint");
    for (component, orientation) in compilation
        .project
        .components
        .iter()
        .zip(&compilation.orientations)
    {
        let d = orientation
            .down
            .map(|c| format_length(c, Units::Millimetre));
        let d = format!("({}, {}, {})", d.x, d.y, d.z);
        let placement = match orientation.facet_area {
            Some(area) => format!(
                "printed on facet {d}, {} {}²",
                format_length(area, units),
                units.keyword()
            ),
            None => format!("printed with {d} down, on an edge or a corner"),
        };
        let why = match &orientation.choice {
            OrientationChoice::Declared => "as declared",
            OrientationChoice::Chosen { reason, .. } => reason,
        };
        let _ = writeln!(
            out,
            "  {}: {placement}, {why}; {} {} high",
            component.name.value,
            format_length(orientation.height, units),
            units.keyword()
        );
    }
}

/// The ball each capsule holds (diameter in the project's units and in millimetres, mass, gap to
/// the wall) and their total mass; nothing without capsules.
fn balls_section(out: &mut String, compilation: &Compilation) {
    let project = &compilation.project;
    let units = project.units;
    let capsules = &compilation.design.capsules;
    if capsules.is_empty() {
        return;
    }
    let grams = |capsule: &PlacedCapsule| {
        project.ball.density * capsule.ball_volume() * units.cubic_in_cm3()
    };
    let total: f64 = capsules.iter().map(grams).sum();
    let _ = writeln!(
        out,
        "\nballs           {} steel ball{}, {:.1} g in all",
        capsules.len(),
        plural(capsules.len()),
        total
    );
    for capsule in capsules {
        let diameter = 2.0 * capsule.ball_radius;
        let mm = diameter * units.in_metres() * 1e3;
        let size = match units {
            Units::Millimetre => format!("{} mm", trimmed(mm)),
            _ => format!(
                "{} {} ({} mm)",
                trimmed(diameter),
                units.keyword(),
                trimmed(mm)
            ),
        };
        let _ = writeln!(
            out,
            "  ball {:<10} {size}, {:.2} g, gap to the wall {}",
            format!("\"{}\"", capsule.name),
            grams(capsule),
            format_length(capsule.radius - capsule.ball_radius, units),
        );
    }
}

/// When the balls of one component go in: its pauses, then each capsule's window.
fn insertion_section(out: &mut String, compilation: &Compilation, plan: &ComponentPlan) {
    let units = compilation.project.units;
    let length = |value: f64| format_length(value, units);
    let name = |index: usize| {
        compilation
            .design
            .capsules
            .get(index)
            .map_or("", |c| c.name.as_str())
    };
    let _ = writeln!(
        out,
        "printing \"{}\" along {}: {} pause{}",
        compilation.project.component_name(plan.component),
        direction_words(&-plan.down),
        plan.pauses.len(),
        plural(plan.pauses.len())
    );
    for (number, pause) in plan.pauses.iter().enumerate() {
        let _ = writeln!(
            out,
            "  pause {} after layer {} at {} (resume at {}): {}",
            number + 1,
            pause.layers_done,
            length(pause.height),
            length(pause.resume_height),
            pause.message
        );
    }
    for capsule in &plan.capsules {
        let window = match (capsule.window, capsule.pause) {
            (Some((low, high)), Some(pause)) => {
                format!(
                    "window {} to {}, pause {}",
                    length(low),
                    length(high),
                    pause + 1
                )
            }
            (Some((low, high)), None) => format!(
                "window {} to {} holds no layer boundary",
                length(low),
                length(high)
            ),
            (None, _) => "no insertion window".to_string(),
        };
        let _ = writeln!(
            out,
            "  capsule \"{}\" {window}, ceiling bridge {}",
            name(capsule.capsule),
            length(capsule.ceiling_bridge)
        );
    }
}

/// `value` with at most 4 decimals and no trailing zeros (`5`, `7.9375`, `0.3125`).
/// `value` to six significant digits, without trailing zeros.
fn significant(value: f64) -> String {
    let magnitude = value.abs().log10().floor();
    let decimals = if magnitude.is_finite() {
        (5.0 - magnitude).clamp(0.0, 20.0) as usize
    } else {
        0
    };
    let text = format!("{value:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

fn trimmed(value: f64) -> String {
    let text = format!("{value:.4}");
    text.trim_end_matches('0').trim_end_matches('.').to_owned()
}

fn pose_section(out: &mut String, evaluation: &PoseEvaluation, units: Units) {
    let length = |value: f64| format_length(value, units);
    let point = |p: [f64; 3]| format!("({}, {}, {})", length(p[0]), length(p[1]), length(p[2]));
    let support = &evaluation.support;
    let _ = writeln!(out, "pose \"{}\"", evaluation.pose);
    let _ = writeln!(out, "  mass            {:.1} g", evaluation.mass);
    let _ = writeln!(
        out,
        "  centre of mass  {}",
        point(evaluation.centre_of_mass)
    );
    // The support only matters to the goals that put the model down on the ground.
    let on_ground = evaluation.goals.iter().any(|goal| {
        matches!(
            goal.outcome,
            GoalOutcome::Stand { .. } | GoalOutcome::Imbalance { .. }
        )
    });
    if on_ground {
        let angles: Vec<f64> = support
            .edges
            .iter()
            .map(|edge| edge.toppling_angle)
            .collect();
        let _ = writeln!(
            out,
            "  support         {} contact point{}, polygon of {} point{}, centre of mass {} above ground",
            support.contacts.len(),
            plural(support.contacts.len()),
            support.polygon.len(),
            plural(support.polygon.len()),
            length(support.centre_height),
        );
        let _ = writeln!(out, "  toppling angles {}", list_angles(&angles));
        let towards = support
            .tilt_direction
            .map(|d| {
                format!(
                    " towards ({:.2}, {:.2}, {:.2})",
                    d[0] + 0.0,
                    d[1] + 0.0,
                    d[2] + 0.0
                )
            })
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "  tilt margin     {:.1}{towards}, balls rolling ({:.1} with the balls held)",
            support.tilt_margin, support.fixed_ball_margin
        );
    }
    for ball in &evaluation.balls {
        let rest = match ball.rest {
            BallRest::From => "at its `from` end",
            BallRest::To => "at its `to` end",
            BallRest::Undetermined => "undetermined (axis too close to horizontal)",
        };
        let _ = writeln!(
            out,
            "  ball {:<10} {rest}, axis {:.1} above horizontal",
            format!("\"{}\"", ball.capsule),
            ball.elevation
        );
    }
    if on_ground {
        for moved in &support.ball_moves {
            let end = match moved.to {
                BallRest::To => "`to`",
                _ => "`from`",
            };
            let _ = writeln!(
                out,
                "  ball {:<10} rolls to its {end} end at a tilt of {:.1}",
                format!("\"{}\"", moved.capsule),
                moved.tilt
            );
        }
    }
    for goal in &evaluation.goals {
        let status = if goal.met { "met " } else { "FAIL" };
        let _ = writeln!(out, "  [{status}] {}", describe(&goal.outcome, units));
        states(out, &goal.outcome);
    }
}

/// The stable states of a hanging or floating goal other than the wanted one, one line each.
fn states(out: &mut String, outcome: &GoalOutcome) {
    let (verb, equilibria) = match outcome {
        GoalOutcome::Suspend { equilibria, .. } => ("hangs", equilibria),
        GoalOutcome::Immerse { equilibria, .. } => ("floats", equilibria),
        _ => return,
    };
    for state in equilibria.unwanted() {
        let _ = writeln!(out, "         also {verb} {}", state.describe());
    }
    if !equilibria.states.iter().any(|state| state.wanted) {
        let _ = writeln!(out, "         the wanted state is not a stable one");
    }
    if !equilibria.complete {
        let _ = writeln!(
            out,
            "         (stable states among {} assignments of ball ends, not all)",
            equilibria.assignments
        );
    }
}

/// One goal's measured and required values, in words.
fn describe(outcome: &GoalOutcome, units: Units) -> String {
    let length = |value: f64| format_length(value, units);
    match outcome {
        GoalOutcome::Stand {
            tilt_margin,
            margin,
        } => format!(
            "stand: survives a tilt of {tilt_margin:.1} (needs {})",
            if *margin > 0.0 {
                format!("at least {margin}")
            } else {
                "more than 0".to_string()
            }
        ),
        GoalOutcome::Imbalance {
            tilt_margin,
            margin,
        } => format!(
            "imbalance: tilt margin {tilt_margin:.1} (needs {})",
            if *margin > 0.0 {
                format!("below -{margin}")
            } else {
                "below 0".to_string()
            }
        ),
        GoalOutcome::Suspend {
            angle, tolerance, ..
        } => format!("suspend: string {angle:.1} off vertical (tolerance {tolerance})"),
        GoalOutcome::Immerse {
            angle,
            tolerance,
            distance,
            min_distance,
            mass_residual,
            mass_tolerance,
            ..
        } => {
            let mut text = format!(
                "immerse: buoyancy {angle:.1} off vertical (tolerance {tolerance}), centres {} apart (needs {}), mass residual {mass_residual:+.1} g",
                length(*distance),
                length(*min_distance),
            );
            if let Some(allowed) = mass_tolerance {
                let _ = write!(text, " (tolerance {allowed} g)");
            }
            text
        }
    }
}

/// Toppling angles in edge order; a long list is summarised by its count and range.
fn list_angles(angles: &[f64]) -> String {
    const SHOWN: usize = 8;
    if angles.len() <= SHOWN {
        let shown: Vec<String> = angles.iter().map(|angle| format!("{angle:.1}")).collect();
        return shown.join(" ");
    }
    let smallest = angles.iter().copied().fold(f64::INFINITY, f64::min);
    let largest = angles.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    format!("{} edges, from {smallest:.1} to {largest:.1}", angles.len())
}

/// A length with as many decimals as the unit needs to show a tenth of a millimetre or better.
fn format_length(value: f64, units: Units) -> String {
    let decimals = match units {
        Units::Millimetre => 2,
        Units::Centimetre | Units::Inch => 3,
        Units::Metre => 5,
    };
    let text = format!("{value:.decimals$}");
    // Never print "-0.00".
    if text
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        text.trim_start_matches('-').to_string()
    } else {
        text
    }
}

/// The unit's name in a sentence, plural (`millimetres`).
pub(super) fn unit_name(units: Units) -> &'static str {
    match units {
        Units::Millimetre => "millimetres",
        Units::Centimetre => "centimetres",
        Units::Metre => "metres",
        Units::Inch => "inches",
    }
}

pub(super) fn plural(count: usize) -> &'static str {
    if count == 1 {
        ""
    } else {
        "s"
    }
}
