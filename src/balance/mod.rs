//! The physics stage: what a design does in one pose.
//!
//! [`evaluate_pose`] takes the project, each component's mesh and mass properties, a design and a
//! pose, and returns a [`PoseEvaluation`]:
//!
//! - the mass and centre of mass of printed material plus balls (paper eq. 7-13);
//! - where each ball rests: at the end of its capsule that gravity sends it to (eq. 19-20), touching
//!   the capsule's spherical cap, or on the axis midpoint when the axis is too close to horizontal
//!   to say;
//! - for a pose that stands on the ground, the facet of the model's convex hull it rests on: the
//!   written rotation corrected to put that facet flat on the ground (see `rest`);
//! - the support polygon on the ground and the toppling angle about each of its edges (the angles
//!   eq. 1 takes a smooth maximum of, balls held still), and the tilt margin with the balls
//!   rolling as the ground tilts, over every direction;
//! - for each goal of the pose, the measured value beside the required one (eq. 1-5);
//! - for each `suspend` and `immerse` goal, every stable state of the hanging or floating model
//!   (each assignment of ball ends that stays put in the orientation it settles in).
//!
//! These are the exact, non-smooth quantities a report states and a verifier re-checks; they are
//! not the smoothed objectives an optimizer descends.
//!
//! # Units and conventions
//!
//! Lengths are in the project's units, volumes in cubic project units, masses in grams, angles in
//! degrees. Points are `[x, y, z]`. "World" is the frame after the pose's transforms; gravity
//! points along `−up`.
//!
//! # No panics, no NaN
//!
//! Any input is accepted. Missing pieces get documented stand-ins (a pose with fewer component
//! transforms than components uses the identity for the rest; a model of zero mass has its centre
//! of mass at the mean of its component centroids; a model without vertices has an empty support
//! and topples), so finite inputs always give finite outputs.

mod ball;
pub(crate) mod equilibria;
pub(crate) mod evaluate;
pub(crate) mod facets;
mod goals;
mod mass;
mod printed;
pub(crate) mod rest;
mod rocking;
pub(crate) mod support;
pub(crate) mod tilt;

pub use equilibria::{CUT_FLIPS, MAX_ENUMERATED_BALLS};
pub use evaluate::evaluate_pose;
pub use facets::{facet_rotation, resting_facets, RestingFacet};
pub use mass::{capsule_shell, component_material};
pub use printed::{bare_bodies, component_voids, cut_bodies, PartPrints};
pub use rest::{Resting, ROCKING_DEGREES, SNAP_WARNING};

use std::borrow::Cow;

use nalgebra::{Isometry3, Matrix3, Rotation3};
use serde::Serialize;

use crate::geometry::{
    convex_hull, print_volumes, ConvexHull, MassProperties, PrintVolumes, Region, Slicing, TriMesh,
};
use crate::spec::model::{Axis, MassModel, Print, Project};

/// Per-component data that does not change with the pose: the mesh in its rest frame, its mass
/// properties and where its material is printed solid or sparse, computed once (they are the
/// expensive part) and shared by every pose.
///
/// The slice passed to [`evaluate_pose`] is indexed like
/// [`Project::components`](crate::spec::model::Project::components).
#[derive(Debug, Clone, Copy)]
pub struct ComponentBody<'a> {
    /// The component's mesh, rest frame. Every position counts as a vertex that may touch the
    /// ground; triangle indices are never read.
    pub mesh: &'a TriMesh,
    /// The mass properties of the solid `mesh` bounds (the union of its shells,
    /// [`MeshCheck::solid`](crate::geometry::MeshCheck::solid)): the outer volume and its
    /// centroid, rest frame.
    pub mass: MassProperties,
    /// The material of the printed mesh before capsules are cut: [`print_volumes`] under the
    /// `fdm` mass model, [`PrintVolumes::uniform`] under `uniform`; or, when `voids_in_print`,
    /// the material measured in a print, voids already empty.
    pub print: PrintVolumes,
    /// Whether `print` already has the capsule voids empty and their shells printed (a measured
    /// deposit, see [`ComponentBody::measured`]): then no void is removed from this component's
    /// material and no shell added; its balls still weigh.
    pub voids_in_print: bool,
    /// The convex hull of `mesh`, rest frame, computed once for every pose
    /// ([`ComponentBody::with_hull`]); `None` when not given, and then computed from `mesh` where
    /// a pose needs it (the same hull).
    pub hull: Option<&'a ConvexHull>,
}

