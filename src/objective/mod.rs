//! The smooth objective and constraints an optimizer descends (paper section 4 and appendix A).
//!
//! [`Objective`] turns a design vector `x` (see [`DesignLayout`]) into
//!
//! - one smooth objective `f(x)`, the log-sum-exp smooth maximum (sharpness α) of every goal's
//!   objective in every pose, each in radians and at most 0 when its goal is met
//!   ([`Objective::value_and_gradient`]);
//! - the constraints `g(x) ≥ 0` ([`Objective::constraints`]),
//!
//! with exact gradients by forward-mode automatic differentiation (`num_dual` dual numbers: the
//! same generic code runs on `f64` for values and on dual numbers for gradients). Each pose's
//! design-independent data is precomputed once in a [`PoseSetup`]. Balls move between the ends of
//! their capsules by the sigmoid of eq. 21, so the centre of mass is smooth in `x`.
//!
//! `docs/optimizer.md` states the formulation. Lengths are in project units, masses in grams,
//! angles in radians. Deterministic: the same `x` gives the same bits. Never panics: a short `x`
//! is padded with zeros, extra entries are ignored.

mod constraints;
mod goals;
mod grid_interior;
mod interior;
mod layout;
mod mass;
mod parameters;
mod scalar;
mod setup;
mod smooth;
mod sparse;
mod uniqueness;

pub use constraints::Insertion;
pub use grid_interior::GridInterior;
pub use interior::InteriorDistance;
pub use layout::{DesignLayout, CAPSULE_STRIDE, P, Q, R};
pub use parameters::Parameters;
pub use scalar::Scalar;
pub use setup::PoseSetup;
pub use smooth::{smooth_max, smooth_min};

use nalgebra::{Point3, Vector3};

use self::constraints::Limits;
use self::mass::{capsules, CapsuleVars, Densities, SmoothTotals};
use self::scalar::Evaluate;
use crate::balance::ComponentBody;
use crate::geometry::TriMesh;
use crate::spec::model::{Goal, Project};

/// Degrees added to the ball's minimum elevation in eq. 22.
const ELEVATION_SLACK_DEGREES: f64 = 0.25;

/// The smooth objective and constraints of one project's goals for a fixed set of capsules.
pub struct Objective {
    layout: DesignLayout,
    parameters: Parameters,
    poses: Vec<PoseSetup>,
    densities: Densities,
    fixed_infill: f64,
    min_angle: f64,
    limits: Limits,
    interior: Option<Box<dyn InteriorDistance>>,
    insertion: Option<Insertion>,
}

impl Objective {
    /// The objective of `project`'s poses and goals for designs laid out by `layout`.
    ///
    /// `bodies` is indexed like `project.components`. Each component's largest capsule radius is
    /// half the shortest side of its mesh's bounding box (rest frame): no wider ball fits.
    pub fn new(
        project: &Project,
        bodies: &[ComponentBody],
        layout: DesignLayout,
        parameters: Parameters,
    ) -> Objective {
        let poses = project
            .poses
            .iter()
            .map(|pose| PoseSetup::new(project, bodies, pose, parameters.angle_smoothing))
            .collect();
        let cubic = project.units.cubic_in_cm3();
        let limits = Limits {
            min_radius: parameters.min_radius,
            max_radius: bodies.iter().map(|b| half_narrowest_side(b.mesh)).collect(),
            min_elevation_sine_squared: project
                .poses
                .iter()
                .map(|pose| {
                    let sine = (min_elevation(project, pose) + ELEVATION_SLACK_DEGREES)
                        .to_radians()
                        .sin();
                    sine * sine
                })
                .collect(),
            wall: project.wall,
            rounding_slack: 0.0,
            samples: parameters.samples(),
        };
        Objective {
            layout,
            poses,
            densities: Densities {
                material: project.material.density * cubic,
                ball: project.ball.density * cubic,
                clearance: project.ball.clearance,
                shell: crate::balance::capsule_shell(&project.print),
            },
            fixed_infill: project.infill.value,
            min_angle: project.ball.min_angle,
            limits,
            parameters,
            interior: None,
            insertion: None,
        }
    }

    /// The same objective with the interior constraints of eq. 15 evaluated by `interior`.
    pub fn with_interior(mut self, interior: Box<dyn InteriorDistance>) -> Objective {
        self.interior = Some(interior);
        self
    }

