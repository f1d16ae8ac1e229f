//! The checked tree to the typed [`Project`]: defaults filled in, names resolved to indices, paths
//! resolved against the project file's folder, transforms composed, and the rules that span
//! several nodes checked (unique names, known components, infill bounds, exclusive properties).
//!
//! The resolver always builds a project, using a placeholder wherever a value was missing or bad;
//! such a value has already been reported, so the caller discards the project.

use std::path::{Path, PathBuf};

use miette::SourceSpan;
use nalgebra::{Isometry3, Point3, Vector3};

use super::bounds;
use super::codes;
use super::model::{
    Axis, Ball, Capsule, Component, FrameSource, Goal, Infill, MassModel, Material, MeshFrame,
    Optimize, Output, Pose, Print, PrintOrientation, Project, Spanned, Units,
};
use super::rig::{self, RigSource};
use super::stock::stock_diameters_mm;
use super::transform::{compose, rotation, Step};
use super::tree::Node;
use super::value::listing;
use super::vocabulary;
use crate::diagnostic::Problem;
use crate::geometry::{MeshSelector, ReadPolicy};

/// Builds the project from the checked top-level `nodes`, reporting cross-node problems.
/// A `rig` is read through `policy`.
pub fn resolve(
    nodes: &[Node],
    units: Units,
    project_path: &Path,
    policy: &ReadPolicy,
    problems: &mut Vec<Problem>,
) -> Project {
    let folder = project_path.parent().unwrap_or(Path::new(""));
    let mut resolver = Resolver {
        nodes,
        units,
        up: Axis::Z,
        folder,
        components: Vec::new(),
        rig: None,
        problems,
    };
    resolver.up = resolver.written_up();
    resolver.components(policy);
    let poses = resolver.poses();
    let capsules = resolver.capsules();
    let optimize = resolver.optimize(&capsules);
    if let Some(settings) = &optimize {
        resolver
            .problems
            .extend(bounds::optimizer_bounds(settings, &capsules, &poses));
    }
    let wall = resolver.top("wall").and_then(Node::number_arg);
    Project {
        units,
        up: resolver.up,
        material: resolver.material(),
        ball: resolver.ball(),
        infill: resolver.infill(),
        wall: wall.unwrap_or(units.from_millimetres(1.0)),
        print: resolver.print(),
        output: output(resolver.top("output"), folder, project_path),
        components: resolver.components,
        poses,
        capsules,
        optimize,
    }
}

/// The capsules and the infill of a solution file, from its checked top-level `nodes`, with
/// component names resolved against `project`. Reports unknown components, repeated capsule
/// names and an infill the project does not leave open.
pub fn resolve_solution(
    nodes: &[Node],
    project: &Project,
    problems: &mut Vec<Problem>,
) -> (Vec<Capsule>, Option<f64>) {
    let mut resolver = Resolver {
        nodes,
        units: project.units,
        up: project.up,
        folder: Path::new(""),
        components: project.components.clone(),
        rig: None,
        problems,
    };
    let capsules = resolver.capsules();
    let infill = resolver.solution_infill(&project.infill);
    (capsules, infill)
}

struct Resolver<'a> {
    nodes: &'a [Node],
    units: Units,
    /// The project's up axis (from the `up` node).
    up: Axis,
    folder: &'a Path,
    components: Vec<Component>,
    /// The `rig`, when there is one and it could be read.
    rig: Option<RigSource>,
    problems: &'a mut Vec<Problem>,
}

