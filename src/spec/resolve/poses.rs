//! The poses: each one's component transforms (written steps, or a rig animation or scene),
//! its `down` direction and its goals.

use miette::SourceSpan;
use nalgebra::{Isometry3, Point3, Vector3};

use super::{name_among, steps, Resolver};
use crate::diagnostic::Problem;
use crate::spec::codes;
use crate::spec::model::{Goal, Pose, Spanned};
use crate::spec::transform::compose;
use crate::spec::tree::Node;

impl Resolver<'_> {
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
            (None, Some(scene)) => source.scene_pose(scene, self.units, self.up, self.problems),
            (None, None) => None,
        }
        .unwrap_or_default()
    }

    pub(super) fn poses(&mut self) -> Vec<Pose> {
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
}