    /// The same objective with the insertion constraints: each capsule `insertion` constrains can
    /// take its ball at a pause with its component printed along its direction.
    pub fn with_insertion(mut self, insertion: Insertion) -> Objective {
        self.insertion = Some(insertion);
        self
    }

    /// The same objective with `slack` (project units, for what rounding the design into the
    /// solution file may take) added to every distance limit: the axis length of eq. 16, the
    /// wall between two capsules (eq. 14) and to the surface (eq. 15).
    pub fn with_rounding_slack(mut self, slack: f64) -> Objective {
        self.limits.rounding_slack = slack;
        self
    }

    /// The layout of the design vector.
    pub fn layout(&self) -> &DesignLayout {
        &self.layout
    }

    /// The parameters in use.
    pub fn parameters(&self) -> &Parameters {
        &self.parameters
    }

    /// The precomputed poses, in project order.
    pub fn poses(&self) -> &[PoseSetup] {
        &self.poses
    }

    /// `f(x)`: the smooth maximum (eq. 6, log-sum-exp with sharpness α) of
    /// [`goal_terms`](Self::goal_terms); 0 when the project has no goals.
    pub fn value(&self, x: &[f64]) -> f64 {
        let x = self.padded(x);
        let terms = self.terms(&x);
        smooth_max(&terms, self.parameters.goal_sharpness)
    }

    /// The largest of the [`goal_terms`](Self::goal_terms) at `x` (radians; at most 0 when the
    /// smooth model meets every goal, where `f`, a smooth maximum, may still be above 0);
    /// −∞ when the project has no goals.
    pub fn worst_goal_term(&self, x: &[f64]) -> f64 {
        let x = self.padded(x);
        self.terms(&x).into_iter().fold(f64::NEG_INFINITY, f64::max)
    }

    /// `f(x)` and its exact gradient `∂f/∂x` (length [`DesignLayout::len`]).
    pub fn value_and_gradient(&self, x: &[f64]) -> (f64, Vec<f64>) {
        let x = self.padded(x);
        scalar::with_gradients(&x, &SmoothMaxOfTerms(self))
            .pop()
            .unwrap_or_else(|| unreachable!("the smooth maximum is one output"))
    }

    /// Every goal's objective with its gradient, pose by pose, goal by goal (the terms `f_i` of
    /// eq. 6): radians, at most 0 when the goal is met.
    pub fn goal_terms(&self, x: &[f64]) -> Vec<(f64, Vec<f64>)> {
        let x = self.padded(x);
        scalar::with_gradients(&x, &Terms(self))
    }

    /// The smooth centre of mass (world) and mass (grams) of the design `x` in pose `pose`
    /// (project order), or `None` past the last pose.
    pub fn mass_properties(&self, pose: usize, x: &[f64]) -> Option<(Point3<f64>, f64)> {
        let setup = self.poses.get(pose)?;
        let x = self.padded(x);
        let totals = self.totals(setup, &x);
        Some((Point3::from(totals.centre.re()), totals.mass))
    }

