//! The project-wide settings: material, balls, print settings, infill, the `optimize` node, a
//! solution file's infill, and the output paths.

use std::path::{Path, PathBuf};

use miette::SourceSpan;

use super::Resolver;
use crate::diagnostic::Problem;
use crate::spec::codes;
use crate::spec::model::{Ball, Capsule, Infill, MassModel, Material, Optimize, Output, Print};
use crate::spec::stock::stock_diameters_mm;
use crate::spec::tree::Node;

/// The default least gap between a resting ball's top and the top of the paused layer, mm.
const DEFAULT_PAUSE_CLEARANCE_MM: f64 = 0.2;

impl Resolver<'_> {
    pub(super) fn material(&self) -> Material {
        let Some(node) = self.top("material") else {
            return Material {
                name: "PLA".to_owned(),
                density: 1.24,
            };
        };
        Material {
            name: node
                .text_arg()
                .map_or_else(|| "material".to_owned(), |name| name.value),
            density: node.number("density").unwrap_or(1.24),
        }
    }

    /// The `ball` node. Without a `diameters` child the balls are the stock sizes
    /// ([`stock_diameters_mm`]) in the project's units; `any-size=#true` allows any size instead,
    /// and is an error beside a `diameters` list.
    pub(super) fn ball(&mut self) -> Ball {
        let node = self.top("ball");
        let number = |name| node.and_then(|node| node.number(name));
        let listed = node.and_then(|node| node.child("diameters"));
        let any_size = node
            .filter(|node| node.flag("any-size") == Some(true))
            .and_then(|node| node.prop("any-size"))
            .map(|value| value.span);
        if let (Some(span), Some(listed)) = (any_size, listed) {
            self.problems.push(
                Problem::error(
                    codes::CONFLICTING_PROPERTIES,
                    "a `ball` takes `any-size=#true` or a `diameters` list, not both",
                )
                .with_label(span, "`any-size=#true` allows every size")
                .with_label(listed.span, "this list allows only these sizes")
                .with_help("keep the list to use those balls, or `any-size=#true` for a study"),
            );
        }
        let stock = || {
            stock_diameters_mm()
                .into_iter()
                .map(|mm| self.units.from_millimetres(mm))
                .collect()
        };
        Ball {
            density: number("density").unwrap_or(7.85),
            clearance: number("clearance").unwrap_or(self.units.from_millimetres(0.2)),
            pause_clearance: number("pause-clearance")
                .unwrap_or(self.units.from_millimetres(DEFAULT_PAUSE_CLEARANCE_MM)),
            min_angle: number("min-angle").unwrap_or(3.0),
            diameters: match listed {
                Some(listed) => listed.numbers().unwrap_or_default(),
                None if any_size.is_some() => Vec::new(),
                None => stock(),
            },
        }
    }

    /// The print settings: PrusaSlicer's defaults where the `print` node says nothing.
    pub(super) fn print(&self) -> Print {
        let defaults = Print::defaults(self.units);
        let Some(node) = self.top("print") else {
            return defaults;
        };
        let count = |name, default| node.count(name).unwrap_or(default);
        let number = |name, default| node.number(name).unwrap_or(default);
        Print {
            model: node
                .text("model")
                .and_then(|model| MassModel::from_keyword(&model.value))
                .unwrap_or(defaults.model),
            perimeters: count("perimeters", defaults.perimeters),
            extrusion_width: number("extrusion-width", defaults.extrusion_width),
            layer_height: number("layer-height", defaults.layer_height),
            first_layer_height: number("first-layer-height", defaults.first_layer_height),
            top_solid_layers: count("top-solid-layers", defaults.top_solid_layers),
            bottom_solid_layers: count("bottom-solid-layers", defaults.bottom_solid_layers),
            solid_infill_below_area: number(
                "solid-infill-below-area",
                defaults.solid_infill_below_area,
            ),
            surface_margin: defaults.surface_margin,
        }
    }

    /// The infill: a fixed fraction, or a range with the value at its top unless given.
    pub(super) fn infill(&mut self) -> Infill {
        let Some(node) = self.top("infill") else {
            return Infill {
                value: 1.0,
                range: None,
            };
        };
        let (has_min, has_max) = (node.has("min"), node.has("max"));
        if has_min != has_max {
            let (given, absent) = if has_min {
                ("min", "max")
            } else {
                ("max", "min")
            };
            self.problems.push(
                Problem::error(
                    codes::MISSING_PROPERTY,
                    format!("`infill` gives `{given}=` without `{absent}=`"),
                )
                .with_label(node.name_span, format!("no `{absent}=` here"))
                .with_help("a range needs both bounds, e.g. `infill min=0.2 max=1`"),
            );
        }
        let min = node.prop("min").zip(node.number("min"));
        let max = node.prop("max").zip(node.number("max"));
        let written = node
            .args
            .first()
            .and_then(Option::as_ref)
            .zip(node.number_arg());
        let mut out_of_range = |span: SourceSpan, message: String, label: &str| {
            self.problems.push(
                Problem::error(codes::OUT_OF_RANGE, message).with_label(span, label.to_owned()),
            );
        };
        if let Some((value, fraction)) = written {
            if fraction > 1.0 {
                out_of_range(
                    value.span,
                    format!("infill must be at most 1 (solid), found {fraction}"),
                    "more than solid",
                );
            }
        }
        let range = match (min, max) {
            (Some((min_value, min)), Some((max_value, max))) => {
                if max > 1.0 {
                    out_of_range(
                        max_value.span,
                        format!("the infill range must end at 1 (solid) or below, found {max}"),
                        "more than solid",
                    );
                }
                if min > max {
                    out_of_range(
                        min_value.span,
                        format!("the infill range starts at {min}, above its end {max}"),
                        "above `max`",
                    );
                }
                if let Some((value, fraction)) = written.filter(|_| min <= max) {
                    if fraction < min || fraction > max {
                        out_of_range(
                            value.span,
                            format!("infill {fraction} is outside its range {min}..{max}"),
                            "outside `min`..`max`",
                        );
                    }
                }
                Some((min, max))
            }
            _ => None,
        };
        let value = written
            .map(|(_, fraction)| fraction)
            .or(range.map(|(_, max)| max))
            .unwrap_or(1.0);
        Infill { value, range }
    }

    /// The `optimize` node, if any; reports a capsule count below the number of pinned capsules.
    pub(super) fn optimize(&mut self, capsules: &[Capsule]) -> Option<Optimize> {
        let node = self.top("optimize")?;
        let wanted = node
            .count("capsules")
            .map(|count| usize::try_from(count).unwrap_or(usize::MAX));
        let pinned: Vec<&Capsule> = capsules.iter().filter(|capsule| capsule.pinned).collect();
        if let (Some(wanted), Some(value)) = (wanted, node.prop("capsules")) {
            if wanted < pinned.len() {
                let mut problem = Problem::error(
                    codes::TOO_FEW_CAPSULES,
                    format!(
                        "`optimize` asks for {wanted} capsule{}, but {} are pinned",
                        if wanted == 1 { "" } else { "s" },
                        pinned.len()
                    ),
                )
                .with_label(value.span, "fewer than the pinned capsules");
                for capsule in &pinned {
                    problem = problem.with_label(capsule.name.span, "pinned");
                }
                self.problems.push(problem.with_help(format!(
                    "ask for at least {} capsules, or unpin some",
                    pinned.len()
                )));
            }
        }
        Some(Optimize {
            capsules: wanted,
            grid_cell: node.number("grid-cell"),
            grid_cell_span: node.prop("grid-cell").map(|value| value.span),
            tolerance_degrees: node.number("tolerance").unwrap_or(1.0),
            seed: node.count("seed").unwrap_or(0),
            span: node.span,
        })
    }

    /// A solution file's `infill`: a fraction at most 1, within the project's range, or equal to
    /// the project's fixed infill.
    pub(super) fn solution_infill(&mut self, project: &Infill) -> Option<f64> {
        let node = self.top("infill")?;
        let value = node.args.first().and_then(Option::as_ref)?;
        let fraction = node.number_arg()?;
        let problem = if fraction > 1.0 {
            Problem::error(
                codes::OUT_OF_RANGE,
                format!("infill must be at most 1 (solid), found {fraction}"),
            )
            .with_label(value.span, "more than solid")
        } else {
            match project.range {
                Some((min, max)) if fraction >= min && fraction <= max => return Some(fraction),
                None if fraction == project.value => return Some(fraction),
                Some((min, max)) => Problem::error(
                    codes::SOLUTION_INFILL,
                    format!("infill {fraction} is outside the project's range {min}..{max}"),
                )
                .with_label(value.span, "outside the project's `min`..`max`")
                .with_help("solve again, or widen the project's `infill min= max=`"),
                None => Problem::error(
                    codes::SOLUTION_INFILL,
                    format!(
                        "the project fixes the infill at {}, but the solution chooses {fraction}",
                        project.value
                    ),
                )
                .with_label(value.span, "not the project's infill")
                .with_help(
                    "remove the solution's `infill`, or give the project a range: \
                     `infill min=... max=...`",
                ),
            }
        };
        self.problems.push(problem);
        None
    }
}

/// Where the build writes: the `output` block's paths, else `build/<stem>.glb`,
/// `build/<stem>.report.json`, the folder `build/<stem>-stl`, `build/<stem>.3mf` and
/// `build/<stem>.insertion.md` next to the project file, and `<stem>.solution.kdl` beside it (a
/// file to commit, so not among the build products).
pub(super) fn output(node: Option<&Node>, folder: &Path, project_path: &Path) -> Output {
    let stem = project_path
        .file_stem()
        .map_or_else(|| "project".into(), |stem| stem.to_string_lossy());
    let path = |name: &str, default: PathBuf| {
        node.and_then(|node| node.child(name))
            .and_then(Node::text_arg)
            .map_or_else(|| folder.join(default), |path| folder.join(path.value))
    };
    let build = Path::new("build");
    Output {
        gltf: path("gltf", build.join(format!("{stem}.glb"))),
        report: path("report", build.join(format!("{stem}.report.json"))),
        solution: path("solution", PathBuf::from(format!("{stem}.solution.kdl"))),
        stl: path("stl", build.join(format!("{stem}-stl"))),
        prusa: path("prusa", build.join(format!("{stem}.3mf"))),
        sheet: path("sheet", build.join(format!("{stem}.insertion.md"))),
    }
}
