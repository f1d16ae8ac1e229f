//! One project's optimization problem: the objective, bounds and starting point for any set of
//! starting capsules, and the exact verdict on the design a solve reaches.

use std::sync::Arc;

use nalgebra::{Point3, Vector3};

use super::bounds::design_bounds;
use super::solver::{preferred, solve, Bounds, Budget, Method, Solve, FEASIBLE, WORTH_HAVING};
use super::stock::{grid_scale, length_decimals};
use crate::balance::{evaluate_pose, ComponentBody, GoalOutcome, PartPrints, PoseEvaluation};
use crate::cancel::Cancel;
use crate::design::{Design, PlacedCapsule};
use crate::fabrication::{check_design, CapsuleIssue, PrintSetup};
use crate::geometry::TriMesh;
use crate::objective::{
    DesignLayout, GridInterior, Insertion, Objective, Parameters, CAPSULE_STRIDE,
};
use crate::spec::model::Project;

mod refine;

/// A capsule the optimizer starts from: from a skeleton segment, from the project file, or
/// random.
#[derive(Debug, Clone, PartialEq)]
pub struct StartCapsule {
    /// Index of its component.
    pub component: usize,
    /// One end of the axis, rest frame.
    pub from: Point3<f64>,
    /// The other end.
    pub to: Point3<f64>,
    /// Void radius.
    pub radius: f64,
    /// Kept exactly as it is: not moved, resized or removed.
    pub pinned: bool,
    /// Its name in the project file, for a capsule written there, or in the earlier design it
    /// comes from.
    pub name: Option<String>,
    /// Where it came from.
    pub origin: Origin,
}

/// Where a start capsule came from, so that the capsule the optimizer makes of it can say so.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    /// Written in the project file; [`StartCapsule::name`] is its name there.
    Written,
    /// Seeded at a skeleton segment's midpoint: the index of its site among those
    /// [`skeleton_seeds`](super::skeleton_seeds) returns.
    Skeleton(usize),
    /// A capsule of an earlier design (watch mode's warm start); [`StartCapsule::name`] is its
    /// name there.
    Earlier,
    /// A random start of exhaustive search.
    Random,
}

impl StartCapsule {
    /// An unnamed, unpinned capsule of `component` centred on `centre`, its ends at
    /// `centre ± half_axis`.
    pub fn centred(
        component: usize,
        centre: Point3<f64>,
        half_axis: Vector3<f64>,
        radius: f64,
        origin: Origin,
    ) -> StartCapsule {
        StartCapsule {
            component,
            from: centre - half_axis,
            to: centre + half_axis,
            radius,
            pinned: false,
            name: None,
            origin,
        }
    }
}

/// A design the optimizer reached, judged exactly.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The capsules and infill.
    pub design: Design,
    /// The smooth objective `f` there (radians; at most 0 when every goal is met).
    pub value: f64,
    /// Whether the design is within the constraints: those of the smooth program after a solve,
    /// the fabrication checks for a design only judged.
    pub feasible: bool,
    /// Whether every goal of every pose is met by the exact evaluation and no capsule has a
    /// fabrication issue.
    pub meets_goals: bool,
    /// The smallest tilt margin over every `stand` goal, degrees; `None` without stand goals.
    pub worst_tilt_margin: Option<f64>,
    /// The exact evaluation, one per pose.
    pub poses: Vec<PoseEvaluation>,
    /// What keeps capsules from being printed where they are (empty when all can be).
    pub fabrication: Vec<CapsuleIssue>,
    /// Objective evaluations spent.
    pub evaluations: usize,
}

