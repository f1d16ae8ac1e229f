//! The simulated model of one pose: one rigid body for all components, one body per ball, and the
//! rapier world they move in.
//!
//! Everything is in SI units (metres, kilograms, seconds). The model's body frame is the pose's
//! world frame scaled to metres, so at the identity pose the body sits exactly as the pose places
//! it.

use rapier3d_f64::prelude::*;

use crate::compile::Compilation;
use crate::spec::model::Pose;

/// Standard gravity, m/s².
pub(crate) const GRAVITY: f64 = 9.81;

/// g/cm³ to kg/m³.
const DENSITY_TO_SI: f64 = 1000.0;

/// One ball: where it may move in the model's body frame and what it weighs.
#[derive(Debug, Clone)]
pub(crate) struct BallSpec {
    /// The `from` end of the axis, body frame.
    pub from: Vector,
    /// The `to` end of the axis, body frame.
    pub to: Vector,
    /// The ball's mass properties about its centre.
    pub mass: MassProperties,
}

impl BallSpec {
    /// The axis length, metres.
    pub fn length(&self) -> f64 {
        (self.to - self.from).length()
    }
}

/// The posed model, as the simulation sees it. Computed from the meshes and capsules with parry's
/// mass properties, not with ballast's own; only the mass model's split into solid and sparse
/// material (checked against a slicer's G-code elsewhere) is taken as given.
#[derive(Debug, Clone)]
pub(crate) struct Model {
    /// Printed material, body frame: every component's solid and sparse parts as the mass model
    /// prints them (the driver's print volumes: solid at the material's density, sparse at the
    /// infill fraction of it), with the design's voids cut (`Compilation::printed`); inertia from
    /// parry's mass properties of the meshes, scaled to that mass.
    pub material: MassProperties,
    /// The points of each component's mesh, body frame: the vertices of their convex hull are
    /// what touches the ground.
    pub hulls: Vec<Vec<Vector>>,
    /// The balls, in the design's order.
    pub balls: Vec<BallSpec>,
    /// Centroid of the outer volume, body frame: where buoyancy acts.
    pub buoyancy_centre: Vector,
    /// Up, against gravity, in the world (and the pose's body frame).
    pub up: Vector,
    /// A length the size of the model (its bounding box diagonal), metres.
    pub size: f64,
    /// Metres per project unit.
    pub scale: f64,
}

/// A point of the project model as a simulation vector, scaled to metres.
fn to_vector(point: &nalgebra::Point3<f64>, scale: f64) -> Vector {
    Vector::new(point.x, point.y, point.z) * scale
}

impl Model {
    /// The model of `compilation` in `pose`.
    pub fn new(compilation: &Compilation, pose: &Pose) -> Model {
        let project = &compilation.project;
        let scale = project.units.in_metres();
        let full = project.material.density * DENSITY_TO_SI;
        let infill = compilation.design.infill;
        let cubic = scale.powi(3);
        let mut material = MassProperties::default();
        let mut outer = MassProperties::default();
        let mut hulls = Vec::new();
        let (mut low, mut high) = (Vector::splat(f64::MAX), Vector::splat(f64::MIN));
        for (index, mesh) in compilation.meshes.iter().enumerate() {
            let frame = pose.component_frame(index);
            let points: Vec<Vector> = mesh
                .positions
                .iter()
                .map(|p| to_vector(&(frame * p), scale))
                .collect();
            for point in &points {
                low = low.min(*point);
                high = high.max(*point);
            }
            let shape = MassProperties::from_trimesh(1.0, &points, &mesh.triangles);
            // The mass model's solid and sparse parts with the design's voids cut (the print
            // volumes the driver computed), with the inertia of the whole solid scaled to their
            // mass.
            if let Some(print) = compilation.printed.get(index) {
                let solid = full * print.solid.volume * cubic;
                let sparse = full * infill * print.sparse.volume * cubic;
                let mass = solid + sparse;
                if mass > 0.0 && shape.mass() > 0.0 {
                    let centre = (to_vector(&(frame * print.solid.centroid), scale) * solid
                        + to_vector(&(frame * print.sparse.centroid), scale) * sparse)
                        / mass;
                    material += MassProperties::with_principal_inertia_frame(
                        centre,
                        mass,
                        shape.principal_inertia() * (mass / shape.mass()),
                        shape.principal_inertia_local_frame,
                    );
                }
            }
            outer += shape;
            hulls.push(points);
        }
        let steel = project.ball.density * DENSITY_TO_SI;
        let mut balls = Vec::new();
        for capsule in &compilation.design.capsules {
            let frame = pose.component_frame(capsule.component);
            let from = to_vector(&(frame * capsule.from), scale);
            let to = to_vector(&(frame * capsule.to), scale);
            balls.push(BallSpec {
                from,
                to,
                mass: MassProperties::from_ball(steel, capsule.ball_radius * scale),
            });
        }
        let up = project.up.unit_vector();
        Model {
            material,
            hulls,
            balls,
            buoyancy_centre: outer.local_com,
            up: Vector::new(up.x, up.y, up.z),
            size: (high - low).length().max(1e-6),
            scale,
        }
    }

