//! One project's optimization problem: the objective, bounds and starting point for any set of
//! starting capsules, and the exact verdict on the design a solve reaches.

use std::sync::Arc;

use nalgebra::{Point3, Vector3};

use super::bounds::design_bounds;
use super::solver::{solve, Bounds, Budget, Method, Solve, FEASIBLE};
use super::stock::{capsule_radius, grid_scale, length_decimals, snap};
use crate::balance::{
    component_material, evaluate_pose, ComponentBody, GoalOutcome, PartPrints, PoseEvaluation,
};
use crate::cancel::Cancel;
use crate::design::{Design, PlacedCapsule};
use crate::fabrication::{check_design, CapsuleIssue, PrintSetup};
use crate::geometry::{PrintCorrection, TriMesh};
use crate::objective::{
    DesignLayout, GridInterior, Insertion, Objective, Parameters, CAPSULE_STRIDE, R,
};
use crate::spec::model::Project;

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

/// At most this many solves, after the first, with the closed-form capsule term corrected
/// towards the re-sliced material ([`Problem::corrected_bodies`]).
const CORRECTIONS: usize = 3;

/// Whether two sets of bodies have the same material within what moves no goal: volumes within
/// 1e-4 of each component's outer volume, first moments within that volume times 1e-4 of its
/// size (its cube root).
fn same_material(a: &[ComponentBody], b: &[ComponentBody]) -> bool {
    a.iter().zip(b).all(|(a, b)| {
        let volume = a.mass.volume.abs();
        let size = volume.cbrt();
        let moment =
            |body: &ComponentBody| body.print.solid.centroid.coords * body.print.solid.volume;
        (a.print.solid.volume - b.print.solid.volume).abs() <= 1e-4 * volume
            && (moment(a) - moment(b)).norm() <= 1e-4 * volume * size
    })
}

