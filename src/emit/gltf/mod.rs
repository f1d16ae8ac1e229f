//! Binary glTF (`.glb`) output: every pose as a named group, side by side in the default scene and
//! alone in a scene of its own.
//!
//! Everything is in glTF's own units and axes: metres, +Y up (the project's units and up axis are
//! converted in the vertices and transforms, so no node carries a unit scale). Node names are
//! unique within the file:
//!
//! - `<pose>`: a group node placing the pose beside the others along +X, a standing pose with its
//!   ground at height 0, a hanging or floating one at the height the project gives it; its `extras`
//!   are the pose's extras.
//!   - `<pose>/<component>`: the translucent component mesh placed by the pose's transform.
//!     - `<pose>/<component>/<capsule>`: the translucent capsule void.
//!     - `<pose>/<component>/<capsule>/ball`: the steel ball at its centre.
//!   - `<pose>/centre of mass`: a red marker; its `extras` are the pose's extras too.
//!   - `<pose>/gravity`: a thin yellow arrow from the centre of mass down -Y.
//!   - `<pose>/support polygon`: thin green tubes along its edges, when the pose stands and the
//!     polygon has two points or more.
//!   - `<pose>/string`: a thin tube up from the suspension point, when the pose hangs.
//!   - `<pose>/buoyancy centre`: a blue marker, when the pose is immersed.
//!
//! One scene per pose holds that pose's group; the last scene, `all poses`, the default, holds
//! every pose group (the same nodes: Blender, which imports every node of the file, sees each
//! pose once, side by side). Every mark is a triangle mesh: no line primitives, which some
//! renderers never draw. Meshes and materials are shared. With no poses, a single scene
//! `components` shows the components and capsules in their own frames. The output is a pure
//! function of the input: no maps are iterated in hash order and nothing depends on time.

use std::collections::BTreeSet;

use gltf::json;
use nalgebra::{Point3, UnitQuaternion, Vector3};

use super::scene::SceneModel;
use super::shapes;
use paint::Paint;

pub use check::GltfError;

mod buffer;
mod check;
mod meshes;
mod paint;

/// Marker radius as a fraction of the model's bounding-box diagonal.
const MARKER_FRACTION: f64 = 0.02;
/// Radius of the support polygon's tubes and of the string as a fraction of the diagonal.
const LINE_FRACTION: f64 = 0.004;
/// Gap between pose groups in the default scene as a fraction of the widest pose.
const LAYOUT_GAP: f64 = 0.25;
/// Name of the default scene, which holds every pose.
const ALL_POSES_SCENE: &str = "all poses";
/// Length of the gravity arrow and of the string as a fraction of the bounding-box diagonal.
const ARROW_FRACTION: f64 = 0.3;
/// Name of the scene written when the model has no poses.
const REST_SCENE: &str = "components";

/// Writes `model` as binary glTF. The same model always gives the same bytes.
pub fn write_glb(model: &SceneModel) -> Result<Vec<u8>, GltfError> {
    check::check(model)?;
    let mut writer = Writer::new(model);
    if model.poses.is_empty() {
        writer.rest_scene()?;
    } else {
        let offsets = writer.layout();
        let groups = offsets
            .iter()
            .enumerate()
            .map(|(pose, offset)| writer.pose_group(pose, offset))
            .collect::<Result<Vec<_>, _>>()?;
        for (pose, group) in model.poses.iter().zip(&groups) {
            writer.push_scene(&pose.name, vec![*group]);
        }
        // Last, so that three.js, which moves a node shared by scenes into the last scene that
        // lists it, has every pose in this default scene.
        let all = writer.push_scene(ALL_POSES_SCENE, groups);
        writer.root.scene = Some(all);
    }
    writer.finish()
}
/// Meshes shared by every scene, created on first use.
#[derive(Default)]
struct SharedMeshes {
    components: Vec<Option<json::Index<json::Mesh>>>,
    capsules: Vec<json::Index<json::Mesh>>,
    ball: Option<json::Index<json::Mesh>>,
    centre_of_mass: Option<json::Index<json::Mesh>>,
    gravity: Option<json::Index<json::Mesh>>,
    string: Option<json::Index<json::Mesh>>,
    buoyancy: Option<json::Index<json::Mesh>>,
}

/// Geometry of one primitive before it goes into the buffer.
struct Primitive<'a> {
    positions: &'a [Point3<f64>],
    normals: &'a [Vector3<f64>],
    /// Three per triangle.
    indices: Vec<u32>,
    paint: Paint,
}