impl<'a> ComponentBody<'a> {
    /// The body of `mesh`, with its mass properties and print volumes computed for `project`'s
    /// [`print`](crate::spec::model::Project::print) settings, printed with the project's `up`
    /// axis up ([`up_to_print`]). The mass properties are the closed form's: right for a mesh
    /// whose shells do not overlap.
    ///
    /// # Panics
    /// If a triangle indexes past the positions (as [`mass_properties`](crate::geometry::mass_properties)
    /// does); meshes from [`load_mesh`](crate::geometry::load_mesh) never do.
    pub fn for_project(mesh: &'a TriMesh, project: &Project) -> Self {
        let mass = crate::geometry::mass_properties(mesh);
        ComponentBody {
            mesh,
            mass,
            print: component_print(project, mesh, &mass, up_to_print(project.up)),
            voids_in_print: false,
            hull: None,
        }
    }

    /// The body of `mesh`, whose solid has the mass properties `mass`, with its print volumes
    /// already computed (by [`component_print`]).
    pub fn with_print(mesh: &'a TriMesh, mass: MassProperties, print: PrintVolumes) -> Self {
        ComponentBody {
            mesh,
            mass,
            print,
            voids_in_print: false,
            hull: None,
        }
    }

    /// This body with its mesh's convex hull `hull` (rest frame, [`convex_hull`] of its
    /// positions) computed already; `None` for a mesh with no hull.
    pub fn with_hull(self, hull: Option<&'a ConvexHull>) -> Self {
        ComponentBody { hull, ..self }
    }

    /// The convex hull of the mesh, rest frame: the one given, or computed now.
    pub(crate) fn rest_hull(&self) -> Option<Cow<'a, ConvexHull>> {
        match self.hull {
            Some(hull) => Some(Cow::Borrowed(hull)),
            None => convex_hull(&self.mesh.positions).map(Cow::Owned),
        }
    }

    /// The body of `mesh` whose material `print` has a design's voids cut from it already
    /// ([`PartPrints::cut`]): only the balls are added to it.
    pub fn with_voids_cut(mesh: &'a TriMesh, mass: MassProperties, print: PrintVolumes) -> Self {
        ComponentBody {
            voids_in_print: true,
            ..ComponentBody::with_print(mesh, mass, print)
        }
    }

    /// The body of `mesh` printed as measured: `deposit` is all its material (volume, cubic
    /// project units, at the material's full density; centroid, rest frame), the capsule voids
    /// already empty in it. The outer volume, for buoyancy, and the vertices, for support, are
    /// still `mesh`'s (its solid's mass properties `mass`).
    pub fn measured(mesh: &'a TriMesh, mass: MassProperties, deposit: Region) -> Self {
        ComponentBody {
            mesh,
            mass,
            print: PrintVolumes {
                solid: deposit,
                sparse: Region {
                    volume: 0.0,
                    centroid: deposit.centroid,
                },
            },
            voids_in_print: true,
            hull: None,
        }
    }
}

/// Where `mesh` (with mass properties `mass`) is printed solid and where sparse under
/// `project`'s mass model, printed turned by `to_print`: the slicer's layers for `fdm`, all
/// sparse for `uniform`.
pub fn component_print(
    project: &Project,
    mesh: &TriMesh,
    mass: &MassProperties,
    to_print: Rotation3<f64>,
) -> PrintVolumes {
    match project.print.model {
        MassModel::Uniform => PrintVolumes::uniform(mass),
        MassModel::Fdm => print_volumes(mesh, &slicing(&project.print, to_print)),
    }
}

/// The rotation that turns a rest frame with `up` pointing up into a print frame (+z up): the
/// identity for z; exact quarter turns about the other axes.
pub fn up_to_print(up: Axis) -> Rotation3<f64> {
    let matrix = match up {
        Axis::X => Matrix3::new(0.0, 0.0, -1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0),
        Axis::Y => Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0),
        Axis::Z => Matrix3::identity(),
    };
    Rotation3::from_matrix_unchecked(matrix)
}