/// Where a solve of the smooth program from a start left the design, before the judge's
/// refinement ([`Problem::explore`], [`Problem::refine`]).
#[derive(Debug, Clone)]
pub struct Explored {
    /// The start, each unpinned capsule upright along its component's print direction.
    start: Vec<StartCapsule>,
    /// Where each capsule's unknowns sit in the design vector.
    layout: DesignLayout,
    /// The bounds the solve kept to (pinned capsules fixed).
    bounds: Bounds,
    /// What the solve reached.
    solved: Solve,
    /// The design the solve reached (radii not yet snapped to stock balls).
    pub design: Design,
}

impl Explored {
    /// Whether this solve reached a better point of the smooth program than `other`: within
    /// the constraints where `other` is not, else the lower objective (the smaller violation
    /// when neither is within them).
    pub fn is_better_than(&self, other: &Explored) -> bool {
        let (a, b) = (&self.solved, &other.solved);
        preferred((a.value, a.violation), (b.value, b.violation))
    }
}

/// Everything fixed while the capsules vary.
pub struct Problem<'a> {
    project: &'a Project,
    meshes: &'a [TriMesh],
    bodies: Vec<ComponentBody<'a>>,
    /// Each component's print, to cut a design's voids from when it is judged (its cuts kept
    /// for whoever weighs the chosen design after the search).
    parts: &'a PartPrints,
    interior: Arc<GridInterior>,
    parameters: Parameters,
    method: Method,
    budget_per_unknown: usize,
    cancel: Cancel,
    /// Steps per unit of the solution file's length grid, which stock capsule radii sit on.
    scale: f64,
    /// How each component is printed: the direction every ball must go in along.
    print: PrintSetup,
}

