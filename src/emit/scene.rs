//! The plain data the glTF writer draws: meshes, capsules and one entry per pose.
//!
//! These types carry no behaviour and name no other ballast type, so any stage can fill them in.

use nalgebra::{Isometry3, Point3, Vector3};

/// Everything the glTF writer draws. Lengths in project units; the writer converts them to glTF's
/// metres with `unit_in_metres` and turns `up` onto glTF's +Y.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneModel {
    /// Length of one project unit in metres, e.g. `0.001` for millimetres.
    pub unit_in_metres: f64,
    /// The project's unit up axis; the root of each scene rotates it onto glTF +Y.
    pub up: Vector3<f64>,
    /// The printed parts, each with its mesh in its own frame.
    pub components: Vec<SceneComponent>,
    /// The capsule-shaped voids, each inside one component.
    pub capsules: Vec<SceneCapsule>,
    /// Each pose is a group in the default scene and has a glTF scene of its own.
    pub poses: Vec<ScenePose>,
}

/// A printed part: a triangle mesh in the component's own frame.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneComponent {
    /// Human-readable name, used for the glTF mesh and node names.
    pub name: String,
    /// Vertex positions in the component frame, project units.
    pub positions: Vec<Point3<f64>>,
    /// Counter-clockwise (outward-facing) triangles indexing `positions`.
    pub triangles: Vec<[u32; 3]>,
}

/// A capsule-shaped void with a steel ball rolling inside it.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneCapsule {
    /// Human-readable name, used for the glTF node names.
    pub name: String,
    /// Index into [`SceneModel::components`] of the component holding the capsule.
    pub component: usize,
    /// One end of the capsule's axis, in the component frame.
    pub from: Point3<f64>,
    /// The other end of the capsule's axis, in the component frame.
    pub to: Point3<f64>,
    /// Radius of the capsule void.
    pub radius: f64,
    /// Radius of the ball inside it.
    pub ball_radius: f64,
}

/// One state of the model: where each component sits, where each ball rests, and the physics markers.
#[derive(Clone, Debug, PartialEq)]
pub struct ScenePose {
    /// Human-readable name; becomes the glTF scene name.
    pub name: String,
    /// Per component: component frame to world, in this pose.
    pub component_transforms: Vec<Isometry3<f64>>,
    /// Per capsule: the ball centre, in that capsule's component frame.
    pub ball_centres: Vec<Point3<f64>>,
    /// Centre of mass, world.
    pub centre_of_mass: Point3<f64>,
    /// Convex support polygon in order, world (may be empty, 1 or 2 points).
    pub support_polygon: Vec<Point3<f64>>,
    /// Height of the ground along up when the pose stands on it, project units; `None` when it
    /// hangs or floats (then no support polygon is drawn and the pose keeps its height).
    pub ground: Option<f64>,
    /// Where the model hangs from a string in this pose, world.
    pub suspension_point: Option<Point3<f64>>,
    /// Centre of buoyancy when the model is immersed in this pose, world.
    pub buoyancy_centre: Option<Point3<f64>>,
    /// Per-pose numbers, attached to the pose's group node and to the centre-of-mass node.
    pub extras: serde_json::Value,
}
