//! What the objective needs of one pose that does not depend on the design, computed once.

use nalgebra::{Isometry3, Point3, Vector3};

use crate::balance::evaluate::{extent, posed_vertices};
use crate::balance::rest::{default_contact_tolerance, settle_pose, solid_centre};
use crate::balance::support::{
    contact_tolerance, footprint, ground_height, support_lines, GroundPlane, SupportLine,
};
use crate::balance::ComponentBody;
use crate::spec::model::{Goal, Pose, Project};

/// One pose, precomputed: component placements, gravity, the support polygon and the goals.
#[derive(Debug, Clone)]
pub struct PoseSetup {
    /// The pose's name.
    pub name: String,
    /// Per component (as many as the project or the bodies have): rest frame to world.
    pub frames: Vec<Isometry3<f64>>,
    /// Per component: unit gravity (`−up`) in the component's rest frame.
    pub gravity: Vec<Vector3<f64>>,
    /// The whole pose's transform, for components past the end of `frames`.
    pub(crate) default_frame: Isometry3<f64>,
    /// Unit up, world.
    pub up: Vector3<f64>,
    /// Per body: outer volume (cubic project units) and its centroid in world.
    pub bodies: Vec<(f64, Point3<f64>)>,
    /// Per body: the volume printed solid and its centroid in world, then the volume printed at
    /// the infill fraction and its centroid ([`ComponentBody::print`]).
    pub printed: Vec<[(f64, Point3<f64>); 2]>,
    /// Outer volume of all components, cubic project units.
    pub volume: f64,
    /// Centroid of the outer volume, world (the centre of buoyancy); the fallback centre when the
    /// volume cancels.
    pub buoyancy_centre: Point3<f64>,
    /// Mean of the bodies' world centroids (origin without bodies): the centre of a massless model.
    pub fallback_centre: Point3<f64>,
    /// The support on the ground, when the model has vertices.
    pub(crate) support: Option<Footing>,
    /// The pose's goals, angles in radians, points in world.
    pub(crate) goals: Vec<GoalSetup>,
    /// The rounding length of [`Parameters::angle_smoothing`](super::Parameters), project units.
    pub(crate) epsilon: f64,
}

/// The fixed support polygon of a pose.
#[derive(Debug, Clone)]
pub(crate) struct Footing {
    /// Ground height along up.
    pub ground: f64,
    /// Horizontal axes of the ground, world.
    pub e1: Vector3<f64>,
    /// See `e1`.
    pub e2: Vector3<f64>,
    /// One per (pseudo-)edge of the support polygon.
    pub lines: Vec<SupportLine>,
}

/// A goal with its numbers in the objective's units.
#[derive(Debug, Clone)]
pub(crate) enum GoalSetup {
    /// Survive a tilt of `margin` radians.
    Stand { margin: f64 },
    /// Topple by at least `margin` radians.
    Imbalance { margin: f64 },
    /// Hang from `point` (world) within `tolerance` radians; with `unique`, in no other stable
    /// state.
    Suspend {
        point: Vector3<f64>,
        tolerance: f64,
        unique: bool,
    },
    /// Right itself in a fluid.
    Immerse {
        /// g per cubic project unit.
        fluid_density: f64,
        min_distance: f64,
        tolerance: f64,
        mass_tolerance: Option<f64>,
        /// In no other stable state.
        unique: bool,
    },
}