struct Writer<'m> {
    model: &'m SceneModel,
    root: json::Root,
    bin: Vec<u8>,
    names: BTreeSet<String>,
    materials: Vec<Option<json::Index<json::Material>>>,
    meshes: SharedMeshes,
    /// The rotation taking the project's up axis onto glTF +Y.
    up_to_y: UnitQuaternion<f64>,
    /// Metres per project unit.
    metres: f64,
    /// Size of the markers, arrows and tubes, in metres.
    marker_radius: f64,
    arrow_length: f64,
    line_radius: f64,
}
impl<'m> Writer<'m> {
    fn new(model: &'m SceneModel) -> Self {
        let up = model.up.normalize();
        let up_to_y = UnitQuaternion::rotation_between(&up, &Vector3::y()).unwrap_or_else(|| {
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
        });
        let diagonal = bounding_diagonal(model) * model.unit_in_metres;
        let root = json::Root {
            asset: json::Asset {
                generator: Some(format!("ballast {}", env!("CARGO_PKG_VERSION"))),
                ..Default::default()
            },
            ..Default::default()
        };
        Writer {
            model,
            root,
            bin: Vec::new(),
            names: BTreeSet::new(),
            materials: vec![None; Paint::ALL.len()],
            meshes: SharedMeshes {
                components: vec![None; model.components.len()],
                ..Default::default()
            },
            up_to_y,
            metres: model.unit_in_metres,
            marker_radius: MARKER_FRACTION * diagonal,
            arrow_length: ARROW_FRACTION * diagonal,
            line_radius: LINE_FRACTION * diagonal,
        }
    }

    /// A world point of the project in glTF's frame: metres, +Y up.
    fn to_gltf(&self, p: &Point3<f64>) -> Point3<f64> {
        Point3::from(self.up_to_y * p.coords * self.metres)
    }