/// The geometry stage's view of the print settings `print` for a component printed turned by
/// `to_print` (rest frame to print frame, +z up).
pub fn slicing(print: &Print, to_print: Rotation3<f64>) -> Slicing {
    let count = |n: u64| usize::try_from(n).unwrap_or(usize::MAX);
    Slicing {
        to_print,
        perimeter_thickness: print.perimeter_thickness(),
        layer_height: print.layer_height,
        first_layer_height: print.first_layer_height,
        top_layers: count(print.top_solid_layers),
        bottom_layers: count(print.bottom_solid_layers),
        min_sparse_area: print.solid_infill_below_area,
        surface_margin: print.surface_margin,
        shell_widening: 3.0 * print.extrusion_width,
        fill_boundary: print.perimeter_thickness() - 0.25 * print.spacing()
            + (print.extrusion_width - print.spacing()) / 2.0,
        infill_spacing: print.spacing(),
    }
}

/// What the model does in one pose.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PoseEvaluation {
    /// The pose's name.
    pub pose: String,
    /// Total mass, grams: printed material (scaled by the design's infill, capsule voids removed)
    /// plus balls.
    pub mass: f64,
    /// Outer volume of all components together, cubic project units (capsules are sealed inside
    /// and do not reduce it). Signed like the meshes' volumes.
    pub volume: f64,
    /// Centre of mass, world. When the mass is zero (no material, no balls), the mean of the
    /// components' centroids in world instead (the origin when there are no components).
    pub centre_of_mass: [f64; 3],
    /// One per capsule of the design, in the design's order.
    pub balls: Vec<BallPlacement>,
    /// Where and how the model rests on the ground in this pose.
    pub support: Support,
    /// The facet of the hull the pose rests on, for a pose with a `stand` or `imbalance` goal
    /// whose model has a volume (`null` otherwise, and when it is balanced exactly on an edge or
    /// a vertex, where it is evaluated as written; then left out of the JSON).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resting: Option<Resting>,
    /// One per goal of the pose, in the pose's order.
    pub goals: Vec<GoalEvaluation>,
    /// Each component's frame (rest frame to world) as the pose was evaluated: the written
    /// pose's, or the settled one's when the pose settled onto its hull ([`Self::resting`]), so
    /// that a drawing of the pose shows the model where its centre of mass and support are. Not
    /// in the report.
    #[serde(skip)]
    pub component_frames: Vec<Isometry3<f64>>,
}

/// Where the ball of one capsule rests in a pose.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BallPlacement {
    /// The capsule's name.
    pub capsule: String,
    /// Index of the capsule's component.
    pub component: usize,
    /// Which end the ball rolled to.
    pub rest: BallRest,
    /// Angle of the capsule's axis above horizontal in this pose, degrees in [0, 90]. A capsule
    /// with a zero-length axis (a spherical cavity) counts as vertical.
    pub elevation: f64,
    /// Ball centre, rest frame of the capsule's component.
    pub centre: [f64; 3],
    /// Ball centre, world.
    pub centre_world: [f64; 3],
    /// Mass of the ball, grams. A capsule whose component has no [`ComponentBody`] is left out of
    /// the model's mass, ball included.
    pub mass: f64,
}

/// Which end of its capsule a ball rests at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum BallRest {
    /// At the `from` end, touching the bottom of its spherical cap. Also reported for a capsule
    /// with a zero-length axis, where both ends coincide and the ball sits at the bottom.
    From,
    /// At the `to` end, touching the bottom of its spherical cap.
    To,
    /// The axis is within [`Ball::min_angle`](crate::spec::model::Ball::min_angle) of horizontal:
    /// the ball could be anywhere along it and is placed at the axis midpoint.
    Undetermined,
}

