//! The components: one per `component` node (its mesh, the frame its coordinates are read in,
//! its print orientation) and the parts of the `rig`, with their names checked unique.

use std::path::{Path, PathBuf};

use super::{name_among, Resolver};
use crate::diagnostic::Problem;
use crate::geometry::{MeshSelector, ReadPolicy};
use crate::spec::codes;
use crate::spec::model::{
    Axis, Component, FrameSource, MeshFrame, PrintOrientation, Spanned, Units,
};
use crate::spec::rig;
use crate::spec::transform::rotation;
use crate::spec::tree::Node;
use crate::spec::vocabulary;

impl Resolver<'_> {
    /// The components, in file order: one per `component` node, and the parts of the `rig`
    /// where it is written (read through `policy`).
    pub(super) fn components(&mut self, policy: &ReadPolicy) {
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
        self.rig_part_prints(node, first);
        self.rig = Some(source);
    }

    /// The print orientations a rig's `part` blocks give its parts, the components from index
    /// `first` on; reports a part the rig does not have and a part given two blocks.
    fn rig_part_prints(&mut self, node: &Node, first: usize) {
        let mut given: Vec<Spanned<String>> = Vec::new();
        for block in node.children_named("part") {
            let Some(name) = block.text_arg() else {
                continue;
            };
            if let Some(earlier) = given.iter().find(|earlier| earlier.value == name.value) {
                self.problems.push(
                    Problem::error(
                        codes::DUPLICATE_NAME,
                        format!("the rig has two `part` blocks for `{}`", name.value),
                    )
                    .with_label(name.span, "given again here")
                    .with_label(earlier.span, "first given here")
                    .with_help("put the part's settings in one `part` block"),
                );
                continue;
            }
            let parts = &self.components[first..];
            let Some(offset) = parts.iter().position(|part| part.name.value == name.value) else {
                let known = parts.iter().map(|part| part.name.value.as_str());
                let help = match vocabulary::suggest(&name.value, known) {
                    Some(close) => format!("did you mean `{close}`?"),
                    None => format!(
                        "the rig's parts are {}",
                        parts
                            .iter()
                            .map(|part| format!("`{}`", part.name.value))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                };
                self.problems.push(
                    Problem::error(
                        codes::RIG_UNKNOWN_PART,
                        format!("the rig has no part called `{}`", name.value),
                    )
                    .with_label(name.span, "not a part of the rig")
                    .with_help(help),
                );
                continue;
            };
            let print = block
                .child("print")
                .and_then(|print| self.print_orientation(print));
            self.components[first + offset].print = print;
            given.push(name);
        }
    }

    /// How a component's mesh coordinates become rest-frame coordinates: `mesh-units=`,
    /// `mesh-up=` and `scale=` as written; unwritten, the glTF specification's metres and +Y up
    /// for a `.gltf` or `.glb` file, millimetres (the file's own unit applied as it is read)
    /// and +Z up for a `.3mf` file, the project's units and up axis for any other (OBJ, STL).
    fn mesh_frame(&mut self, node: &Node, mesh: &Path) -> MeshFrame {
        let extension = mesh
            .extension()
            .and_then(|extension| extension.to_str())
            .unwrap_or_default()
            .to_ascii_lowercase();
        let mut frame = match extension.as_str() {
            "gltf" | "glb" => MeshFrame::gltf(),
            "3mf" => MeshFrame::three_mf(),
            _ => MeshFrame::project(self.units, self.up),
        };
        let written = node.text("mesh-units");
        if let (Some(written), FrameSource::ThreeMf) = (&written, frame.units_from) {
            self.problems.push(
                Problem::error(
                    codes::MESH_UNITS_STATED,
                    "a 3MF file states its own unit: `mesh-units=` cannot change it",
                )
                .with_label(written.span, "a unit for a file that has one")
                .with_help(
                    "remove `mesh-units=`: ballast reads the file in the unit its model states; \
                     use `scale=` to print it at another size",
                ),
            );
        } else if let Some(units) = written.and_then(|units| Units::from_keyword(&units.value)) {
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
}
