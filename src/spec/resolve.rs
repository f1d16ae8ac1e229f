//! The checked tree to the typed [`Project`]: defaults filled in, names resolved to indices, paths
//! resolved against the project file's folder, transforms composed, and the rules that span
//! several nodes checked (unique names, known components, infill bounds, exclusive properties).
//!
//! The resolver always builds a project, using a placeholder wherever a value was missing or bad;
//! such a value has already been reported, so the caller discards the project.
//!
//! This file holds the resolver, the capsules and the names they refer to; its submodules resolve
//! the components (`components.rs`), the poses and their goals (`poses.rs`) and the project-wide
//! settings (`settings.rs`).

mod components;
mod poses;
mod ranges;
mod settings;

use std::path::Path;

use nalgebra::Point3;

use super::bounds;
use super::codes;
use super::model::{Axis, Capsule, Component, Project, Spanned, Units};
use super::rig::RigSource;
use super::transform::Step;
use super::tree::Node;
use super::value::listing;
use super::vocabulary;
use crate::diagnostic::Problem;
use crate::geometry::ReadPolicy;

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
    resolver.check_physical_ranges();
    Project {
        units,
        up: resolver.up,
        material: resolver.material(),
        ball: resolver.ball(),
        infill: resolver.infill(),
        wall: wall.unwrap_or(units.from_millimetres(1.0)),
        print: resolver.print(),
        output: settings::output(resolver.top("output"), folder, project_path),
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