    /// The constraints, each `(g(x), ∂g/∂x)` with `g(x) ≥ 0` required, in this order:
    ///
    /// 1. per capsule: `|q − p|² − (r + s)² ≥ 0` (eq. 16, squared project units; `s` the
    ///    rounding slack, [`Objective::with_rounding_slack`], 0 by default; it is added to the
    ///    wall limits below too), `r − r_min ≥ 0`,
    ///    `r_max − r ≥ 0` (project units), then per pose `z² − sin² φ_min ≥ 0` (eq. 22, `z` the
    ///    cosine between axis and gravity, `φ_min` = [`Ball::min_angle`](crate::spec::model::Ball::min_angle),
    ///    or the largest `stand` or `imbalance` margin of the pose when more, plus a slack of
    ///    0.25°, so a solution on this constraint's boundary still has a determined ball that does
    ///    not roll within the required tilt);
    /// 2. per pair of capsules in one component, at the closest points of their axes:
    ///    `|x_i − x_j|² − (r_i + r_j + wall + s)² ≥ 0` (eq. 14);
    /// 3. when the infill is a variable: `w − lo ≥ 0`, `hi − w ≥ 0`;
    /// 4. per pose, per `immerse` goal: `|c − c_buo|² − d_min² ≥ 0` (eq. 5), then with a mass
    ///    tolerance `τ`: `τ − (m − ρ_F V) ≥ 0` and `τ + (m − ρ_F V) ≥ 0` (eq. 3, grams), once per
    ///    distinct fluid density and tolerance (mass and volume do not depend on the pose);
    /// 5. per pose, per `suspend` or `immerse` goal with `unique=#true`, per assignment of ball
    ///    ends other than the wanted one (all of them up to 6 capsules, those moving one or two
    ///    balls beyond): some ball leaves its assigned end where that assignment settles,
    ///    `smax(−σ_i â_i·g_A) − ln(n)/s − sin(φ_min + 2°) ≥ 0` (`docs/optimizer.md`, "Uniqueness");
    /// 6. with an [`Insertion`] ([`with_insertion`](Self::with_insertion)), per capsule it
    ///    constrains: `u·(q − p) − (r − 3c + 2h + g + slack) ≥ 0` (eq. 16 in the print direction
    ///    `u` with the stepped floor and the pause clearance `g`, project units;
    ///    `docs/optimizer.md`);
    /// 7. with an [`InteriorDistance`] ([`with_interior`](Self::with_interior)), per capsule per
    ///    axis sample: `d(x) − r − wall − s ≥ 0` (eq. 15).
    ///
    /// The count depends only on the layout, the project, the parameters and the insertion
    /// directions, never on `x`.
    pub fn constraints(&self, x: &[f64]) -> Vec<(f64, Vec<f64>)> {
        let x = self.padded(x);
        // Those of one capsule or two in dual numbers of their unknowns alone; the rest in
        // dual numbers of every unknown.
        let mut result = sparse::capsule_gradients(self, &x);
        result.extend(sparse::pair_gradients(self, &x));
        result.extend(scalar::with_gradients(&x, &SharedConstraints(self)));
        result.extend(sparse::insertion_gradients(self, &x));
        if let Some(interior) = &self.interior {
            result.extend(self.interior_constraints(interior.as_ref(), &x));
        }
        result
    }

    /// The values of [`constraints`](Self::constraints) without their gradients (cheaper).
    pub fn constraint_values(&self, x: &[f64]) -> Vec<f64> {
        let x = self.padded(x);
        let mut result = self.smooth_constraints(&x);
        if let Some(interior) = &self.interior {
            result.extend(
                self.interior_constraints(interior.as_ref(), &x)
                    .into_iter()
                    .map(|(g, _)| g),
            );
        }
        result
    }

    /// Every constraint but eq. 15, in the order of [`constraints`](Self::constraints).
    fn smooth_constraints<D: Scalar>(&self, x: &[D]) -> Vec<D> {
        let mut out = Vec::new();
        let vars = capsules(&self.layout, x);
        constraints::capsule_constraints(&vars, &self.poses, &self.limits, &mut out);
        constraints::pair_constraints(&vars, &self.limits, &mut out);
        self.shared_constraints(x, &vars, &mut out);
        if let Some(insertion) = &self.insertion {
            constraints::insertion_constraints(&vars, insertion, &mut out);
        }
        out
    }

    /// Constraints 3 to 5 of [`constraints`](Self::constraints), which read more than two
    /// capsules' unknowns (the infill's, the mass, the centre of mass), added to `out`.
    fn shared_constraints<D: Scalar>(&self, x: &[D], vars: &[CapsuleVars<D>], out: &mut Vec<D>) {
        if let (Some(i), Some(range)) = (self.layout.infill_index(), self.layout.infill_range) {
            constraints::infill_constraints(&x[i], range, out);
        }
        let mut seen = Vec::new();
        for setup in &self.poses {
            if setup
                .goals
                .iter()
                .any(|g| matches!(g, setup::GoalSetup::Immerse { .. }))
            {
                let totals = self.totals(setup, x);
                constraints::immersion_constraints(setup, &totals, &mut seen, out);
            }
        }
        let infill = self.infill(x);
        for setup in &self.poses {
            uniqueness::uniqueness_constraints(
                setup,
                vars,
                &infill,
                self.densities,
                self.min_angle,
                out,
            );
        }
    }