impl<'a> Resolver<'a> {
    /// The first top-level node called `name`.
    fn top(&self, name: &str) -> Option<&'a Node> {
        self.nodes.iter().find(|node| node.name == name)
    }

    /// The top-level nodes called `name`.
    fn all(&self, name: &'static str) -> impl Iterator<Item = &'a Node> + 'a {
        self.nodes.iter().filter(move |node| node.name == name)
    }

    fn written_up(&self) -> Axis {
        self.top("up")
            .and_then(Node::text_arg)
            .and_then(|axis| Axis::from_keyword(&axis.value))
            .unwrap_or(Axis::Z)
    }

    fn material(&self) -> Material {
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
    fn ball(&mut self) -> Ball {
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
            min_angle: number("min-angle").unwrap_or(3.0),
            diameters: match listed {
                Some(listed) => listed.numbers().unwrap_or_default(),
                None if any_size.is_some() => Vec::new(),
                None => stock(),
            },
        }
    }

    /// The print settings: PrusaSlicer's defaults where the `print` node says nothing.
    fn print(&self) -> Print {
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
    fn infill(&mut self) -> Infill {
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

    /// The components, in file order: one per `component` node, and the parts of the `rig`
    /// where it is written (read through `policy`).
    fn components(&mut self, policy: &ReadPolicy) {
        let nodes = self.nodes;
        for node in nodes
            .iter()
            .filter(|node| matches!(node.name, "component" | "rig"))
        {
            if node.name == "rig" {
                self.rig_components(node, policy);
                continue;
            }
            let name = name_among(&self.components, "component", node, self.problems, |c| {
                &c.name
            });
            let mesh = node.text("mesh").map_or_else(
                || Spanned::new(PathBuf::new(), node.name_span),
                |mesh| Spanned::new(self.folder.join(&mesh.value), mesh.span),
            );
            let selector = match (node.text("object"), node.text("node")) {
                (Some(object), Some(gltf_node)) => {
                    self.problems.push(
                        Problem::error(
                            codes::CONFLICTING_PROPERTIES,
                            "a component takes `object=` or `node=`, not both",
                        )
                        .with_label(gltf_node.span, "`node=` names a glTF node")
                        .with_label(object.span, "`object=` names an OBJ object")
                        .with_help("keep the one that matches the mesh file's format"),
                    );
                    MeshSelector::Whole
                }
                (Some(object), None) => MeshSelector::ObjObject(object.value),
                (None, Some(gltf_node)) => MeshSelector::GltfNode(gltf_node.value),
                (None, None) => MeshSelector::Whole,
            };
            let print = node
                .child("print")
                .and_then(|block| self.print_orientation(block));
            let frame = self.mesh_frame(node, &mesh.value);
            self.components.push(Component {
                name,
                mesh,
                selector,
                frame,
                print,
                span: node.span,
            });
        }
    }

    /// The parts of the rig `node` names, appended to the components; reports a part named as
    /// an earlier component.
    fn rig_components(&mut self, node: &Node, policy: &ReadPolicy) {
        let Some(path) = node.text_arg() else {
            return;
        };
        let frame = self.mesh_frame(node, Path::new(&path.value));
        let first = self.components.len();
        let Some((source, parts)) =
            rig::read(node, self.folder, frame, policy, first, self.problems)
        else {
            return;
        };
        for part in parts {
            if let Some(earlier) = self
                .components
                .iter()
                .find(|component| component.name.value == part.name.value)
            {
                self.problems.push(
                    Problem::error(
                        codes::DUPLICATE_NAME,
                        format!("two components are called `{}`", part.name.value),
                    )
                    .with_label(part.name.span, "a part of the rig")
                    .with_label(earlier.name.span, "first named here")
                    .with_help("rename the component, or list the rig's other nodes with `nodes`"),
                );
            }
            self.components.push(part);
        }
        self.rig = Some(source);
    }

    /// The component transforms a pose's `animation=` or `scene=` gives, when it has one;
    /// reports either without a rig, both together, and `time=` without `animation=`.
    fn animated(&mut self, node: &Node) -> Vec<(usize, Isometry3<f64>)> {
        let animation = node.text("animation");
        let scene = node.text("scene");
        if animation.is_none() {
            if let Some(time) = node.prop("time") {
                self.problems.push(
                    Problem::error(
                        codes::MISSING_PROPERTY,
                        "`time=` says when in an animation, but the pose has no `animation=`",
                    )
                    .with_label(time.span, "a time in no animation")
                    .with_help("add `animation=\"name\"`, or remove `time=`"),
                );
            }
        }
        let named = match (&animation, &scene) {
            (None, None) => return Vec::new(),
            (Some(animation), Some(scene)) => {
                self.problems.push(
                    Problem::error(
                        codes::RIG_TWO_SOURCES,
                        "the pose takes its parts both from an animation and from a scene",
                    )
                    .with_label(animation.span, "an animation")
                    .with_label(scene.span, "a scene")
                    .with_help("keep one of `animation=` and `scene=`"),
                );
                return Vec::new();
            }
            (Some(named), None) | (None, Some(named)) => named,
        };
        let Some(source) = &self.rig else {
            if self.top("rig").is_none() {
                let what = if scene.is_some() {
                    "a scene"
                } else {
                    "an animation"
                };
                self.problems.push(
                    Problem::error(
                        codes::RIG_MISSING,
                        format!(
                            "the pose takes its parts from {what}, but the project has no `rig`"
                        ),
                    )
                    .with_label(named.span, format!("{what} of no rig"))
                    .with_help(
                        "add `rig \"figure.glb\"` to read the parts, animations and scenes of a \
                         glTF file",
                    ),
                );
            }
            return Vec::new();
        };
        match (&animation, &scene) {
            (Some(animation), _) => {
                source.animated(node, animation, self.units, self.up, self.problems)
            }
            (None, Some(scene)) => source.from_scene(scene, self.units, self.up, self.problems),
            (None, None) => None,
        }
        .unwrap_or_default()
    }

    /// How a component's mesh coordinates become rest-frame coordinates: `mesh-units=`,
    /// `mesh-up=` and `scale=` as written; unwritten, the glTF specification's metres and +Y up
    /// for a `.gltf` or `.glb` file, the project's units and up axis for any other.
    fn mesh_frame(&self, node: &Node, mesh: &Path) -> MeshFrame {
        let is_gltf = mesh
            .extension()
            .and_then(|extension| extension.to_str())
            .is_some_and(|extension| {
                extension.eq_ignore_ascii_case("gltf") || extension.eq_ignore_ascii_case("glb")
            });
        let mut frame = if is_gltf {
            MeshFrame::gltf()
        } else {
            MeshFrame::project(self.units, self.up)
        };
        if let Some(units) = node
            .text("mesh-units")
            .and_then(|units| Units::from_keyword(&units.value))
        {
            frame.units = units;
            frame.units_from = FrameSource::Written;
        }
        if let Some(up) = node
            .text("mesh-up")
            .and_then(|up| Axis::from_keyword(&up.value))
        {
            frame.up = up;
            frame.up_from = FrameSource::Written;
        }
        frame.scale = node.number("scale").unwrap_or(1.0);
        frame
    }

    /// The orientation a component's `print` block declares, if any; reports a zero `down` and a
    /// `down` beside a `rotate`.
    fn print_orientation(&mut self, block: &Node) -> Option<PrintOrientation> {
        match (block.child("down"), block.child("rotate")) {
            (None, None) => None,
            (Some(down), Some(rotate)) => {
                self.problems.push(
                    Problem::error(
                        codes::PRINT_DOWN_WITH_ROTATE,
                        "a `print` block takes `down` or `rotate`, not both",
                    )
                    .with_label(down.span, "`down` names the facet on the bed")
                    .with_label(rotate.span, "`rotate` turns the component onto the bed")
                    .with_help("keep one of them"),
                );
                None
            }
            (Some(down), None) => {
                let direction = down.vector()?;
                if direction.norm() == 0.0 {
                    self.problems.push(
                        Problem::error(
                            codes::ZERO_PRINT_DOWN,
                            "`down` is the zero vector: it points nowhere",
                        )
                        .with_label(down.span, "this direction")
                        .with_help("give the rest-frame direction that points to the print bed, e.g. `down 0 0 -1`"),
                    );
                    return None;
                }
                Some(PrintOrientation::Down(Spanned::new(direction, down.span)))
            }
            (None, Some(rotate)) => {
                let degrees = rotate.vector()?;
                Some(PrintOrientation::Rotate(Spanned::new(
                    rotation(degrees),
                    rotate.span,
                )))
            }
        }
    }

    fn poses(&mut self) -> Vec<Pose> {
        let mut poses: Vec<Pose> = Vec::new();
        for node in self.all("pose") {
            let name = name_among(&poses, "pose", node, self.problems, |pose| &pose.name);
            let mut component_transforms = vec![Isometry3::identity(); self.components.len()];
            for (index, transform) in self.animated(node) {
                component_transforms[index] = transform;
            }
            let mut moved: Vec<(usize, SourceSpan)> = Vec::new();
            for block in node.children_named("component") {
                let Some(component) = block.text_arg() else {
                    continue;
                };
                let Some(index) = self.component_index(&component) else {
                    continue;
                };
                if let Some((_, first)) = moved.iter().find(|(moved, _)| *moved == index) {
                    self.problems.push(
                        Problem::error(
                            codes::DUPLICATE_NAME,
                            format!(
                                "pose `{}` moves component `{}` twice",
                                name.value, component.value
                            ),
                        )
                        .with_label(component.span, "moved again here")
                        .with_label(*first, "first moved here")
                        .with_help("put all of its steps in one `component` block"),
                    );
                    continue;
                }
                moved.push((index, component.span));
                component_transforms[index] = compose(steps(block));
            }
            let goals = node
                .children
                .iter()
                .filter_map(|child| self.goal(child))
                .collect();
            let down = self.down(node);
            poses.push(Pose {
                name,
                transform: compose(steps(node)),
                down,
                component_transforms,
                goals,
                span: node.span,
            });
        }
        poses
    }

    /// The `down` direction of a pose node, if it has one; reports a zero direction and a `down`
    /// beside pose-level transform steps.
    fn down(&mut self, node: &Node) -> Option<Spanned<Vector3<f64>>> {
        let child = node.child("down")?;
        let direction = child.vector()?;
        if let Some(step) = ["rotate", "translate", "pivot"]
            .iter()
            .find_map(|name| node.child(name))
        {
            self.problems.push(
                Problem::error(
                    codes::DOWN_WITH_STEPS,
                    format!("`down` sets the whole pose's placement; `{}` cannot go with it", step.name),
                )
                .with_label(step.span, "this step")
                .with_label(child.span, "the pose is placed by `down`")
                .with_help("remove the step, or write the pose's rotation instead of `down`; `component` blocks may still move components"),
            );
            return None;
        }
        if direction.norm() == 0.0 {
            self.problems.push(
                Problem::error(codes::ZERO_DOWN, "`down` is the zero vector: it points nowhere")
                    .with_label(child.span, "this direction")
                    .with_help("give the direction, in the rest frame, that points to the ground, e.g. `down 0 0 -1`; `ballast poses` lists the facets"),
            );
            return None;
        }
        Some(Spanned::new(direction, child.span))
    }

    /// The goal a child of a pose states, if it is a goal node.
    fn goal(&mut self, node: &Node) -> Option<Spanned<Goal>> {
        let number = |name, default: f64| node.number(name).unwrap_or(default);
        let goal = match node.name {
            "stand" => Goal::Stand {
                margin: number("margin", 0.0),
                contact_tolerance: node.number("contact-tolerance"),
            },
            "imbalance" => Goal::Imbalance {
                margin: number("margin", 0.0),
                contact_tolerance: node.number("contact-tolerance"),
            },
            "suspend" => Goal::Suspend {
                point: node.point().unwrap_or(Point3::origin()),
                component: node
                    .text("component")
                    .and_then(|name| self.component_index(&name))
                    .unwrap_or(0),
                tolerance: number("tolerance", 2.0),
                unique: node.flag("unique").unwrap_or(false),
            },
            "immerse" => Goal::Immerse {
                fluid_density: number("fluid-density", 1.0),
                min_distance: number("min-distance", 0.0),
                tolerance: number("tolerance", 2.0),
                mass_tolerance: node.number("mass-tolerance"),
                unique: node.flag("unique").unwrap_or(false),
            },
            _ => return None,
        };
        Some(Spanned::new(goal, node.span))
    }

    /// The `optimize` node, if any; reports a capsule count below the number of pinned capsules.
    fn optimize(&mut self, capsules: &[Capsule]) -> Option<Optimize> {
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
    fn solution_infill(&mut self, project: &Infill) -> Option<f64> {
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

    fn capsules(&mut self) -> Vec<Capsule> {
        let mut capsules: Vec<Capsule> = Vec::new();
        for node in self.all("capsule") {
            let name = name_among(&capsules, "capsule", node, self.problems, |c| &c.name);
            let component = node.text("component").map_or_else(
                || Spanned::new(0, node.name_span),
                |name| Spanned::new(self.component_index(&name).unwrap_or(0), name.span),
            );
            let end = |name| {
                node.child(name)
                    .and_then(Node::point)
                    .unwrap_or(Point3::origin())
            };
            capsules.push(Capsule {
                name,
                component,
                from: end("from"),
                to: end("to"),
                radius: node.number("radius").unwrap_or(1.0),
                pinned: node.flag("pinned").unwrap_or(false),
                span: node.span,
            });
        }
        capsules
    }

    /// The index of the component called `name`, or `None` after reporting that there is none.
    fn component_index(&mut self, name: &Spanned<String>) -> Option<usize> {
        if let Some(index) = self
            .components
            .iter()
            .position(|component| component.name.value == name.value)
        {
            return Some(index);
        }
        let mut known: Vec<&str> = Vec::new();
        for component in &self.components {
            if !known.contains(&component.name.value.as_str()) {
                known.push(&component.name.value);
            }
        }
        let help = match vocabulary::suggest(&name.value, known.iter().copied()) {
            Some(close) => format!("did you mean `{close}`?"),
            None if known.is_empty() => "no component is defined yet".to_owned(),
            None => format!(
                "the components are {}",
                listing(&known, |name| format!("`{name}`"), "and")
            ),
        };
        self.problems.push(
            Problem::error(
                codes::UNKNOWN_COMPONENT,
                format!("no component is called `{}`", name.value),
            )
            .with_label(name.span, "not a component")
            .with_help(help),
        );
        None
    }
}

/// The name argument of `node`, reporting a name already used by one of `earlier`.
fn name_among<T>(
    earlier: &[T],
    kind: &str,
    node: &Node,
    problems: &mut Vec<Problem>,
    name_of: impl Fn(&T) -> &Spanned<String>,
) -> Spanned<String> {
    let Some(name) = node.text_arg() else {
        return Spanned::new(String::new(), node.name_span);
    };
    if let Some(first) = earlier.iter().map(name_of).find(|other| **other == name) {
        problems.push(
            Problem::error(
                codes::DUPLICATE_NAME,
                format!("two {kind}s are called `{}`", name.value),
            )
            .with_label(name.span, "named again here")
            .with_label(first.span, "first named here")
            .with_help(format!("give each {kind} its own name")),
        );
    }
    name
}

/// The transform steps among `node`'s children, in file order.
fn steps(node: &Node) -> impl Iterator<Item = Step> + '_ {
    node.children.iter().filter_map(|child| match child.name {
        "pivot" => child.point().map(Step::Pivot),
        "rotate" => child.vector().map(Step::Rotate),
        "translate" => child.vector().map(Step::Translate),
        _ => None,
    })
}

/// Where the build writes: the `output` block's paths, else `build/<stem>.glb`,
/// `build/<stem>.report.json`, the folder `build/<stem>-stl`, `build/<stem>.3mf` and
/// `build/<stem>.insertion.md` next to the project file, and `<stem>.solution.kdl` beside it (a
/// file to commit, so not among the build products).
fn output(node: Option<&Node>, folder: &Path, project_path: &Path) -> Output {
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