    /// Where each pose group goes in the default scene, metres: side by side along +X in pose
    /// order with a gap, centred on the origin; a standing pose lifted or lowered so its ground
    /// is at height 0, a hanging or floating one left at its height.
    fn layout(&self) -> Vec<Vector3<f64>> {
        let model = self.model;
        let spans: Vec<(f64, f64)> = model
            .poses
            .iter()
            .map(|pose| {
                let xs = model
                    .components
                    .iter()
                    .zip(&pose.component_transforms)
                    .flat_map(|(c, t)| c.positions.iter().map(move |p| t * p))
                    .chain(std::iter::once(pose.centre_of_mass))
                    .map(|p| self.to_gltf(&p).x);
                let (min, max) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x), hi.max(x))
                });
                // Room for the markers on both sides.
                (min - self.marker_radius, max + self.marker_radius)
            })
            .collect();
        let widest = spans.iter().map(|(lo, hi)| hi - lo).fold(0.0, f64::max);
        let gap = LAYOUT_GAP * widest;
        let total: f64 =
            spans.iter().map(|(lo, hi)| hi - lo).sum::<f64>() + gap * (spans.len() - 1) as f64;
        let mut cursor = -total / 2.0;
        model
            .poses
            .iter()
            .zip(&spans)
            .map(|(pose, (lo, hi))| {
                let x = cursor - lo;
                cursor += hi - lo + gap;
                let y = pose.ground.map_or(0.0, |ground| -ground * self.metres);
                Vector3::new(x, y, 0.0)
            })
            .collect()
    }

    /// The scene written when there are no poses: components and capsules in their own frames.
    fn rest_scene(&mut self) -> Result<(), GltfError> {
        let rotation = unit_quaternion(&self.up_to_y, || "the up axis".to_owned())?;
        let identity = rotation == json::scene::UnitQuaternion::default().0;
        let root = self.push_node(
            REST_SCENE.to_owned(),
            json::Node {
                rotation: (!identity).then_some(json::scene::UnitQuaternion(rotation)),
                ..Default::default()
            },
        );
        let mut children = Vec::new();
        for component in 0..self.model.components.len() {
            let name = format!("{REST_SCENE}/{}", self.model.components[component].name);
            let node = self.component_node(&name, component, None)?;
            children.push(node);
        }
        self.set_children(root, children);
        self.push_scene(REST_SCENE, vec![root]);
        Ok(())
    }

    /// The group node of one pose, placed at `offset` (metres), with everything the pose shows.
    fn pose_group(
        &mut self,
        pose_index: usize,
        offset: &Vector3<f64>,
    ) -> Result<json::Index<json::Node>, GltfError> {
        let model = self.model;
        let pose = &model.poses[pose_index];
        let extras = raw_extras(&pose.extras)?;
        let translation = f32x3(offset, || format!("the place of pose `{}`", pose.name))?;
        let root = self.push_node(
            pose.name.clone(),
            json::Node {
                translation: (translation != [0.0; 3]).then_some(translation),
                extras: extras.clone(),
                ..Default::default()
            },
        );
        let prefix = self.node(root).name.clone().unwrap_or_default();
        let mut children = Vec::new();

        for (component, transform) in pose.component_transforms.iter().enumerate() {
            let name = format!("{prefix}/{}", model.components[component].name);
            let node = self.component_node(&name, component, Some(pose_index))?;
            let moved = self.up_to_y * transform.translation.vector * self.metres;
            let translation = f32x3(&moved, || format!("the translation of `{name}`"))?;
            let rotation = unit_quaternion(&(self.up_to_y * transform.rotation), || {
                format!("the rotation of `{name}`")
            })?;
            let n = self.node_mut(node);
            n.translation = Some(translation);
            n.rotation = Some(json::scene::UnitQuaternion(rotation));
            children.push(node);
        }

        // Centre of mass with the gravity arrow.
        let com = &self.to_gltf(&pose.centre_of_mass);
        let mesh = self.centre_of_mass_mesh()?;
        let node = self.marker_node(
            format!("{prefix}/centre of mass"),
            mesh,
            com,
            self.marker_radius,
        )?;
        self.node_mut(node).extras = extras;
        children.push(node);
        let mesh = self.gravity_mesh()?;
        children.push(self.marker_node(
            format!("{prefix}/gravity"),
            mesh,
            com,
            self.arrow_length,
        )?);

        // Support polygon: tubes along a loop or a segment, only where the pose stands.
        let support: Vec<Point3<f64>> = pose
            .support_polygon
            .iter()
            .map(|p| self.to_gltf(p))
            .collect();
        let tubes = shapes::polygon_tubes(&support, self.line_radius);
        if pose.ground.is_some() && !tubes.triangles.is_empty() {
            let name = format!("{prefix}/support polygon");
            let mesh = self.shape_mesh(&name, &tubes, Paint::SupportPolygon)?;
            let node = self.push_node(
                name,
                json::Node {
                    mesh: Some(mesh),
                    ..Default::default()
                },
            );
            children.push(node);
        }

        if let Some(point) = &pose.suspension_point {
            let point = &self.to_gltf(point);
            let mesh = self.string_mesh()?;
            children.push(self.marker_node(
                format!("{prefix}/string"),
                mesh,
                point,
                self.arrow_length,
            )?);
        }
        if let Some(point) = &pose.buoyancy_centre {
            let point = &self.to_gltf(point);
            let mesh = self.buoyancy_mesh()?;
            children.push(self.marker_node(
                format!("{prefix}/buoyancy centre"),
                mesh,
                point,
                self.marker_radius,
            )?);
        }

        self.set_children(root, children);
        Ok(root)
    }

    /// A component node with its capsules and, in a pose, its balls as children.
    /// The node's own transform is left at identity.
    fn component_node(
        &mut self,
        name: &str,
        component: usize,
        pose: Option<usize>,
    ) -> Result<json::Index<json::Node>, GltfError> {
        let model = self.model;
        let mesh = self.component_mesh(component)?;
        let node = self.push_node(
            name.to_owned(),
            json::Node {
                mesh,
                ..Default::default()
            },
        );
        let prefix = self.node(node).name.clone().unwrap_or_default();
        let mut children = Vec::new();
        for (index, capsule) in model.capsules.iter().enumerate() {
            if capsule.component != component {
                continue;
            }
            let capsule_name = format!("{prefix}/{}", capsule.name);
            let mesh = self.capsule_mesh(index)?;
            let capsule_node = self.push_node(
                capsule_name,
                json::Node {
                    mesh: Some(mesh),
                    ..Default::default()
                },
            );
            children.push(capsule_node);
            if let Some(pose) = pose {
                let ball_name = format!(
                    "{}/ball",
                    self.node(capsule_node).name.clone().unwrap_or_default()
                );
                let centre =
                    Point3::from(model.poses[pose].ball_centres[index].coords * self.metres);
                let mesh = self.ball_mesh()?;
                let radius = capsule.ball_radius * self.metres;
                children.push(self.marker_node(ball_name, mesh, &centre, radius)?);
            }
        }
        self.set_children(node, children);
        Ok(node)
    }

    /// A node drawing `mesh` translated to `at` and scaled uniformly by `scale`.
    fn marker_node(
        &mut self,
        name: String,
        mesh: json::Index<json::Mesh>,
        at: &Point3<f64>,
        scale: f64,
    ) -> Result<json::Index<json::Node>, GltfError> {
        let translation = f32x3(&at.coords, || format!("the position of `{name}`"))?;
        let s = scale as f32;
        if !(s.is_finite() && s > 0.0) {
            return Err(GltfError::NonFinite(format!("the size of `{name}`")));
        }
        let node = json::Node {
            mesh: Some(mesh),
            translation: Some(translation),
            scale: Some([s; 3]),
            ..Default::default()
        };
        Ok(self.push_node(name, node))
    }

    /// Adds `node` under `name`, made unique within the file.
    fn push_node(&mut self, name: String, node: json::Node) -> json::Index<json::Node> {
        let name = self.unique(name);
        self.root.push(json::Node {
            name: Some(name),
            ..node
        })
    }

    fn node(&self, index: json::Index<json::Node>) -> &json::Node {
        &self.root.nodes[index.value()]
    }

    fn node_mut(&mut self, index: json::Index<json::Node>) -> &mut json::Node {
        &mut self.root.nodes[index.value()]
    }

    fn set_children(
        &mut self,
        parent: json::Index<json::Node>,
        children: Vec<json::Index<json::Node>>,
    ) {
        self.node_mut(parent).children = (!children.is_empty()).then_some(children);
    }

    /// Adds a scene of the root `nodes`; the first one added is the default until another is set.
    fn push_scene(
        &mut self,
        name: &str,
        nodes: Vec<json::Index<json::Node>>,
    ) -> json::Index<json::Scene> {
        let scene = self.root.push(json::Scene {
            extensions: None,
            extras: None,
            name: Some(name.to_owned()),
            nodes,
        });
        if self.root.scene.is_none() {
            self.root.scene = Some(scene);
        }
        scene
    }

    /// `name`, or `name (2)`, `name (3)`… if it is already taken.
    fn unique(&mut self, name: String) -> String {
        let mut candidate = name.clone();
        let mut n = 2;
        while self.names.contains(&candidate) {
            candidate = format!("{name} ({n})");
            n += 1;
        }
        self.names.insert(candidate.clone());
        candidate
    }
}
/// The pose's extras as raw JSON; `null` means none.
fn raw_extras(value: &serde_json::Value) -> Result<json::Extras, GltfError> {
    if value.is_null() {
        return Ok(None);
    }
    Ok(Some(serde_json::value::to_raw_value(value)?))
}