/// How the model rests on a horizontal ground in a pose.
///
/// The ground touches the lowest posed vertex (in the pose settled on its hull). The vertices
/// within the contact tolerance of it are the contact points; their convex hull, seen from above, is the support polygon. Tilting the
/// ground about one of the polygon's edges topples the model once the centre of mass passes over
/// that edge: the angle at which that happens is the edge's toppling angle.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Support {
    /// Height of the ground along up (the lowest vertex's), project units. 0 when there are no
    /// vertices.
    pub ground_height: f64,
    /// Vertices at most this far above the ground touch it, project units: the tolerance of the
    /// pose's first `stand` or `imbalance` goal (0 if that is negative), else the hull's
    /// coplanarity tolerance (1e-6 of the posed model's extent). Every `stand` and `imbalance`
    /// goal of the pose is judged on this one support.
    pub contact_tolerance: f64,
    /// Height of the centre of mass above the ground, project units.
    pub centre_height: f64,
    /// The vertices touching the ground, world, in component and vertex order.
    pub contacts: Vec<[f64; 3]>,
    /// The convex hull of the contacts projected onto the ground, world, counter-clockwise seen
    /// from above, without repeated or collinear points. One point when everything touches at a
    /// point, two when along a line; empty when there are no vertices.
    pub polygon: Vec<[f64; 3]>,
    /// The edges the model can topple over, each with its toppling angle.
    ///
    /// For a polygon of three or more points, its edges in order. For a single point `p`, one
    /// pseudo-edge from `p` to `p` whose distance is the centre's distance from `p`. For a segment
    /// `a`-`b`, its two sides (`a`→`b`, `b`→`a`), whose distance is the centre's distance from the
    /// line, counted as outside on both, then its two end caps (`a`→`a`, `b`→`b`), whose distance
    /// is how far beyond that end the centre lies along the segment (negative when between the
    /// ends). So a point or a line never stands with a positive margin.
    pub edges: Vec<SupportEdge>,
    /// The smallest toppling angle over all edges with every ball held where it rests, degrees.
    /// Negative: it topples. −90 when there is no support at all.
    pub fixed_ball_margin: f64,
    /// The tilt of the ground the pose survives in every direction, degrees, with every ball
    /// rolling to the end the tilted gravity sends it to as the tilt grows (docs/physics.md): the
    /// smallest tilt, over all directions, that topples the model.
    /// Negative when it topples on level ground: minus the smallest tilt that would make it stand.
    /// For a support of one or two points, where nothing stands with a positive margin, the
    /// fixed-ball margin. −90 when there is no support at all.
    pub tilt_margin: f64,
    /// The horizontal unit vector, world, towards which the ground descends at the worst tilt:
    /// the way the model topples (or, when it topples on level ground, the way the ground would
    /// have to descend to make it stand). `None` without a support, or for a point support under
    /// the centre of mass. Left out of the JSON when `None`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tilt_direction: Option<[f64; 3]>,
    /// The balls that roll to their other end as the ground tilts towards `tilt_direction`,
    /// before the model's state changes, in the order they roll.
    pub ball_moves: Vec<BallMove>,
}

/// A ball rolling to its capsule's other end while the ground tilts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BallMove {
    /// The capsule's name.
    pub capsule: String,
    /// The tilt of the ground at which it rolls, degrees.
    pub tilt: f64,
    /// The end it rolls to.
    pub to: BallRest,
}

/// One edge of the support polygon and how far the model is from toppling over it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SupportEdge {
    /// Start of the edge, world, on the ground.
    pub start: [f64; 3],
    /// End of the edge, world, on the ground.
    pub end: [f64; 3],
    /// Signed horizontal distance of the centre of mass from the edge's line, project units:
    /// positive outside the support, negative inside.
    pub distance: f64,
    /// `atan2(−distance, centre height)`, degrees: how far the ground can tilt about this edge
    /// before the model topples over it. Positive: stable against this edge.
    pub toppling_angle: f64,
}

/// The outcome of one goal of a pose.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GoalEvaluation {
    /// Whether the goal holds.
    pub met: bool,
    /// What was measured and what was required.
    #[serde(flatten)]
    pub outcome: GoalOutcome,
}

/// The measured and required values of one goal, by kind. Serialised with a `kind` field naming
/// the goal as in the project file.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum GoalOutcome {
    /// Met when `tilt_margin > 0` and `tilt_margin ≥ margin`.
    Stand {
        /// The support's tilt margin, degrees.
        tilt_margin: f64,
        /// The required margin, degrees.
        margin: f64,
    },
    /// Met when `tilt_margin < 0` and `tilt_margin < −margin`.
    Imbalance {
        /// The support's tilt margin, degrees.
        tilt_margin: f64,
        /// The required margin, degrees.
        margin: f64,
    },
    /// Met when `angle ≤ tolerance`.
    Suspend {
        /// Angle between the string (from the suspension point to the centre of mass) and
        /// gravity, degrees in [0, 180]. 90 when the centre of mass is at the suspension point,
        /// where the hang is neutral.
        angle: f64,
        /// The allowed angle, degrees.
        tolerance: f64,
        /// The suspension point, world.
        point: [f64; 3],
        /// Whether the goal asks for the wanted state to be the only stable one (`unique=#true`);
        /// then it is met only when [`Equilibria::states`] holds no other.
        unique: bool,
        /// Every stable state of the model hanging from `point`.
        equilibria: Equilibria,
    },
    /// Met when `angle ≤ tolerance`, `distance ≥ min_distance` and, when `mass_tolerance` is
    /// given, `|mass_residual| ≤ mass_tolerance`.
    Immerse {
        /// Angle between up and the direction from the centre of mass to the centre of buoyancy,
        /// degrees in [0, 180]. 90 when the two centres coincide.
        angle: f64,
        /// The allowed angle, degrees.
        tolerance: f64,
        /// Distance between the centres of mass and buoyancy, project units.
        distance: f64,
        /// The required distance, project units.
        min_distance: f64,
        /// The centre of buoyancy (centroid of the outer volume), world.
        buoyancy_centre: [f64; 3],
        /// Mass of the fluid the model displaces when fully submerged, grams.
        displaced_mass: f64,
        /// Model mass minus displaced mass, grams: positive sinks, negative rises.
        mass_residual: f64,
        /// The allowed |mass_residual|, grams, when the goal gives one (left out of the JSON
        /// otherwise).
        #[serde(skip_serializing_if = "Option::is_none")]
        mass_tolerance: Option<f64>,
        /// As for [`GoalOutcome::Suspend`]: the floating model is then also met only when it has
        /// no other stable state.
        unique: bool,
        /// Every stable state of the fully submerged model.
        equilibria: Equilibria,
    },
}