impl PoseSetup {
    /// Precomputes `pose` of the model made of `bodies` (indexed like `project.components`);
    /// `angle_smoothing` as in [`Parameters`](super::Parameters).
    ///
    /// A pose that stands on the ground is first settled onto its hull with the solid model's
    /// centre of mass (the design is not known yet), as `balance::evaluate_pose` does with the
    /// design's.
    pub fn new(
        project: &Project,
        bodies: &[ComponentBody],
        pose: &Pose,
        angle_smoothing: f64,
    ) -> PoseSetup {
        let settled = settle_pose(project, bodies, pose, &solid_centre(bodies, pose));
        let pose = &settled.pose;
        let up = project.up.unit_vector();
        let count = bodies.len().max(project.components.len());
        let frames: Vec<Isometry3<f64>> = (0..count).map(|i| pose.component_frame(i)).collect();
        let gravity = frames.iter().map(|f| f.rotation.inverse() * -up).collect();
        let placed: Vec<(f64, Point3<f64>)> = bodies
            .iter()
            .zip(&frames)
            .map(|(body, frame)| (body.mass.volume, frame * body.mass.centroid))
            .collect();
        let printed = bodies
            .iter()
            .zip(&frames)
            .map(|(body, frame)| {
                let (solid, sparse) = (&body.print.solid, &body.print.sparse);
                [
                    (solid.volume, frame * solid.centroid),
                    (sparse.volume, frame * sparse.centroid),
                ]
            })
            .collect();
        let fallback_centre = if placed.is_empty() {
            Point3::origin()
        } else {
            Point3::from(
                placed.iter().map(|(_, c)| c.coords).sum::<Vector3<f64>>() / placed.len() as f64,
            )
        };
        let volume: f64 = placed.iter().map(|(v, _)| v).sum();
        let buoyancy_centre = solid_centre(bodies, pose);
        let vertices = posed_vertices(bodies, pose);
        let plane = GroundPlane::new(project.up);
        let tolerance = contact_tolerance(pose)
            .unwrap_or_else(|| default_contact_tolerance(&vertices))
            .max(0.0);
        let support = ground_height(&vertices, &plane).map(|ground| {
            let (_, polygon) = footprint(&vertices, &plane, ground, tolerance);
            Footing {
                ground,
                e1: plane.e1,
                e2: plane.e2,
                lines: support_lines(&polygon)
                    .into_iter()
                    .map(|(_, _, line)| line)
                    .collect(),
            }
        });
        let cubic = project.units.cubic_in_cm3();
        let goals = pose
            .goals
            .iter()
            .map(|goal| match goal.value {
                Goal::Stand { margin, .. } => GoalSetup::Stand {
                    margin: margin.to_radians(),
                },
                Goal::Imbalance { margin, .. } => GoalSetup::Imbalance {
                    margin: margin.to_radians(),
                },
                Goal::Suspend {
                    point,
                    component,
                    tolerance,
                    unique,
                } => GoalSetup::Suspend {
                    point: (pose.component_frame(component) * point).coords,
                    tolerance: tolerance.to_radians(),
                    unique,
                },
                Goal::Immerse {
                    fluid_density,
                    min_distance,
                    tolerance,
                    mass_tolerance,
                    unique,
                } => GoalSetup::Immerse {
                    fluid_density: fluid_density * cubic,
                    min_distance,
                    tolerance: tolerance.to_radians(),
                    mass_tolerance,
                    unique,
                },
            })
            .collect();
        // Positive even for a model without extent, so the rounded norms stay differentiable.
        let epsilon = (angle_smoothing * extent(&vertices)).max(1e-100);
        PoseSetup {
            name: pose.name.value.clone(),
            frames,
            gravity,
            default_frame: pose.transform,
            up,
            bodies: placed,
            printed,
            volume,
            buoyancy_centre,
            fallback_centre,
            support,
            goals,
            epsilon,
        }
    }

    /// Rest frame of `component` to world.
    pub fn frame(&self, component: usize) -> Isometry3<f64> {
        self.frames
            .get(component)
            .copied()
            .unwrap_or(self.default_frame)
    }

    /// Unit gravity in the rest frame of `component`.
    pub fn gravity_in(&self, component: usize) -> Vector3<f64> {
        self.gravity
            .get(component)
            .copied()
            .unwrap_or_else(|| self.default_frame.rotation.inverse() * -self.up)
    }
}
