//! The physical range of each print setting and ball property: a value outside it describes no
//! printer or ball that exists (a layer a nanometre thick, a ball a kilometre wide) and would
//! only make the print model ask for unbounded memory or the optimizer place capsules outside
//! the part. Each is refused at its span with the range.

use super::Resolver;
use crate::diagnostic::Problem;
use crate::spec::codes;
use crate::spec::tree::{Node, Scalar, Value};

/// Where a bounded value is written in its node.
#[derive(Clone, Copy, PartialEq)]
enum Place {
    /// The property `name=`.
    Property,
    /// Every argument of the child node `name` (`diameters`).
    ChildArguments,
    /// Every argument of the node itself (`wall 1.5`).
    Arguments,
}

/// One bounded quantity: where it is written and its closed range.
struct Bound {
    /// The top-level node.
    node: &'static str,
    /// The property or child, as messages name it (the node's own name for its arguments).
    name: &'static str,
    /// Where the value is.
    place: Place,
    /// The least accepted value: millimetres for a length.
    min: f64,
    /// The greatest.
    max: f64,
    /// How the bound is shown: `mm` for a length (the value is compared in millimetres), `mm²`
    /// for an area (in square millimetres), `g/cm³`, `°`, or empty for a count.
    unit: &'static str,
}

/// Every bounded quantity. The ranges hold every FDM printer, nozzle and stock ball there is.
const BOUNDS: &[Bound] = &[
    bound("material", "density", 0.05, 25.0, "g/cm³"),
    bound("ball", "density", 0.5, 25.0, "g/cm³"),
    bound("ball", "clearance", 0.0, 5.0, "mm"),
    bound("ball", "pause-clearance", 0.0, 5.0, "mm"),
    bound("ball", "min-angle", 0.0, 45.0, "°"),
    Bound {
        node: "ball",
        name: "diameters",
        place: Place::ChildArguments,
        min: 0.5,
        max: 100.0,
        unit: "mm",
    },
    Bound {
        node: "wall",
        name: "wall",
        place: Place::Arguments,
        min: 0.0,
        max: 100.0,
        unit: "mm",
    },
    bound("print", "perimeters", 0.0, 100.0, ""),
    bound("print", "extrusion-width", 0.1, 5.0, "mm"),
    bound("print", "layer-height", 0.01, 2.0, "mm"),
    bound("print", "first-layer-height", 0.01, 2.0, "mm"),
    bound("print", "top-solid-layers", 0.0, 1000.0, ""),
    bound("print", "bottom-solid-layers", 0.0, 1000.0, ""),
    bound("print", "solid-infill-below-area", 0.0, 1e6, "mm²"),
];

/// A property's bound.
const fn bound(
    node: &'static str,
    name: &'static str,
    min: f64,
    max: f64,
    unit: &'static str,
) -> Bound {
    Bound {
        node,
        name,
        place: Place::Property,
        min,
        max,
        unit,
    }
}

impl Resolver<'_> {
    /// Refuses every print setting and ball property outside its physical range ([`BOUNDS`]).
    pub(super) fn check_physical_ranges(&mut self) {
        let to_mm = 1.0 / self.units.from_millimetres(1.0);
        let mut problems = Vec::new();
        for bound in BOUNDS {
            let Some(node) = self.top(bound.node) else {
                continue;
            };
            let scale = match bound.unit {
                "mm" => to_mm,
                "mm²" => to_mm * to_mm,
                _ => 1.0,
            };
            for value in written(node, bound) {
                let number = match value.scalar {
                    Scalar::Number(number) => number * scale,
                    Scalar::Count(count) => count as f64,
                    _ => continue,
                };
                if (bound.min..=bound.max).contains(&number) {
                    continue;
                }
                problems.push(out_of_range(bound, number, value));
            }
        }
        self.problems.extend(problems);
    }
}

/// The error for `value`, `number` in the bound's unit, outside `bound`.
fn out_of_range(bound: &Bound, number: f64, value: &Value) -> Problem {
    let unit = match bound.unit {
        "" => String::new(),
        "°" => "°".to_owned(),
        unit => format!(" {unit}"),
    };
    let what = match bound.place {
        Place::Arguments => format!("`{}`", bound.node),
        _ => format!("`{}` of `{}`", bound.name, bound.node),
    };
    let help = match bound.node {
        "print" => "the range holds every FDM printer, nozzle and part; docs/format.md lists each",
        "ball" => {
            "the range holds every stock ball (steel, tungsten, lead); docs/format.md lists each"
        }
        "wall" => "the range holds every printable wall; docs/format.md lists it",
        _ => "the range holds every printing material; docs/format.md lists each",
    };
    Problem::error(
        codes::OUT_OF_RANGE,
        format!(
            "{what} must be from {} to {}{unit}, found {number}{unit}",
            bound.min, bound.max
        ),
    )
    .with_label(value.span, "outside the range")
    .with_help(help)
}

/// The values of `bound` written in `node`.
fn written<'a>(node: &'a Node, bound: &Bound) -> Vec<&'a Value> {
    match bound.place {
        Place::Property => node.prop(bound.name).into_iter().collect(),
        Place::ChildArguments => node
            .child(bound.name)
            .map(|child| child.args.iter().flatten().collect())
            .unwrap_or_default(),
        Place::Arguments => node.args.iter().flatten().collect(),
    }
}
