//! Binary glTF (`.glb`) output: one scene per pose of the model.
//!
//! Layout of each scene, with node names unique within the file:
//!
//! - `<pose>`: the root. It rotates the project's up axis onto glTF +Y and scales project units
//!   to metres; its `extras` are the pose's extras. Everything below is in project units.
//!   - `<pose>/<component>`: the component mesh placed by the pose's transform.
//!     - `<pose>/<component>/<capsule>`: the translucent capsule void.
//!     - `<pose>/<component>/<capsule>/ball`: the steel ball at its centre.
//!   - `<pose>/centre of mass`: a red marker; its `extras` are the pose's extras too.
//!   - `<pose>/gravity`: a yellow arrow from the centre of mass along -up.
//!   - `<pose>/support polygon`: a green line loop (absent with fewer than two points).
//!   - `<pose>/string`: a line up from the suspension point, when the pose hangs.
//!   - `<pose>/buoyancy centre`: a blue marker, when the pose is immersed.
//!
//! Meshes and materials are shared between scenes. With no poses, a single scene `components`
//! shows the components and capsules in their own frames. The output is a pure function of the
//! input: no maps are iterated in hash order and nothing depends on time.

use std::collections::BTreeSet;

use gltf::json;
use json::validation::{Checked, USize64};
use nalgebra::{Point3, UnitQuaternion, Vector3};

use super::scene::SceneModel;
use super::shapes::{self, ShapeMesh};

/// Marker radius as a fraction of the model's bounding-box diagonal.
const MARKER_FRACTION: f64 = 0.02;
/// Length of the gravity arrow and of the string as a fraction of the bounding-box diagonal.
const ARROW_FRACTION: f64 = 0.3;
/// Name of the scene written when the model has no poses.
const REST_SCENE: &str = "components";

/// What can stop a model from being written as glTF.
#[derive(Debug, thiserror::Error)]
pub enum GltfError {
    #[error("the unit length must be a positive number of metres, got {0}")]
    InvalidUnit(f64),
    #[error("the up axis must be a finite non-zero vector, got ({}, {}, {})", .0.x, .0.y, .0.z)]
    InvalidUp(Vector3<f64>),
    #[error("capsule `{capsule}` belongs to component #{component}, but there are only {count} components")]
    ComponentOutOfRange {
        capsule: String,
        component: usize,
        count: usize,
    },
    #[error("capsule `{capsule}` needs a positive radius and ball radius, got {radius} and {ball_radius}")]
    InvalidCapsule {
        capsule: String,
        radius: f64,
        ball_radius: f64,
    },
    #[error(
        "component `{component}` has a triangle using vertex {index}, but only {vertices} vertices"
    )]
    TriangleOutOfRange {
        component: String,
        index: u32,
        vertices: usize,
    },
    #[error("component `{component}` has {vertices} vertices, more than glTF indices can address")]
    TooManyVertices { component: String, vertices: usize },
    #[error("pose `{pose}` places {found} components, but the model has {expected}")]
    TransformCount {
        pose: String,
        expected: usize,
        found: usize,
    },
    #[error("pose `{pose}` has {found} ball centres, but the model has {expected} capsules")]
    BallCount {
        pose: String,
        expected: usize,
        found: usize,
    },
    #[error("{0} is not finite in single precision")]
    NonFinite(String),
    #[error("the glTF file would be {bytes} bytes, over the 4 GiB limit of binary glTF")]
    TooLarge { bytes: u64 },
    #[error("could not encode the glTF JSON: {0}")]
    Json(#[from] serde_json::Error),
    #[error("could not encode the binary glTF container: {0}")]
    Container(#[source] gltf::Error),
}

/// Writes `model` as binary glTF. The same model always gives the same bytes.
pub fn write_glb(model: &SceneModel) -> Result<Vec<u8>, GltfError> {
    check(model)?;
    let mut writer = Writer::new(model);
    if model.poses.is_empty() {
        writer.rest_scene()?;
    } else {
        for pose in 0..model.poses.len() {
            writer.pose_scene(pose)?;
        }
    }
    writer.finish()
}

/// Structural checks that do not depend on the numbers being drawable.
fn check(model: &SceneModel) -> Result<(), GltfError> {
    if !(model.unit_in_metres.is_finite() && model.unit_in_metres > 0.0) {
        return Err(GltfError::InvalidUnit(model.unit_in_metres));
    }
    if !(model.up.iter().all(|c| c.is_finite()) && model.up.norm() > 0.0) {
        return Err(GltfError::InvalidUp(model.up));
    }
    for component in &model.components {
        let vertices = component.positions.len();
        if u32::try_from(vertices).is_err() {
            return Err(GltfError::TooManyVertices {
                component: component.name.clone(),
                vertices,
            });
        }
        if let Some(&index) = component
            .triangles
            .iter()
            .flatten()
            .find(|&&i| i as usize >= vertices)
        {
            return Err(GltfError::TriangleOutOfRange {
                component: component.name.clone(),
                index,
                vertices,
            });
        }
    }
    for capsule in &model.capsules {
        if capsule.component >= model.components.len() {
            return Err(GltfError::ComponentOutOfRange {
                capsule: capsule.name.clone(),
                component: capsule.component,
                count: model.components.len(),
            });
        }
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !(positive(capsule.radius) && positive(capsule.ball_radius)) {
            return Err(GltfError::InvalidCapsule {
                capsule: capsule.name.clone(),
                radius: capsule.radius,
                ball_radius: capsule.ball_radius,
            });
        }
    }
    for pose in &model.poses {
        if pose.component_transforms.len() != model.components.len() {
            return Err(GltfError::TransformCount {
                pose: pose.name.clone(),
                expected: model.components.len(),
                found: pose.component_transforms.len(),
            });
        }
        if pose.ball_centres.len() != model.capsules.len() {
            return Err(GltfError::BallCount {
                pose: pose.name.clone(),
                expected: model.capsules.len(),
                found: pose.ball_centres.len(),
            });
        }
    }
    Ok(())
}

/// The materials the writer uses, each created on first use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Paint {
    Component,
    Capsule,
    Steel,
    CentreOfMass,
    SupportPolygon,
    Gravity,
    String,
    Buoyancy,
}