    /// Two horizontal unit vectors that, with `up`, make a right-handed frame.
    pub fn horizontal_axes(&self) -> (Vector, Vector) {
        horizontal_axes(self.up)
    }
}

/// Two unit vectors perpendicular to the unit vector `up` that, with it, make a right-handed
/// frame: for a world axis `up`, the next two world axes.
pub(crate) fn horizontal_axes(up: Vector) -> (Vector, Vector) {
    let first = Vector::new(up.z, up.x, up.y);
    let first = (first - up * first.dot(up)).normalize_or(Vector::X);
    (first, up.cross(first))
}

/// Where a ball is along its capsule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BallEnd {
    /// Within the first tenth of the axis, at the `from` end.
    From,
    /// Within the last tenth of the axis, at the `to` end.
    To,
    /// Anywhere between, or the capsule has no axis length.
    Between,
}

/// A rapier world holding one posed model.
pub(crate) struct World {
    pipeline: PhysicsPipeline,
    parameters: IntegrationParameters,
    gravity: Vector,
    islands: IslandManager,
    broad_phase: BroadPhaseBvh,
    narrow_phase: NarrowPhase,
    /// The bodies: model, balls, and whatever the caller adds.
    pub bodies: RigidBodySet,
    /// The colliders.
    pub colliders: ColliderSet,
    impulse_joints: ImpulseJointSet,
    /// The joints, in reduced coordinates so that they hold exactly: the balls' prismatic joints
    /// and whatever the caller adds.
    pub joints: MultibodyJointSet,
    soft_bodies: SoftBodySet,
    ccd: CCDSolver,
    /// The model's rigid body.
    pub model: RigidBodyHandle,
    /// One body per ball, in the design's order.
    pub balls: Vec<RigidBodyHandle>,
}

/// How the model's world is built.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Build {
    /// Where the model's body frame is at the start.
    pub start: Pose3,
    /// Whether the model gets its contact colliders (only needed with a ground).
    pub colliders: bool,
    /// Whether the balls are part of the model's own body (placed with
    /// [`World::place_balls`]) instead of bodies of their own on prismatic joints.
    pub fused_balls: bool,
    /// Linear and angular damping of every body, 1/s.
    pub damping: (f64, f64),
    /// The time step, seconds.
    pub time_step: f64,
}

/// Friction coefficient of the hulls and the ground: high enough that nothing slides below a
/// 60° tilt.
pub(crate) const FRICTION: f64 = 2.0;
/// Radius of the contact spheres at the hull's vertices, as a fraction of the model's size.
pub(crate) const CONTACT_RADIUS: f64 = 1e-4;
/// Natural frequency of the contacts' springs, Hz: stiff, so that a model sinks into the ground
/// by `g / (2π f)²`, a quarter of a micrometre, and does not lean on a soft contact.
pub(crate) const CONTACT_FREQUENCY: f64 = 1000.0;
/// Restitution of the hulls and the ground: a print on a table barely bounces.
pub(crate) const RESTITUTION: f64 = 0.05;