impl<'a> Problem<'a> {
    /// The problem of `project` (its capsules are ignored: the start capsules replace them) over
    /// `meshes` (one per component), with `interior` keeping capsules inside and every ball
    /// insertable at a pause with the components printed as `print` says.
    pub fn new(
        project: &'a Project,
        meshes: &'a [TriMesh],
        parts: &'a PartPrints,
        print: PrintSetup,
        interior: Arc<GridInterior>,
        method: Method,
    ) -> Problem<'a> {
        Problem {
            project,
            meshes,
            bodies: parts.bare_bodies(meshes),
            parts,
            interior,
            parameters: Parameters::for_project(project),
            method,
            budget_per_unknown: 100,
            cancel: Cancel::new(),
            scale: grid_scale(length_decimals(meshes)),
            print,
        }
    }

    /// This problem, with every solve giving up soon after `cancel` is set.
    pub fn with_cancel(mut self, cancel: Cancel) -> Problem<'a> {
        self.cancel = cancel;
        self
    }

    /// Whether the work on this problem was asked to stop: a solve reached since means nothing.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.is_cancelled()
    }

    /// The project.
    pub fn project(&self) -> &Project {
        self.project
    }

    /// The component meshes.
    pub fn meshes(&self) -> &[TriMesh] {
        self.meshes
    }

    /// The parameters of the smooth formulation.
    pub fn parameters(&self) -> &Parameters {
        &self.parameters
    }

    /// Optimizes from `start` and judges the result: [`Problem::explore`], then
    /// [`Problem::refine`].
    pub fn optimize(&self, start: &[StartCapsule]) -> Outcome {
        self.refine(&self.explore(start))
    }

    /// Whether two solves of one round reached the same minimum of the smooth program: both
    /// within the constraints, their objectives within 10⁻⁴ rad (a gain worth having) of each
    /// other, and every capsule's ends and radius within its component's distance-grid spacing
    /// of the other's (closer than the wall constraint's grid resolves), the infill within
    /// 10⁻³. Refining one after the other would only repeat it.
    pub fn same_minimum(&self, a: &Explored, b: &Explored) -> bool {
        let (sa, sb) = (&a.solved, &b.solved);
        let (da, db) = (&a.design, &b.design);
        sa.violation <= FEASIBLE
            && sb.violation <= FEASIBLE
            && (sa.value - sb.value).abs() < WORTH_HAVING
            && (da.infill - db.infill).abs() <= 1e-3
            && da.capsules.len() == db.capsules.len()
            && da.capsules.iter().zip(&db.capsules).all(|(ca, cb)| {
                let cell = self.grid_cell(ca.component);
                ca.component == cb.component
                    && (ca.from - cb.from).norm() <= cell
                    && (ca.to - cb.to).norm() <= cell
                    && (ca.radius - cb.radius).abs() <= cell
            })
    }

    /// Solves the smooth program from `start`, the closed-form capsule term standing in for the
    /// material the judge weighs. Each unpinned capsule is first turned end for end when its
    /// `from` is the higher end along its component's print direction: the insertion constraint
    /// wants `to` on top.
    pub fn explore(&self, start: &[StartCapsule]) -> Explored {
        self.explore_within(start, |layout| self.budget(layout))
    }

    /// Optimizes from `start`, a design already solved with capsules added to it, and judges the
    /// result: as [`Problem::optimize`], with the hybrid's COBYLA pass only where SLSQP ends
    /// outside the constraints (the budget of the refinement's solves).
    pub fn optimize_near(&self, start: &[StartCapsule]) -> Outcome {
        self.refine(&self.explore_within(start, |layout| self.near_budget(layout)))
    }

    /// [`Problem::explore`] with the stops `budget` gives a layout.
    fn explore_within(
        &self,
        start: &[StartCapsule],
        budget: impl Fn(&DesignLayout) -> Budget,
    ) -> Explored {
        let start: Vec<StartCapsule> = start.iter().map(|c| self.upright(c)).collect();
        let design = self.start_design(&start);
        let layout = DesignLayout::for_design(self.project, &design);
        let objective = self.objective_over(&self.bodies, &layout, &start);
        let mut bounds = design_bounds(&objective, self.meshes);
        let x0 = layout.to_vector(&design);
        for (j, capsule) in start.iter().enumerate() {
            if capsule.pinned {
                let entries = j * CAPSULE_STRIDE..(j + 1) * CAPSULE_STRIDE;
                for (range, &value) in bounds.range[entries.clone()].iter_mut().zip(&x0[entries]) {
                    *range = (value, value);
                }
            }
        }
        let solved = solve(&objective, &x0, &bounds, self.method, budget(&layout));
        let design = layout.to_design(&solved.x, &self.project.ball, self.project.infill.value);
        Explored {
            start,
            layout,
            bounds,
            solved,
            design,
        }
    }

    /// The objective of designs laid out as `layout` from `start`, over `bodies`.
    fn objective_over(
        &self,
        bodies: &[ComponentBody],
        layout: &DesignLayout,
        start: &[StartCapsule],
    ) -> Objective {
        Objective::new(
            self.project,
            bodies,
            layout.clone(),
            self.parameters.clone(),
        )
        .with_interior(Box::new(self.interior.clone()))
        .with_insertion(self.insertion(start))
        .with_rounding_slack(self.rounding_slack())
    }

    /// The stops of one local solve of a design laid out as `layout`.
    fn budget(&self, layout: &DesignLayout) -> Budget {
        Budget {
            evaluations: (self.budget_per_unknown * layout.len()).max(200),
            cancel: self.cancel.clone(),
            ..Budget::default()
        }
    }

    /// The stops of a solve from a design already solved (the refinement's): as
    /// [`Problem::budget`], with the hybrid's COBYLA pass only when SLSQP ends outside the
    /// constraints.
    fn near_budget(&self, layout: &DesignLayout) -> Budget {
        Budget {
            fallback_on_goals: false,
            ..self.budget(layout)
        }
    }

    /// `capsule` with `to` its upper end along its component's print direction, unless pinned.
    fn upright(&self, capsule: &StartCapsule) -> StartCapsule {
        let up = self.up(capsule.component);
        let mut capsule = capsule.clone();
        if !capsule.pinned && up.dot(&(capsule.to - capsule.from)) < 0.0 {
            std::mem::swap(&mut capsule.from, &mut capsule.to);
        }
        capsule
    }

    /// The print direction of component `component` (+z past the list).
    fn up(&self, component: usize) -> Vector3<f64> {
        self.print
            .up
            .get(component)
            .copied()
            .unwrap_or_else(Vector3::z)
    }

    /// What rounding both ends of a capsule onto the solution file's length grid may take from
    /// a length or a distance: two steps of that grid (at most √3 steps can be lost).
    fn rounding_slack(&self) -> f64 {
        2.0 / self.scale
    }

    /// The insertion constraints of `start`: every unpinned capsule along its component's print
    /// direction, with a slack of two steps of the solution file's length grid (what rounding
    /// both ends there can take from the rise is at most √3 steps).
    fn insertion(&self, start: &[StartCapsule]) -> Insertion {
        Insertion {
            up: start
                .iter()
                .map(|c| (!c.pinned).then(|| self.up(c.component)))
                .collect(),
            clearance: self.project.ball.clearance,
            layer_height: self.print.grid.layer_height,
            pause_clearance: self.print.grid.pause_clearance,
            slack: self.rounding_slack(),
        }
    }

    /// The spacing of component `component`'s distance grid (0 without one).
    fn grid_cell(&self, component: usize) -> f64 {
        self.interior
            .grids
            .get(component)
            .map_or(0.0, |grid| grid.cell())
    }

    /// What keeps the capsules of `design` from being printed where they are
    /// ([`check_design`]).
    fn fabrication(&self, design: &Design) -> Vec<CapsuleIssue> {
        check_design(
            self.meshes,
            design,
            self.project.wall,
            self.project.ball.clearance,
            &self.print,
        )
    }

    /// The bodies of the components with `design`'s voids cut from the print
    /// ([`PartPrints::bodies`]): the material the judge weighs.
    fn cut(&self, design: &Design) -> Vec<ComponentBody<'_>> {
        self.parts.bodies(self.meshes, design)
    }

    /// The exact verdict on `design`, whose fabrication checks ([`Problem::fabrication`]) found
    /// `fabrication` and whose voids cut from the print leave `bodies` ([`Problem::cut`]):
    /// every pose evaluated with them.
    fn judge(
        &self,
        design: Design,
        fabrication: Vec<CapsuleIssue>,
        bodies: &[ComponentBody],
    ) -> Outcome {
        let poses: Vec<PoseEvaluation> = self
            .project
            .poses
            .iter()
            .map(|pose| evaluate_pose(self.project, bodies, &design, pose))
            .collect();
        let printable = fabrication.is_empty();
        let goals_met = poses.iter().all(|p| p.goals.iter().all(|g| g.met));
        let worst_tilt_margin = poses
            .iter()
            .flat_map(|p| &p.goals)
            .filter_map(|g| match g.outcome {
                GoalOutcome::Stand { tilt_margin, .. } => Some(tilt_margin),
                _ => None,
            })
            .reduce(f64::min);
        Outcome {
            design,
            value: f64::NAN,
            feasible: printable,
            meets_goals: goals_met && printable,
            worst_tilt_margin,
            poses,
            fabrication,
            evaluations: 0,
        }
    }

    /// The design `start` describes, each capsule with the ball that fits it.
    fn start_design(&self, start: &[StartCapsule]) -> Design {
        let ball = &self.project.ball;
        Design {
            capsules: start
                .iter()
                .enumerate()
                .map(|(j, c)| PlacedCapsule {
                    name: c
                        .name
                        .clone()
                        .unwrap_or_else(|| format!("capsule {}", j + 1)),
                    component: c.component,
                    from: c.from,
                    to: c.to,
                    radius: c.radius,
                    ball_radius: ball.radius_for(c.radius).unwrap_or(0.0),
                })
                .collect(),
            infill: self.project.infill.value,
        }
    }
}