impl Paint {
    const ALL: [Paint; 8] = [
        Paint::Component,
        Paint::Capsule,
        Paint::Steel,
        Paint::CentreOfMass,
        Paint::SupportPolygon,
        Paint::Gravity,
        Paint::String,
        Paint::Buoyancy,
    ];

    fn material(self) -> json::Material {
        // (name, base colour, metallic, roughness, emissive, blend)
        let (name, colour, metallic, roughness, emissive, blend) = match self {
            Paint::Component => ("component", [0.8, 0.8, 0.8, 1.0], 0.0, 0.7, false, false),
            Paint::Capsule => ("capsule", [0.2, 0.6, 1.0, 0.35], 0.0, 0.3, false, true),
            Paint::Steel => ("steel", [0.56, 0.57, 0.58, 1.0], 1.0, 0.25, false, false),
            Paint::CentreOfMass => (
                "centre of mass",
                [1.0, 0.0, 0.0, 1.0],
                0.0,
                0.5,
                true,
                false,
            ),
            Paint::SupportPolygon => (
                "support polygon",
                [0.0, 0.8, 0.2, 1.0],
                0.0,
                1.0,
                true,
                false,
            ),
            Paint::Gravity => ("gravity", [1.0, 0.85, 0.0, 1.0], 0.0, 1.0, true, false),
            Paint::String => ("string", [0.9, 0.9, 0.85, 1.0], 0.0, 1.0, true, false),
            Paint::Buoyancy => (
                "buoyancy centre",
                [0.0, 0.3, 1.0, 1.0],
                0.0,
                0.5,
                true,
                false,
            ),
        };
        let emissive_factor = if emissive {
            [colour[0], colour[1], colour[2]]
        } else {
            [0.0; 3]
        };
        json::Material {
            alpha_mode: Checked::Valid(if blend {
                json::material::AlphaMode::Blend
            } else {
                json::material::AlphaMode::Opaque
            }),
            double_sided: false,
            name: Some(name.to_owned()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(colour),
                metallic_factor: json::material::StrengthFactor(metallic),
                roughness_factor: json::material::StrengthFactor(roughness),
                ..Default::default()
            },
            emissive_factor: json::material::EmissiveFactor(emissive_factor),
            ..Default::default()
        }
    }
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
    /// `None` draws the vertices in order.
    indices: Option<Vec<u32>>,
    mode: json::mesh::Mode,
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
    /// The unit up axis.
    up: Vector3<f64>,
    /// Size of the markers and arrows, in project units.
    marker_radius: f64,
    arrow_length: f64,
}

