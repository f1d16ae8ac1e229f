//! The constraints of the design, each written `g(x) ≥ 0` (paper eq. 3, 5, 14, 16 and 22, eq. 16
//! in the print direction, and the bounds on radius and infill).

use nalgebra::Vector3;

use super::mass::{axis_cosine, CapsuleVars, SmoothTotals};
use super::scalar::{Scalar, V3};
use super::setup::{GoalSetup, PoseSetup};

/// The fixed numbers the constraints compare with.
#[derive(Debug, Clone)]
pub(crate) struct Limits {
    /// Smallest radius, project units.
    pub min_radius: f64,
    /// Per component: the largest radius, project units.
    pub max_radius: Vec<f64>,
    /// Per pose: `sin²` of the minimum axis elevation.
    pub min_elevation_sine_squared: Vec<f64>,
    /// Material between two capsules, project units.
    pub wall: f64,
    /// Added to every distance limit (the axis at least as long as the radius, eq. 16; the wall
    /// to the surface, eq. 15; the wall between two capsules) for what rounding the design's
    /// ends into the solution file may take from it (project units).
    pub rounding_slack: f64,
    /// Sample positions along an axis, in [0, 1].
    pub samples: Vec<f64>,
}

/// The capsule constraints, capsule by capsule: `|q − p|² − (r + s)² ≥ 0` (eq. 16, `s` the
/// rounding slack), `r − r_min ≥ 0`,
/// `r_max − r ≥ 0`, then per pose `z² − sin² φ_min ≥ 0` (eq. 22 written without the arccos:
/// `|arccos z − π/2| ≥ φ` ⇔ `|z| ≥ sin φ`).
pub(crate) fn capsule_constraints<D: Scalar>(
    capsules: &[CapsuleVars<D>],
    poses: &[PoseSetup],
    limits: &Limits,
    out: &mut Vec<D>,
) {
    for capsule in capsules {
        let r = &capsule.r;
        let least = r.clone() + limits.rounding_slack;
        out.push(capsule.q.sub(&capsule.p).norm_squared() - least.clone() * least);
        out.push(r.clone() - limits.min_radius);
        let max = limits
            .max_radius
            .get(capsule.component)
            .copied()
            .unwrap_or(0.0);
        out.push(-r.clone() + max);
        for (pose, bound) in poses.iter().zip(&limits.min_elevation_sine_squared) {
            let z = axis_cosine(capsule, &pose.gravity_in(capsule.component));
            out.push(z.clone() * z - *bound);
        }
    }
}

/// How the balls must be able to go in while printing: what the insertion constraint compares
/// with.
#[derive(Debug, Clone, PartialEq)]
pub struct Insertion {
    /// Per capsule, in design order: the unit direction, rest frame, its component is printed
    /// along (away from the bed), or `None` for a capsule not constrained (a pinned one).
    pub up: Vec<Option<Vector3<f64>>>,
    /// Ball clearance `c`: a ball of radius at most `r − c` goes in a void of radius `r`.
    pub clearance: f64,
    /// Height of a printed layer `h`.
    pub layer_height: f64,
    /// Least gap `g` between the top of a resting ball and the top of the paused layer.
    pub pause_clearance: f64,
    /// Added to the rise required, for what rounding the design may take from it (project
    /// units).
    pub slack: f64,
}

/// Per constrained capsule: `u·(q − p) − (r − 3c + 2h + g + slack) ≥ 0`, `u` its print
/// direction.
///
/// The insertion window `[z_P − r + 2b + h + g, z_Q + r − b]` (heights along `u`, `b` the ball
/// radius; a layer for the stepped floor, `fabrication::insertion_window`) holds a layer
/// boundary whenever it is at least a layer `h` long, that is when the axis rises
/// `z_Q − z_P ≥ 3b − 2r + 2h + g`; with `b ≤ r − c` this follows from
/// `z_Q − z_P ≥ r − 3c + 2h + g`. Written
/// with `q` as the upper end (linear, so its gradient never vanishes, even for an axis across
/// `u`); the optimizer turns each capsule so that `q` is its upper end before it solves.
pub(crate) fn insertion_constraints<D: Scalar>(
    capsules: &[CapsuleVars<D>],
    insertion: &Insertion,
    out: &mut Vec<D>,
) {
    for (capsule, up) in capsules.iter().zip(&insertion.up) {
        if let Some(up) = up {
            out.push(insertion_constraint(capsule, up, insertion));
        }
    }
}

/// The insertion constraint of one capsule printed along `up` ([`insertion_constraints`]).
pub(crate) fn insertion_constraint<D: Scalar>(
    capsule: &CapsuleVars<D>,
    up: &Vector3<f64>,
    insertion: &Insertion,
) -> D {
    let rise = capsule.q.sub(&capsule.p).dot_constant(up);
    let needed = capsule.r.clone()
        + (2.0 * insertion.layer_height + insertion.pause_clearance + insertion.slack
            - 3.0 * insertion.clearance);
    rise - needed
}