    /// Eq. 15 at every axis sample of every capsule, by the chain rule through `interior`.
    fn interior_constraints(
        &self,
        interior: &dyn InteriorDistance,
        x: &[f64],
    ) -> Vec<(f64, Vec<f64>)> {
        let mut out = Vec::new();
        for (j, &component) in self.layout.components.iter().enumerate() {
            let base = j * CAPSULE_STRIDE;
            let p = Vector3::from_column_slice(&x[base + P..base + P + 3]);
            let q = Vector3::from_column_slice(&x[base + Q..base + Q + 3]);
            for &s in &self.limits.samples {
                let point = Point3::from(p + (q - p) * s);
                let (distance, direction) = interior.distance(component, &point);
                let mut gradient = vec![0.0; x.len()];
                for k in 0..3 {
                    gradient[base + P + k] = (1.0 - s) * direction[k];
                    gradient[base + Q + k] = s * direction[k];
                }
                gradient[base + R] = -1.0;
                out.push((
                    distance - x[base + R] - self.limits.wall - self.limits.rounding_slack,
                    gradient,
                ));
            }
        }
        out
    }

    /// Every goal's objective, pose by pose.
    fn terms<D: Scalar>(&self, x: &[D]) -> Vec<D> {
        let mut terms = Vec::new();
        for setup in &self.poses {
            if setup.goals.is_empty() {
                continue;
            }
            let totals = self.totals(setup, x);
            for goal in &setup.goals {
                terms.push(goals::goal_objective(
                    goal,
                    setup,
                    &totals,
                    self.parameters.edge_sharpness,
                ));
            }
        }
        terms
    }

    /// The smooth mass totals of `x` in `setup`'s pose.
    fn totals<D: Scalar>(&self, setup: &PoseSetup, x: &[D]) -> SmoothTotals<D> {
        mass::totals(
            setup,
            &capsules(&self.layout, x),
            &self.infill(x),
            self.densities,
            self.parameters.ball_sharpness,
        )
    }

    /// The infill fraction of `x`: its variable, or the project's fixed value.
    fn infill<D: Scalar>(&self, x: &[D]) -> D {
        match self.layout.infill_index() {
            Some(i) => x[i].clone(),
            None => D::from(self.fixed_infill),
        }
    }

    /// `x` cut or padded with zeros to the layout's length.
    fn padded(&self, x: &[f64]) -> Vec<f64> {
        let mut x = x.to_vec();
        x.resize(self.layout.len(), 0.0);
        x
    }
}

/// `f(x)` as the one output of an [`Evaluate`]: for its gradient.
struct SmoothMaxOfTerms<'a>(&'a Objective);

impl Evaluate for SmoothMaxOfTerms<'_> {
    fn evaluate<D: Scalar>(&self, x: &[D]) -> Vec<D> {
        let objective = self.0;
        vec![smooth_max(
            &objective.terms(x),
            objective.parameters.goal_sharpness,
        )]
    }
}

/// The goal terms as the outputs of an [`Evaluate`]: for their gradients.
struct Terms<'a>(&'a Objective);

impl Evaluate for Terms<'_> {
    fn evaluate<D: Scalar>(&self, x: &[D]) -> Vec<D> {
        self.0.terms(x)
    }
}

/// Constraints 3 to 5 as the outputs of an [`Evaluate`]: for their gradients.
struct SharedConstraints<'a>(&'a Objective);

impl Evaluate for SharedConstraints<'_> {
    fn evaluate<D: Scalar>(&self, x: &[D]) -> Vec<D> {
        let mut out = Vec::new();
        let vars = capsules(&self.0.layout, x);
        self.0.shared_constraints(x, &vars, &mut out);
        out
    }
}

/// The smallest elevation of a capsule axis in `pose`, degrees, before the slack of eq. 22: the
/// ball's `min-angle`, or the largest margin a `stand` or `imbalance` goal of the pose asks for
/// when that is more. No ball then rolls while the ground tilts by less than the required margin,
/// so a design whose balls-held margin meets it meets it with the balls rolling too.
fn min_elevation(project: &Project, pose: &crate::spec::model::Pose) -> f64 {
    pose.goals
        .iter()
        .filter_map(|goal| match goal.value {
            Goal::Stand { margin, .. } | Goal::Imbalance { margin, .. } => Some(margin),
            Goal::Suspend { .. } | Goal::Immerse { .. } => None,
        })
        .fold(project.ball.min_angle, f64::max)
}

/// Half the shortest side of `mesh`'s bounding box; 0 without vertices.
pub(crate) fn half_narrowest_side(mesh: &TriMesh) -> f64 {
    let Some(first) = mesh.positions.first() else {
        return 0.0;
    };
    let (lo, hi) = mesh
        .positions
        .iter()
        .fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    0.5 * (hi - lo).min()
}