impl World {
    /// A world holding `model` as `build` says, each ball at the end of its capsule that gravity
    /// sends it to in the start orientation (the midpoint when the axis is horizontal).
    pub fn new(model: &Model, build: &Build) -> World {
        let mut parameters = IntegrationParameters {
            length_unit: model.size / 10.0,
            // A recycled contact keeps its points and its lever arms from the model's centre of
            // mass while the model barely moves: stale by up to half a percent of the model's
            // size, and by a whole capsule's length of a ball's shift once the ball changes end.
            contact_recycling: false,
            ..IntegrationParameters::default()
        };
        parameters.dt = build.time_step;
        parameters.contact_softness = SpringCoefficients::new(CONTACT_FREQUENCY, 10.0);
        parameters.static_contact_softness = SpringCoefficients::new(CONTACT_FREQUENCY, 10.0);
        let mut bodies = RigidBodySet::new();
        let mut colliders = ColliderSet::new();
        let mut joints = MultibodyJointSet::new();
        let (linear, angular) = build.damping;
        let body = RigidBodyBuilder::dynamic()
            .pose(build.start)
            .additional_mass_properties(model.material)
            .linear_damping(linear)
            .angular_damping(angular)
            .can_sleep(false);
        let handle = bodies.insert(body);
        if build.colliders {
            for points in &model.hulls {
                // Only the vertices of the convex hull can touch a flat ground: a tiny sphere at
                // each gives exact point contacts. (A convex-polyhedron collider did the same on
                // boxes, but rocked on the many facets of a round base.)
                let (vertices, _) = rapier3d_f64::parry::transformation::convex_hull(points);
                for vertex in vertices {
                    let contact = ColliderBuilder::ball(CONTACT_RADIUS * model.size)
                        .translation(vertex)
                        .density(0.0)
                        .friction(FRICTION)
                        .restitution(RESTITUTION);
                    colliders.insert_with_parent(contact, handle, &mut bodies);
                }
            }
        }
        let down = build.start.rotation.inverse() * -model.up;
        let mut balls = Vec::new();
        for ball in model.balls.iter().filter(|_| !build.fused_balls) {
            let length = ball.length();
            let along = if length > 0.0 {
                (ball.to - ball.from) / length
            } else {
                Vector::ZERO
            };
            let slope = along.dot(down);
            let start = if slope > 0.0 {
                length
            } else if slope < 0.0 {
                0.0
            } else {
                length / 2.0
            };
            let centre = build.start * (ball.from + along * start);
            let ball_body = RigidBodyBuilder::dynamic()
                .pose(Pose3::from_parts(centre, build.start.rotation))
                .additional_mass_properties(ball.mass)
                .linear_damping(linear)
                .angular_damping(angular)
                .can_sleep(false);
            let ball_handle = bodies.insert(ball_body);
            // A multibody joint starts at coordinate 0: the joint frame is put where the ball
            // starts, and the limits measured from there.
            let start_point = ball.from + along * start;
            if length > 0.0 {
                let joint = PrismaticJointBuilder::new(along)
                    .local_anchor1(start_point)
                    .local_anchor2(Vector::ZERO)
                    .limits([-start, length - start]);
                joints.insert(handle, ball_handle, joint, true);
            } else {
                let joint = FixedJointBuilder::new()
                    .local_anchor1(start_point)
                    .local_anchor2(Vector::ZERO);
                joints.insert(handle, ball_handle, joint, true);
            }
            balls.push(ball_handle);
        }
        World {
            pipeline: PhysicsPipeline::new(),
            parameters,
            gravity: -model.up * GRAVITY,
            islands: IslandManager::new(),
            broad_phase: BroadPhaseBvh::new(),
            narrow_phase: NarrowPhase::new(),
            bodies,
            colliders,
            impulse_joints: ImpulseJointSet::new(),
            joints,
            soft_bodies: SoftBodySet::new(),
            ccd: CCDSolver::new(),
            model: handle,
            balls,
        }
    }

    /// Gives every degree of freedom of the model's joints (the string's or the fluid's pivot,
    /// the balls' slides) a viscous damping of `rates` (linear, angular, 1/s) times the inertia
    /// it moves, so a model of a few grams and one of a kilogram settle alike. This replaces
    /// rapier's default joint damping (0.1 N·m·s per rotational degree of freedom), which on a
    /// small print is thousands of times its inertia and lets it creep, not swing, towards rest;
    /// a body's own damping does not act on the links of a multibody.
    pub fn damp_joints(&mut self, (linear, angular): (f64, f64)) {
        for handle in std::iter::once(&self.model).chain(&self.balls) {
            self.bodies[*handle].recompute_mass_properties_from_colliders(&self.colliders);
        }
        let Some(link) = self.joints.rigid_body_link(self.model).copied() else {
            return;
        };
        let Some(multibody) = self.joints.get_multibody_mut(link.multibody) else {
            return;
        };
        let inverse_inertia = multibody.dof_inverse_inertia(&self.bodies);
        let dofs: Vec<(usize, usize, usize)> = multibody
            .links()
            .map(|link| {
                let data = &link.joint().data;
                let locked = data.locked_axes.bits();
                let free_linear = 3 - (locked & 0b111).count_ones() as usize;
                (link.assembly_id(), link.joint().ndofs(), free_linear)
            })
            .collect();
        let damping = multibody.damping_mut();
        for (first, count, free_linear) in dofs {
            for k in 0..count {
                let dof = first + k;
                let rate = if k < free_linear { linear } else { angular };
                let inverse = inverse_inertia[dof];
                damping[dof] = if inverse > 0.0 { rate / inverse } else { 0.0 };
            }
        }
    }

