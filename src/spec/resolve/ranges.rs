//! The physical range of each print setting and ball property: a value outside it describes no
//! printer or ball that exists (a layer a nanometre thick, a ball a kilometre wide) and would
//! only make the print model ask for unbounded memory or the optimizer place capsules outside
//! the part. Each is refused at its span with the range.

use super::Resolver;
use crate::diagnostic::Problem;
use crate::spec::codes;
use crate::spec::tree::{Node, Scalar, Value};

/// One bounded quantity: where it is written and its closed range.
struct Bound {
    /// The top-level node.
    node: &'static str,
    /// The property of that node, or its child whose arguments are bounded (`diameters`).
    name: &'static str,
    /// Whether `name` is a child node (its every argument bounded) rather than a property.
    child: bool,
    /// The least accepted value: millimetres for a length.
    min: f64,
    /// The greatest.
    max: f64,
    /// How the bound is shown: `mm` for a length (the value is compared in millimetres),
    /// `g/cm³`, or empty for a count.
    unit: &'static str,
}

/// Every bounded quantity. The ranges hold every FDM printer, nozzle and stock ball there is.
const BOUNDS: &[Bound] = &[
    bound("material", "density", 0.05, 25.0, "g/cm³"),
    bound("ball", "density", 0.5, 25.0, "g/cm³"),
    bound("ball", "clearance", 0.0, 5.0, "mm"),
    Bound {
        node: "ball",
        name: "diameters",
        child: true,
        min: 0.5,
        max: 100.0,
        unit: "mm",
    },
    bound("print", "perimeters", 0.0, 100.0, ""),
    bound("print", "extrusion-width", 0.1, 5.0, "mm"),
    bound("print", "layer-height", 0.01, 2.0, "mm"),
    bound("print", "first-layer-height", 0.01, 2.0, "mm"),
    bound("print", "top-solid-layers", 0.0, 1000.0, ""),
    bound("print", "bottom-solid-layers", 0.0, 1000.0, ""),
];

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
        child: false,
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
            for value in written(node, bound) {
                let (number, shown) = match value.scalar {
                    Scalar::Number(number) if bound.unit == "mm" => {
                        (number * to_mm, number * to_mm)
                    }
                    Scalar::Number(number) => (number, number),
                    Scalar::Count(count) => (count as f64, count as f64),
                    _ => continue,
                };
                if (bound.min..=bound.max).contains(&number) {
                    continue;
                }
                let unit = if bound.unit.is_empty() {
                    String::new()
                } else {
                    format!(" {}", bound.unit)
                };
                problems.push(
                    Problem::error(
                        codes::OUT_OF_RANGE,
                        format!(
                            "`{}` of `{}` must be from {} to {}{unit}, found {shown}{unit}",
                            bound.name, bound.node, bound.min, bound.max
                        ),
                    )
                    .with_label(value.span, "outside the range")
                    .with_help(match bound.node {
                        "print" => "the range holds every FDM printer, nozzle and part; docs/format.md lists each",
                        "ball" => "the range holds every stock ball (steel, tungsten, lead); docs/format.md lists each",
                        _ => "the range holds every printing material; docs/format.md lists each",
                    }),
                );
            }
        }
        self.problems.extend(problems);
    }
}

/// The values of `bound` written in `node`.
fn written<'a>(node: &'a Node, bound: &Bound) -> Vec<&'a Value> {
    if bound.child {
        node.child(bound.name)
            .map(|child| child.args.iter().flatten().collect())
            .unwrap_or_default()
    } else {
        node.prop(bound.name).into_iter().collect()
    }
}