impl<'m> Writer<'m> {
    fn new(model: &'m SceneModel) -> Self {
        let up = model.up.normalize();
        let up_to_y = UnitQuaternion::rotation_between(&up, &Vector3::y()).unwrap_or_else(|| {
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
        });
        let diagonal = bounding_diagonal(model);
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
            up,
            marker_radius: MARKER_FRACTION * diagonal,
            arrow_length: ARROW_FRACTION * diagonal,
        }
    }

    /// The scene written when there are no poses: components and capsules in their own frames.
    fn rest_scene(&mut self) -> Result<(), GltfError> {
        let root = self.root_node(REST_SCENE, None)?;
        let mut children = Vec::new();
        for component in 0..self.model.components.len() {
            let name = format!("{REST_SCENE}/{}", self.model.components[component].name);
            let node = self.component_node(&name, component, None)?;
            children.push(node);
        }
        self.set_children(root, children);
        self.push_scene(REST_SCENE, root);
        Ok(())
    }

    fn pose_scene(&mut self, pose_index: usize) -> Result<(), GltfError> {
        let model = self.model;
        let pose = &model.poses[pose_index];
        let extras = raw_extras(&pose.extras)?;
        let root = self.root_node(&pose.name, extras.clone())?;
        let prefix = self.node(root).name.clone().unwrap_or_default();
        let mut children = Vec::new();

        for (component, transform) in pose.component_transforms.iter().enumerate() {
            let name = format!("{prefix}/{}", model.components[component].name);
            let node = self.component_node(&name, component, Some(pose_index))?;
            let translation = f32x3(&transform.translation.vector, || {
                format!("the translation of `{name}`")
            })?;
            let rotation =
                unit_quaternion(&transform.rotation, || format!("the rotation of `{name}`"))?;
            let n = self.node_mut(node);
            n.translation = Some(translation);
            n.rotation = Some(json::scene::UnitQuaternion(rotation));
            children.push(node);
        }

        // Centre of mass with the gravity arrow.
        let com = &pose.centre_of_mass;
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

        // Support polygon: a loop, a segment, or nothing.
        let support = &pose.support_polygon;
        if support.len() >= 2 {
            let mode = if support.len() == 2 {
                json::mesh::Mode::Lines
            } else {
                json::mesh::Mode::LineLoop
            };
            let name = format!("{prefix}/support polygon");
            let mesh = self.mesh(
                &name,
                Primitive {
                    positions: support,
                    normals: &[],
                    indices: None,
                    mode,
                    paint: Paint::SupportPolygon,
                },
            )?;
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
            let mesh = self.string_mesh()?;
            children.push(self.marker_node(
                format!("{prefix}/string"),
                mesh,
                point,
                self.arrow_length,
            )?);
        }
        if let Some(point) = &pose.buoyancy_centre {
            let mesh = self.buoyancy_mesh()?;
            children.push(self.marker_node(
                format!("{prefix}/buoyancy centre"),
                mesh,
                point,
                self.marker_radius,
            )?);
        }

        self.set_children(root, children);
        self.push_scene(&pose.name, root);
        Ok(())
    }

    /// The root node of a scene: project up onto +Y, project units to metres.
    fn root_node(
        &mut self,
        name: &str,
        extras: json::Extras,
    ) -> Result<json::Index<json::Node>, GltfError> {
        let rotation = unit_quaternion(&self.up_to_y, || "the up axis".to_owned())?;
        let s = self.model.unit_in_metres as f32;
        if !(s.is_finite() && s > 0.0) {
            return Err(GltfError::NonFinite("the unit length".to_owned()));
        }
        let identity = rotation == json::scene::UnitQuaternion::default().0;
        let node = json::Node {
            rotation: (!identity).then_some(json::scene::UnitQuaternion(rotation)),
            scale: (s != 1.0).then_some([s; 3]),
            extras,
            ..Default::default()
        };
        Ok(self.push_node(name.to_owned(), node))
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
                let centre = &model.poses[pose].ball_centres[index];
                let mesh = self.ball_mesh()?;
                children.push(self.marker_node(ball_name, mesh, centre, capsule.ball_radius)?);
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

    fn component_mesh(
        &mut self,
        component: usize,
    ) -> Result<Option<json::Index<json::Mesh>>, GltfError> {
        if let Some(mesh) = self.meshes.components[component] {
            return Ok(Some(mesh));
        }
        let c = &self.model.components[component];
        if c.triangles.is_empty() {
            return Ok(None);
        }
        let mesh = self.mesh(
            &c.name,
            Primitive {
                positions: &c.positions,
                normals: &[],
                indices: Some(c.triangles.iter().flatten().copied().collect()),
                mode: json::mesh::Mode::Triangles,
                paint: Paint::Component,
            },
        )?;
        self.meshes.components[component] = Some(mesh);
        Ok(Some(mesh))
    }

    fn capsule_mesh(&mut self, capsule: usize) -> Result<json::Index<json::Mesh>, GltfError> {
        if self.meshes.capsules.is_empty() {
            // All capsule meshes at once, in model order, so indices do not depend on pose order.
            for c in &self.model.capsules {
                let shape = shapes::capsule(&c.from, &c.to, c.radius);
                let mesh =
                    self.shape_mesh(&format!("capsule {}", c.name), &shape, Paint::Capsule)?;
                self.meshes.capsules.push(mesh);
            }
        }
        Ok(self.meshes.capsules[capsule])
    }

    /// The mesh in the cache slot `slot`, built by `build` the first time it is asked for.
    fn cached(
        &mut self,
        slot: fn(&mut SharedMeshes) -> &mut Option<json::Index<json::Mesh>>,
        build: impl FnOnce(&mut Self) -> Result<json::Index<json::Mesh>, GltfError>,
    ) -> Result<json::Index<json::Mesh>, GltfError> {
        if let Some(mesh) = *slot(&mut self.meshes) {
            return Ok(mesh);
        }
        let mesh = build(self)?;
        *slot(&mut self.meshes) = Some(mesh);
        Ok(mesh)
    }

    fn ball_mesh(&mut self) -> Result<json::Index<json::Mesh>, GltfError> {
        self.cached(
            |meshes| &mut meshes.ball,
            |writer| writer.shape_mesh("ball", &shapes::unit_sphere(), Paint::Steel),
        )
    }

    fn centre_of_mass_mesh(&mut self) -> Result<json::Index<json::Mesh>, GltfError> {
        self.cached(
            |meshes| &mut meshes.centre_of_mass,
            |writer| {
                let shape = shapes::unit_octahedron();
                writer.shape_mesh("centre of mass marker", &shape, Paint::CentreOfMass)
            },
        )
    }

    fn buoyancy_mesh(&mut self) -> Result<json::Index<json::Mesh>, GltfError> {
        self.cached(
            |meshes| &mut meshes.buoyancy,
            |writer| {
                let shape = shapes::unit_octahedron();
                writer.shape_mesh("buoyancy centre marker", &shape, Paint::Buoyancy)
            },
        )
    }

    fn gravity_mesh(&mut self) -> Result<json::Index<json::Mesh>, GltfError> {
        self.cached(
            |meshes| &mut meshes.gravity,
            |writer| {
                let lines = shapes::unit_arrow(&-writer.up);
                writer.lines_mesh("gravity arrow", &lines, Paint::Gravity)
            },
        )
    }

    fn string_mesh(&mut self) -> Result<json::Index<json::Mesh>, GltfError> {
        self.cached(
            |meshes| &mut meshes.string,
            |writer| {
                let lines = shapes::unit_line(&writer.up);
                writer.lines_mesh("string", &lines, Paint::String)
            },
        )
    }

    fn shape_mesh(
        &mut self,
        name: &str,
        shape: &ShapeMesh,
        paint: Paint,
    ) -> Result<json::Index<json::Mesh>, GltfError> {
        self.mesh(
            name,
            Primitive {
                positions: &shape.positions,
                normals: &shape.normals,
                indices: Some(shape.triangles.iter().flatten().copied().collect()),
                mode: json::mesh::Mode::Triangles,
                paint,
            },
        )
    }

    fn lines_mesh(
        &mut self,
        name: &str,
        lines: &[Point3<f64>],
        paint: Paint,
    ) -> Result<json::Index<json::Mesh>, GltfError> {
        self.mesh(
            name,
            Primitive {
                positions: lines,
                normals: &[],
                indices: None,
                mode: json::mesh::Mode::Lines,
                paint,
            },
        )
    }

    /// A one-primitive mesh; its data goes into the buffer.
    fn mesh(
        &mut self,
        name: &str,
        primitive: Primitive<'_>,
    ) -> Result<json::Index<json::Mesh>, GltfError> {
        let positions = primitive
            .positions
            .iter()
            .enumerate()
            .map(|(i, p)| f32x3(&p.coords, || format!("vertex {i} of mesh `{name}`")))
            .collect::<Result<Vec<_>, _>>()?;
        let mut attributes = std::collections::BTreeMap::new();
        let position_accessor = self.vec3_accessor(&positions, true);
        attributes.insert(
            Checked::Valid(json::mesh::Semantic::Positions),
            position_accessor,
        );
        if !primitive.normals.is_empty() {
            let normals: Vec<[f32; 3]> = primitive
                .normals
                .iter()
                .map(|n| {
                    let n = n.normalize().cast::<f32>();
                    let n = n / n.norm();
                    [n.x, n.y, n.z]
                })
                .collect();
            let normal_accessor = self.vec3_accessor(&normals, false);
            attributes.insert(
                Checked::Valid(json::mesh::Semantic::Normals),
                normal_accessor,
            );
        }
        let indices = primitive.indices.map(|i| self.index_accessor(&i));
        let material = self.material(primitive.paint);
        let mesh = json::Mesh {
            extensions: None,
            extras: None,
            name: Some(name.to_owned()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: None,
                indices,
                material: Some(material),
                mode: Checked::Valid(primitive.mode),
                targets: None,
            }],
            weights: None,
        };
        Ok(self.root.push(mesh))
    }

    fn material(&mut self, paint: Paint) -> json::Index<json::Material> {
        let slot = Paint::ALL
            .iter()
            .position(|&p| p == paint)
            .expect("every paint is listed");
        if let Some(index) = self.materials[slot] {
            return index;
        }
        let index = self.root.push(paint.material());
        self.materials[slot] = Some(index);
        index
    }

    /// A tightly packed f32 VEC3 accessor; positions carry their min and max.
    fn vec3_accessor(&mut self, values: &[[f32; 3]], bounds: bool) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let view = self.view(&bytes, json::buffer::Target::ArrayBuffer);
        let (min, max) = if bounds {
            let mut min = [f32::INFINITY; 3];
            let mut max = [f32::NEG_INFINITY; 3];
            for v in values {
                for k in 0..3 {
                    min[k] = min[k].min(v[k]);
                    max[k] = max[k].max(v[k]);
                }
            }
            (
                Some(json::Value::from(min.to_vec())),
                Some(json::Value::from(max.to_vec())),
            )
        } else {
            (None, None)
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(values.len()),
            component_type: Checked::Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::F32,
            )),
            extensions: None,
            extras: None,
            type_: Checked::Valid(json::accessor::Type::Vec3),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    fn index_accessor(&mut self, indices: &[u32]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.view(&bytes, json::buffer::Target::ElementArrayBuffer);
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(indices.len()),
            component_type: Checked::Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::U32,
            )),
            extensions: None,
            extras: None,
            type_: Checked::Valid(json::accessor::Type::Scalar),
            min: None,
            max: None,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// Appends `bytes` to the buffer at a 4-byte aligned offset.
    fn view(
        &mut self,
        bytes: &[u8],
        target: json::buffer::Target,
    ) -> json::Index<json::buffer::View> {
        pad_to_four(&mut self.bin, 0);
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: Some(Checked::Valid(target)),
            extensions: None,
            extras: None,
        })
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

    fn push_scene(&mut self, name: &str, root: json::Index<json::Node>) {
        let scene = self.root.push(json::Scene {
            extensions: None,
            extras: None,
            name: Some(name.to_owned()),
            nodes: vec![root],
        });
        if self.root.scene.is_none() {
            self.root.scene = Some(scene);
        }
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

    fn finish(mut self) -> Result<Vec<u8>, GltfError> {
        pad_to_four(&mut self.bin, 0);
        if !self.bin.is_empty() {
            self.root.buffers.push(json::Buffer {
                byte_length: USize64::from(self.bin.len()),
                name: None,
                uri: None,
                extensions: None,
                extras: None,
            });
        }
        let mut json = self.root.to_vec()?;
        pad_to_four(&mut json, b' ');
        // Header, JSON chunk header and JSON, BIN chunk header and data.
        let bytes = 12
            + 8
            + json.len() as u64
            + if self.bin.is_empty() {
                0
            } else {
                8 + self.bin.len() as u64
            };
        if bytes > u64::from(u32::MAX) {
            return Err(GltfError::TooLarge { bytes });
        }
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header {
                magic: *b"glTF",
                version: 2,
                length: bytes as u32,
            },
            json: json.into(),
            bin: (!self.bin.is_empty()).then(|| self.bin.into()),
        };
        glb.to_vec().map_err(GltfError::Container)
    }
}

fn pad_to_four(bytes: &mut Vec<u8>, fill: u8) {
    while bytes.len() % 4 != 0 {
        bytes.push(fill);
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