fn f32x3(v: &Vector3<f64>, what: impl FnOnce() -> String) -> Result<[f32; 3], GltfError> {
    let out = [v.x as f32, v.y as f32, v.z as f32];
    if out.iter().all(|c| c.is_finite()) {
        Ok(out)
    } else {
        Err(GltfError::NonFinite(what()))
    }
}

/// A glTF rotation `[x, y, z, w]`, renormalised in single precision.
fn unit_quaternion(
    q: &UnitQuaternion<f64>,
    what: impl FnOnce() -> String,
) -> Result<[f32; 4], GltfError> {
    let c = q.coords.cast::<f32>();
    let norm = c.norm();
    if !(norm.is_finite() && norm > 0.0) {
        return Err(GltfError::NonFinite(what()));
    }
    let c = c / norm;
    Ok([c.x, c.y, c.z, c.w])
}

/// The largest bounding-box diagonal of the components over all poses (in their own frames
/// when there are no poses), in project units; 1 when there is nothing to measure.
fn bounding_diagonal(model: &SceneModel) -> f64 {
    let diagonal = |points: &mut dyn Iterator<Item = Point3<f64>>| {
        let mut min = Vector3::repeat(f64::INFINITY);
        let mut max = Vector3::repeat(f64::NEG_INFINITY);
        for p in points {
            min = min.inf(&p.coords);
            max = max.sup(&p.coords);
        }
        let d = (max - min).norm();
        if d.is_finite() {
            d
        } else {
            0.0
        }
    };
    let d = if model.poses.is_empty() {
        diagonal(
            &mut model
                .components
                .iter()
                .flat_map(|c| c.positions.iter().copied()),
        )
    } else {
        model
            .poses
            .iter()
            .map(|pose| {
                diagonal(
                    &mut model
                        .components
                        .iter()
                        .zip(&pose.component_transforms)
                        .flat_map(|(c, t)| c.positions.iter().map(move |p| t * p)),
                )
            })
            .fold(0.0, f64::max)
    };
    if d > 0.0 {
        d
    } else {
        1.0
    }
}
