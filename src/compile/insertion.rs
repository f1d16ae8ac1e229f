//! When the balls go in: each component's insertion windows and pauses for the design, printed
//! in the direction its print plan lays it on the bed, and a warning for each void whose ceiling a slicer must
//! bridge further than it reliably does.

use nalgebra::Vector3;

use crate::design::Design;
use crate::diagnostic::Problem;
use crate::fabrication::{plan_insertions, required_rise, PrintPlan, PrintSetup};
use crate::geometry::TriMesh;
use crate::spec::model::{Project, Units};

/// The widest ceiling bridge that passes without a warning, millimetres: PrusaSlicer bridges
/// gaps of this size without support at its default bridge settings (an assumption, see
/// `docs/fabrication.md`, "The ceiling").
pub const BRIDGE_LIMIT_MM: f64 = 10.0;

/// Fills in every component of `plan` with its insertion windows and pauses for `design`, each
/// measured along the direction the component is printed in (its `to_bed` turns that direction
/// to +z); `meshes` are the components.
pub fn plan_insertions_into(
    project: &Project,
    meshes: &[TriMesh],
    design: &Design,
    plan: &mut PrintPlan,
) {
    let print = PrintSetup::from_plan(plan);
    let describe = |diameter: f64| ball_words(diameter, project.units);
    for (component, mesh) in meshes.iter().enumerate() {
        let frame = print.frame(component, mesh);
        let capsules = design.capsules_of(component);
        let (capsules, pauses) = plan_insertions(&capsules, &frame, &print.grid, &describe);
        if let Some(component) = plan.components.get_mut(component) {
            component.capsules = capsules;
            component.pauses = pauses;
        }
    }
}

/// A warning for every capsule whose ceiling bridge is wider than [`BRIDGE_LIMIT_MM`], on its
/// node in the project file when it has one.
pub fn ceiling_warnings(project: &Project, design: &Design, plan: &PrintPlan) -> Vec<Problem> {
    let units = project.units;
    let limit = units.from_millimetres(BRIDGE_LIMIT_MM);
    let mut warnings = Vec::new();
    for insertion in plan
        .components
        .iter()
        .flat_map(|component| &component.capsules)
    {
        let Some(capsule) = design.capsules.get(insertion.capsule) else {
            continue;
        };
        if insertion.ceiling_bridge <= limit {
            continue;
        }
        let name = &capsule.name;
        let mut warning = Problem::warning(
            "ballast::capsule::ceiling_bridge",
            format!(
                "the ceiling of capsule `{name}` overhangs more than 45° over {}, wider than the {} a slicer is assumed to bridge without support",
                length_words(insertion.ceiling_bridge, units),
                length_words(limit, units),
            ),
        )
        .with_help("make the capsule narrower, or let the slicer add support inside the void (and clear it before the pause)");
        if let Some(node) = project.capsules.iter().find(|c| &c.name.value == name) {
            warning = warning.with_label(node.span, "this capsule");
        }
        warnings.push(warning);
    }
    warnings
}

/// A warning for every capsule whose ball cannot go in at any pause in its component's print
/// orientation (no layer boundary in its insertion window), on its node in the project file when
/// it has one: the design cannot be printed the way the balls are meant to go in.
pub fn window_warnings(
    project: &Project,
    meshes: &[TriMesh],
    design: &Design,
    plan: &PrintPlan,
) -> Vec<Problem> {
    let print = PrintSetup::from_plan(plan);
    let units = project.units;
    let mut warnings = Vec::new();
    for insertion in plan
        .components
        .iter()
        .flat_map(|component| &component.capsules)
    {
        if insertion.pause.is_some() {
            continue;
        }
        let Some(capsule) = design.capsules.get(insertion.capsule) else {
            continue;
        };
        let Some(mesh) = meshes.get(capsule.component) else {
            continue;
        };
        let frame = print.frame(capsule.component, mesh);
        let (rise, required) = required_rise(capsule, &frame, &print.grid);
        let up = direction_words(&frame.up);
        let name = &capsule.name;
        let mut warning = Problem::warning(
            "ballast::capsule::no_insertion_window",
            format!(
                "the ball of capsule `{name}` cannot be dropped in at any pause: printed along {up}, its axis rises {}; a layer boundary between the resting ball's top and the end of the opening needs {}",
                length_words(rise, units),
                length_words(required, units),
            ),
        )
        .with_help(format!(
            "raise one end so that the axis rises {} more along {up}, or print the component in another orientation (a `print` block)",
            length_words((required - rise).max(0.0), units)
        ));
        if let Some(node) = project.capsules.iter().find(|c| &c.name.value == name) {
            warning = warning.with_label(node.span, "this capsule");
        }
        warnings.push(warning);
    }
    warnings
}

/// A print direction in words: `+z` for an axis, else its components.
pub fn direction_words(up: &Vector3<f64>) -> String {
    for (axis, name) in ["x", "y", "z"].iter().enumerate() {
        for (sign, word) in [(1.0, "+"), (-1.0, "-")] {
            if (up[axis] - sign).abs() < 1e-12 {
                return format!("{word}{name}");
            }
        }
    }
    format!("({:.3}, {:.3}, {:.3})", up.x, up.y, up.z)
}

/// A ball diameter for the printer's message: "8 mm" in a millimetre project, else in the
/// project's unit with millimetres beside it ("0.3125 in (7.94 mm)").
fn ball_words(diameter: f64, units: Units) -> String {
    let millimetres = diameter * units.in_metres() * 1000.0;
    match units {
        Units::Millimetre => format!("{} mm", short(millimetres, 2)),
        _ => format!(
            "{} {} ({} mm)",
            short(diameter, 4),
            units.keyword(),
            short(millimetres, 2)
        ),
    }
}

/// A length in the project's unit, with millimetres beside it when that is another unit.
fn length_words(length: f64, units: Units) -> String {
    match units {
        Units::Millimetre => format!("{} mm", short(length, 2)),
        _ => ball_words(length, units),
    }
}

/// `value` rounded to `decimals`, without trailing zeros.
fn short(value: f64, decimals: i32) -> String {
    let scale = 10f64.powi(decimals);
    let rounded = (value * scale).round() / scale;
    format!("{rounded}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ball_sizes_read_in_millimetres() {
        assert_eq!(ball_words(8.0, Units::Millimetre), "8 mm");
        assert_eq!(ball_words(15.6049, Units::Millimetre), "15.6 mm");
        assert_eq!(ball_words(0.3125, Units::Inch), "0.3125 in (7.94 mm)");
        assert_eq!(ball_words(0.8, Units::Centimetre), "0.8 cm (8 mm)");
    }
}