/// Eq. 14 for every pair of capsules `i < j` of one component, once, at the closest points of
/// their axes: `|x_i(s*) − x_j(t*)|² − (r_i + r_j + wall)² ≥ 0` with `x(s) = p + s (q − p)` and
/// `(s*, t*)` the parameters of the closest points (clamped to the segments). The paper samples
/// every pair of axis points instead; the closest pair is the one that matters, and one constraint
/// per pair keeps the solver's subproblems small. `(s*, t*)` are found on the values and held
/// fixed for the derivative, which is then exact (the distance is minimal in them: Danskin's
/// theorem) wherever the closest points are unique. Squared, so it stays differentiable where the
/// axes meet.
pub(crate) fn pair_constraints<D: Scalar>(
    capsules: &[CapsuleVars<D>],
    limits: &Limits,
    out: &mut Vec<D>,
) {
    for (i, a) in capsules.iter().enumerate() {
        for b in &capsules[i + 1..] {
            if a.component != b.component {
                continue;
            }
            let reach = a.r.clone() + &b.r + limits.wall + limits.rounding_slack;
            let (s, t) = closest_parameters(&a.p.re(), &a.q.re(), &b.p.re(), &b.q.re());
            let gap = sample(a, s).sub(&sample(b, t)).norm_squared();
            out.push(gap - reach.clone() * reach);
        }
    }
}

/// The parameters `(s, t) ∈ [0, 1]²` of the closest points of the segments `p1 q1` and `p2 q2`
/// (Ericson, Real-Time Collision Detection, 5.1.9). Degenerate segments are points.
pub(crate) fn closest_parameters(
    p1: &Vector3<f64>,
    q1: &Vector3<f64>,
    p2: &Vector3<f64>,
    q2: &Vector3<f64>,
) -> (f64, f64) {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.dot(&d1);
    let e = d2.dot(&d2);
    let f = d2.dot(&r);
    let tiny = 1e-300;
    if a <= tiny && e <= tiny {
        return (0.0, 0.0);
    }
    if a <= tiny {
        return (0.0, (f / e).clamp(0.0, 1.0));
    }
    let c = d1.dot(&r);
    if e <= tiny {
        return ((-c / a).clamp(0.0, 1.0), 0.0);
    }
    let b = d1.dot(&d2);
    let denominator = a * e - b * b;
    let mut s = if denominator > 1e-12 * a * e {
        ((b * f - c * e) / denominator).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    (s, t)
}

/// The point `p + s (q − p)` of a capsule's axis.
pub(crate) fn sample<D: Scalar>(capsule: &CapsuleVars<D>, s: f64) -> V3<D> {
    capsule.p.add(&capsule.q.sub(&capsule.p).scale_by(s))
}

/// `w − lo ≥ 0` and `hi − w ≥ 0` for the infill fraction `w`.
pub(crate) fn infill_constraints<D: Scalar>(infill: &D, (lo, hi): (f64, f64), out: &mut Vec<D>) {
    out.push(infill.clone() - lo);
    out.push(-infill.clone() + hi);
}

/// The fraction of the displaced mass `ρ_F V` by which the smooth program keeps the mass within
/// an `immerse` goal's tolerance (at most half the tolerance): the objective gains from a mass
/// at the edge of the tolerance, so a solve ends there, and the material the judge weighs
/// differs from the corrected smooth model's by up to about a thousandth of it (the fish's two
/// capsules, solved onto the bound, were judged 7.6 mg outside a 1 g tolerance, 0.034 % of the
/// water it displaces).
pub(crate) const MASS_SLACK: f64 = 1e-3;

/// The immersion constraints of one pose, goal by goal: `|c − c_buo|² − d_min² ≥ 0` (eq. 5),
/// then, when the goal gives a mass tolerance `τ`, eq. 3 relaxed to `|m − ρ_F V| ≤ τ − σ` as
/// `τ − σ − (m − ρ_F V) ≥ 0` and `τ − σ + (m − ρ_F V) ≥ 0` (grams), the slack
/// `σ = min(MASS_SLACK · ρ_F V, τ / 2)`.
///
/// Mass and volume do not depend on the pose, so a mass constraint whose fluid density and
/// tolerance are already in `seen` (from an earlier goal) is not repeated; new ones are added to
/// `seen`.
pub(crate) fn immersion_constraints<D: Scalar>(
    setup: &PoseSetup,
    totals: &SmoothTotals<D>,
    seen: &mut Vec<(f64, f64)>,
    out: &mut Vec<D>,
) {
    for goal in &setup.goals {
        if let GoalSetup::Immerse {
            fluid_density,
            min_distance,
            mass_tolerance,
            ..
        } = goal
        {
            let offset = totals.centre.sub_constant(&setup.buoyancy_centre.coords);
            out.push(offset.norm_squared() - min_distance * min_distance);
            if let Some(tolerance) = mass_tolerance {
                if seen.contains(&(*fluid_density, *tolerance)) {
                    continue;
                }
                seen.push((*fluid_density, *tolerance));
                let displaced = fluid_density * setup.volume;
                let allowed = tolerance - (MASS_SLACK * displaced.abs()).min(0.5 * tolerance);
                let residual = totals.mass.clone() - displaced;
                out.push(-residual.clone() + allowed);
                out.push(residual + allowed);
            }
        }
    }
}