/// Every stable state of a model hanging from a point or floating fully submerged, the pose's
/// articulation kept and the whole model free to turn.
///
/// An assignment of ball ends gives a centre of mass `c`; hung from `s` (or floating about the
/// centre of buoyancy `s`) the model settles with gravity along `c − s`, a stable orientation
/// since `c` is then below `s`. The assignment is a stable state when, with gravity so, every
/// ball rests at the end it was assigned. Standing states (resting facets) are not enumerated.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Equilibria {
    /// Whether every assignment was tried: false past
    /// [`MAX_ENUMERATED_BALLS`] rolling balls, when only the assignments that move at most
    /// [`CUT_FLIPS`] balls from the wanted state were.
    pub complete: bool,
    /// How many assignments were tried.
    pub assignments: usize,
    /// The stable states found, the wanted one first when it is one; then in the order of the
    /// assignments tried (deterministic).
    pub states: Vec<Equilibrium>,
}

impl Equilibria {
    /// The stable states other than the wanted one.
    pub fn unwanted(&self) -> impl Iterator<Item = &Equilibrium> {
        self.states.iter().filter(|state| !state.wanted)
    }
}

impl Equilibrium {
    /// The state in words, after a verb such as "hangs": `23.0° off, ball "c0" at its `from`
    /// end`, naming every ball that moved from where the pose has it, and whether it is marginal.
    pub fn describe(&self) -> String {
        let moved: Vec<String> = self
            .balls
            .iter()
            .filter(|ball| ball.moved)
            .map(|ball| {
                let end = match ball.rest {
                    BallRest::To => "to",
                    _ => "from",
                };
                format!("ball \"{}\" at its `{end}` end", ball.capsule)
            })
            .collect();
        let mut text = format!("{:.1}° off", self.angle);
        if !moved.is_empty() {
            text.push_str(", ");
            text.push_str(&moved.join(", "));
        }
        if self.marginal {
            text.push_str(" (marginal: a ball's axis is within min-angle of horizontal)");
        }
        text
    }
}

/// One stable state: where the balls are and how the model settles.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Equilibrium {
    /// Whether this is the state the goal wants: every ball at the end the pose puts it at (a
    /// ball undetermined in the pose matches either end).
    pub wanted: bool,
    /// Angle between the pose's gravity and this state's, both in the posed model's frame,
    /// degrees in [0, 180]: how far the settled model is turned from the goal's orientation.
    pub angle: f64,
    /// Unit gravity once settled, in the pose's world frame (which turns with the model).
    pub gravity: [f64; 3],
    /// Centre of mass in this state, the pose's world frame.
    pub centre_of_mass: [f64; 3],
    /// Whether some ball's axis is within the ball's min-angle of horizontal here, so the state
    /// may or may not hold in a print.
    pub marginal: bool,
    /// One per ball that weighs in the model (its capsule's component has a body), in the
    /// design's order.
    pub balls: Vec<StateBall>,
}

/// A ball in a stable state.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StateBall {
    /// The capsule's name.
    pub capsule: String,
    /// The end it rests at ([`BallRest::From`] for a spherical cavity).
    pub rest: BallRest,
    /// Angle of the capsule's axis above horizontal in this state, degrees in [0, 90].
    pub elevation: f64,
    /// Whether it rests at the other end than in the pose.
    pub moved: bool,
}