/// Everything fixed while the capsules vary.
pub struct Problem<'a> {
    project: &'a Project,
    meshes: &'a [TriMesh],
    bodies: Vec<ComponentBody<'a>>,
    /// Each component's print, to cut a design's voids from when it is judged.
    parts: PartPrints,
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
        parts: &PartPrints,
        print: PrintSetup,
        interior: Arc<GridInterior>,
        method: Method,
    ) -> Problem<'a> {
        Problem {
            project,
            meshes,
            bodies: parts.bare_bodies(meshes),
            parts: parts.clone(),
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

    /// Optimizes from `start` and judges the result. Each unpinned capsule is first turned end
    /// for end when its `from` is the higher end along its component's print direction: the
    /// insertion constraint wants `to` on top.
    pub fn optimize(&self, start: &[StartCapsule]) -> Outcome {
        let start: Vec<StartCapsule> = start.iter().map(|c| self.upright(c)).collect();
        let start = start.as_slice();
        let design = self.start_design(start);
        let layout = DesignLayout::for_design(self.project, &design);
        let objective_over = |bodies: &[ComponentBody]| {
            Objective::new(
                self.project,
                bodies,
                layout.clone(),
                self.parameters.clone(),
            )
            .with_interior(Box::new(self.interior.clone()))
            .with_insertion(self.insertion(start))
            .with_rounding_slack(self.rounding_slack())
        };
        let objective = objective_over(&self.bodies);
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
        let budget = Budget {
            evaluations: (self.budget_per_unknown * layout.len()).max(200),
            cancel: self.cancel.clone(),
            ..Budget::default()
        };
        let solved = solve(&objective, &x0, &bounds, self.method, budget.clone());
        // The closed-form capsule term is the smooth stand-in for the material the judge weighs
        // (the design's voids cut from the print): correct it by their difference at the solved
        // design and solve again from there, until the correction at the new design is the one
        // it was solved with, so that the objective is that material's near the design.
        let to_design =
            |x: &[f64]| layout.to_design(x, &self.project.ball, self.project.infill.value);
        let mut corrected = self.corrected_bodies(&to_design(&solved.x));
        let mut solved = solved;
        for _ in 0..CORRECTIONS {
            let again = solve(
                &objective_over(&corrected),
                &solved.x,
                &bounds,
                self.method,
                budget.clone(),
            );
            solved = Solve {
                evaluations: solved.evaluations + again.evaluations,
                ..again
            };
            let next = self.corrected_bodies(&to_design(&solved.x));
            let settled = same_material(&corrected, &next);
            corrected = next;
            if settled {
                break;
            }
        }
        let objective = objective_over(&corrected);
        let solved = self.snapped(&objective, &bounds, start, solved, budget);
        let mut design = layout.to_design(&solved.x, &self.project.ball, self.project.infill.value);
        for (capsule, started) in design.capsules.iter_mut().zip(start) {
            if let Some(ball) = self.project.ball.radius_for(capsule.radius) {
                capsule.ball_radius = ball;
            }
            if started.pinned {
                capsule.from = started.from;
                capsule.to = started.to;
                capsule.radius = started.radius;
            }
        }
        let mut outcome = self.judge(design);
        // The grid's interpolant can overestimate the distance to a sharp feature by a fraction
        // of a cell: shrink any capsule that came too close, by the exact deficit, and re-judge.
        // A stock radius cannot shrink by a fraction of a cell, only to the next smaller ball:
        // first the capsules are moved instead, solved again as if wider by their deficit. A
        // deficit past a cell is not the interpolant's but a solve that ended outside the
        // constraints; solving again from there rarely mends it and costs as much as the solve,
        // so such a capsule is only shrunk.
        let listed = self.project.ball.is_listed();
        let mut widening = vec![0.0; start.len()];
        for attempt in 0..3 {
            let move_first = listed && attempt < 2;
            let mut shrunk = outcome.design.clone();
            let (mut changed, mut moving) = (false, false);
            for issue in &outcome.fabrication {
                if let CapsuleIssue::TooCloseToSurface {
                    capsule,
                    distance,
                    required,
                    ..
                } = *issue
                {
                    if start.get(capsule).is_none_or(|s| s.pinned) {
                        continue;
                    }
                    let c = &mut shrunk.capsules[capsule];
                    // Past the limit by what rounding the ends into the solution file may take.
                    let deficit = (required - distance) * 1.01
                        + 1e-9 * c.radius.abs()
                        + self.rounding_slack();
                    if move_first && required - distance <= self.grid_cell(c.component) {
                        widening[capsule] += deficit;
                        moving = true;
                        continue;
                    }
                    let mut radius = c.radius - deficit;
                    let Some(ball) = self.project.ball.radius_for(radius) else {
                        continue;
                    };
                    if listed {
                        radius = capsule_radius(&self.project.ball, ball, self.scale);
                    }
                    c.radius = radius;
                    c.ball_radius = ball;
                    changed = true;
                }
            }
            if !changed && !moving {
                break;
            }
            // A capsule shrunk beside one moved is shrunk at a later attempt, if still too close
            // where the move left it.
            if moving {
                shrunk = self.moved(&objective, &bounds, &layout, &outcome.design, &widening);
            }
            outcome = self.judge(shrunk);
        }
        outcome.value = objective.value(&layout.to_vector(&outcome.design));
        outcome.feasible = solved.violation <= FEASIBLE;
        outcome.evaluations = solved.evaluations;
        outcome
    }

    /// The bodies of the smooth objective near `design`: each component's bare material, plus
    /// for one with capsules the difference between its material with `design`'s voids cut
    /// ([`PartPrints::bodies`], what [`Problem::judge`] weighs) and the closed-form capsule term
    /// at `design`, as a correction of its solid part.
    fn corrected_bodies(&self, design: &Design) -> Vec<ComponentBody<'a>> {
        let cut = self.parts.bodies(self.meshes, design);
        self.bodies
            .iter()
            .zip(&cut)
            .enumerate()
            .map(|(index, (bare, cut))| {
                if !design.capsules.iter().any(|c| c.component == index) {
                    return *bare;
                }
                let truth = component_material(self.project, cut, design, index);
                let surrogate = component_material(self.project, bare, design, index);
                let correction = PrintCorrection::default().plus_difference(&truth, &surrogate);
                match correction.apply(&bare.print) {
                    Some(print) => ComponentBody { print, ..*bare },
                    None => *bare,
                }
            })
            .collect()
    }

    /// The spacing of component `component`'s distance grid (0 without one).
    fn grid_cell(&self, component: usize) -> f64 {
        self.interior
            .grids
            .get(component)
            .map_or(0.0, |grid| grid.cell())
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
            slack: self.rounding_slack(),
        }
    }

    /// `design` with its capsules' ends and the infill solved again from where they are, every
    /// radius fixed and each capsule seen by the constraints as `widening` wider than it is (so
    /// that it keeps that much further from the surface); radii and balls stay `design`'s.
    fn moved(
        &self,
        objective: &Objective,
        bounds: &Bounds,
        layout: &DesignLayout,
        design: &Design,
        widening: &[f64],
    ) -> Design {
        let mut x = layout.to_vector(design);
        let mut fixed = bounds.clone();
        for (j, extra) in widening.iter().enumerate() {
            let i = j * CAPSULE_STRIDE + R;
            x[i] += extra;
            fixed.range[i] = (x[i], x[i]);
        }
        let budget = Budget {
            evaluations: (self.budget_per_unknown * layout.len()).max(200),
            cancel: self.cancel.clone(),
            ..Budget::default()
        };
        let again = solve(objective, &x, &fixed, self.method, budget);
        let mut moved = layout.to_design(&again.x, &self.project.ball, self.project.infill.value);
        for (capsule, kept) in moved.capsules.iter_mut().zip(&design.capsules) {
            capsule.radius = kept.radius;
            capsule.ball_radius = kept.ball_radius;
        }
        moved
    }

    /// `solved` with the radius of every unpinned capsule snapped to a stock ball plus the
    /// clearance ([`snap`]; the larger ball only when it breaks no constraint the smaller keeps),
    /// then those radii fixed and everything else solved again from there; the snapped point
    /// itself when the second solve ends at a higher objective. `solved` itself when balls come
    /// in any size.
    fn snapped(
        &self,
        objective: &Objective,
        bounds: &Bounds,
        start: &[StartCapsule],
        solved: Solve,
        budget: Budget,
    ) -> Solve {
        let ball = &self.project.ball;
        if !ball.is_listed() || start.iter().all(|c| c.pinned) {
            return solved;
        }
        let mut x = solved.x.clone();
        let mut fixed = bounds.clone();
        for (j, capsule) in start.iter().enumerate() {
            let i = j * CAPSULE_STRIDE + R;
            if capsule.pinned {
                continue;
            }
            let with = |radius: f64| {
                let mut trial = x.clone();
                trial[i] = radius;
                objective.constraint_values(&trial)
            };
            let allowed = |larger: f64| {
                let lower = ball
                    .radius_for(x[i])
                    .map_or(0.0, |b| capsule_radius(ball, b, self.scale));
                larger <= bounds.range[i].1
                    && with(larger)
                        .iter()
                        .zip(with(lower))
                        .all(|(g, kept)| *g >= 0.0 || *g >= kept)
            };
            let Some((radius, _)) = snap(ball, x[i], self.scale, allowed) else {
                continue;
            };
            x[i] = radius;
            fixed.range[i] = (radius, radius);
        }
        // The snapped point itself, evaluated as a solve with nothing free: the second solve
        // prefers a smaller constraint violation to a lower objective, and from a point just
        // outside the constraints it can drift far from the design the first solve found.
        let pinned = Bounds {
            range: x.iter().map(|&v| (v, v)).collect(),
            ..bounds.clone()
        };
        let at_snap = solve(objective, &x, &pinned, self.method, budget.clone());
        let again = solve(objective, &x, &fixed, self.method, budget);
        let evaluations = solved.evaluations + at_snap.evaluations + again.evaluations;
        let best = if at_snap.value < again.value {
            at_snap
        } else {
            again
        };
        Solve {
            evaluations,
            ..best
        }
    }

    /// The exact verdict on `design`: every pose evaluated with the design's voids cut from the
    /// print ([`PartPrints::bodies`]), every capsule checked.
    pub fn judge(&self, design: Design) -> Outcome {
        let bodies = self.parts.bodies(self.meshes, &design);
        let poses: Vec<PoseEvaluation> = self
            .project
            .poses
            .iter()
            .map(|pose| evaluate_pose(self.project, &bodies, &design, pose))
            .collect();
        let fabrication = check_design(
            self.meshes,
            &design,
            self.project.wall,
            self.project.ball.clearance,
            &self.print,
        );
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