    /// With fused balls: makes the model's mass the material plus each ball at the end of its
    /// capsule `ends` says (`true`: the `to` end).
    pub fn place_balls(&mut self, model: &Model, ends: &[bool]) {
        let mut mass = model.material;
        for (ball, to) in model.balls.iter().zip(ends) {
            let centre = if *to { ball.to } else { ball.from };
            mass += ball.mass.transform_by(&Pose3::from_translation(centre));
        }
        self.bodies[self.model].set_additional_mass_properties(mass, true);
    }

    /// The time step, seconds.
    pub fn time_step(&self) -> f64 {
        self.parameters.dt
    }

    /// Advances the simulation by one time step.
    pub fn step(&mut self) {
        self.pipeline.step(
            self.gravity,
            &self.parameters,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            &mut self.bodies,
            &mut self.colliders,
            &mut self.impulse_joints,
            &mut self.joints,
            &mut self.soft_bodies,
            &mut self.ccd,
            &(),
            &(),
        );
    }

    /// Gravity now, world, m/s².
    pub fn gravity(&self) -> Vector {
        self.gravity
    }

    /// Sets gravity, world, m/s²: turning it is tilting the ground without moving it.
    pub fn set_gravity(&mut self, gravity: Vector) {
        self.gravity = gravity;
    }

    /// The model's body.
    pub fn model_body(&self) -> &RigidBody {
        &self.bodies[self.model]
    }

    /// Centre of mass of the model and its balls together, world.
    pub fn centre_of_mass(&self) -> Vector {
        let mut weighted = Vector::ZERO;
        let mut mass = 0.0;
        for handle in std::iter::once(&self.model).chain(&self.balls) {
            let body = &self.bodies[*handle];
            weighted += body.center_of_mass() * body.mass();
            mass += body.mass();
        }
        if mass > 0.0 {
            weighted / mass
        } else {
            self.model_body().translation()
        }
    }

    /// Where each ball is along its capsule (by its centre's position in the model's frame).
    pub fn ball_ends(&self, model: &Model) -> Vec<BallEnd> {
        let frame = *self.model_body().position();
        model
            .balls
            .iter()
            .zip(&self.balls)
            .map(|(ball, handle)| {
                let length = ball.length();
                if length <= 0.0 {
                    return BallEnd::Between;
                }
                let centre = frame.inverse_transform_point(self.bodies[*handle].translation());
                let along = (centre - ball.from).dot(ball.to - ball.from) / (length * length);
                if along < 0.1 {
                    BallEnd::From
                } else if along > 0.9 {
                    BallEnd::To
                } else {
                    BallEnd::Between
                }
            })
            .collect()
    }

    /// How fast the model tilts and the balls move in it, m/s: the model's angular speed about
    /// horizontal axes times its size, or a ball's speed along its capsule, whichever is
    /// largest. Translation and turning about `up` are left out: neither changes a hanging or
    /// floating goal's angle.
    pub fn motion(&self, size: f64, up: Vector) -> f64 {
        let body = self.model_body();
        let spin = body.angvel();
        let tilting = spin - up * spin.dot(up);
        self.balls
            .iter()
            .map(|handle| self.slide_speed(*handle))
            .fold(tilting.length() * size, f64::max)
    }

    /// How fast the ball `handle` slides along its capsule, m/s: its joint's velocity when it
    /// is a link of the model's multibody, else its speed relative to the model.
    fn slide_speed(&self, handle: RigidBodyHandle) -> f64 {
        let joint = self.joints.rigid_body_link(handle).and_then(|link| {
            let multibody = self.joints.get_multibody(link.multibody)?;
            let velocity = multibody.joint_velocity(multibody.link(link.id)?);
            Some(velocity.iter().map(|v| v * v).sum::<f64>().sqrt())
        });
        joint.unwrap_or_else(|| {
            let body = self.model_body();
            let ball = &self.bodies[handle];
            (ball.linvel() - body.velocity_at_point(ball.translation())).length()
        })
    }
}
