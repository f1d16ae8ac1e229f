//! The constraints that make the wanted state of a hanging or floating goal the only stable one
//! (`unique=#true`).
//!
//! For an assignment `A` of ball ends (`σ_i = +1` at `to`, `−1` at `from`) the model settles with
//! gravity `g_A` along `c_A − s`, `s` the suspension point or the centre of buoyancy. `A` is not a
//! stable state when some ball would leave its assigned end there: `−σ_i â_i·g_A ≥ sin φ` for the
//! unit axis `â_i` (world) and `φ` the ball's min-angle. Per assignment other than the wanted one,
//!
//! `smax_s(−σ_i â_i·g_A) − ln(n)/s − sin(φ + slack) ≥ 0`,
//!
//! the log-sum-exp maximum less its largest excess `ln(n)/s`, so that the constraint holding
//! implies the true maximum clears `sin(φ + slack)`.

use super::mass::{axis_cosine, ball_mass, material, CapsuleVars, Densities};
use super::scalar::{Scalar, V3};
use super::setup::{GoalSetup, PoseSetup};
use super::smooth::smooth_max;
use crate::balance::equilibria::flip_sets;

/// Capsules up to which every other assignment gets a constraint; with more, only those moving
/// one or two balls from the wanted state (the exact judge still tries every assignment).
pub(crate) const MAX_CONSTRAINED_BALLS: usize = 6;

/// Sharpness `s` of the smooth maximum over balls, per unit of `â·g`.
const SHARPNESS: f64 = 200.0;

/// Degrees added to the ball's min-angle: covers the ball's drop against its end cap (`r − b`,
/// left out of `c_A` here), the rounding of the solution, the step to the re-sliced material the
/// judge weighs and the print's departure from it (an unwanted state close to its anchor turns
/// by a fraction of a degree for each: `docs/optimizer.md`, "Uniqueness").
const SLACK_DEGREES: f64 = 2.0;

/// Whether `goal` asks for uniqueness, and about which point (world) the model then turns.
fn anchor(goal: &GoalSetup, setup: &PoseSetup) -> Option<nalgebra::Vector3<f64>> {
    match goal {
        GoalSetup::Suspend {
            point,
            unique: true,
            ..
        } => Some(*point),
        GoalSetup::Immerse { unique: true, .. } => Some(setup.buoyancy_centre.coords),
        _ => None,
    }
}

/// Per `unique` goal of `setup`, per assignment other than the wanted one (the wanted end of each
/// ball read from the sign of its axis cosine at `x`), the constraint of the module's formula.
/// Balls sit at their end points (the cap drop is in the slack); capsules of components without a
/// body are left out, as in the exact evaluation.
pub(crate) fn uniqueness_constraints<D: Scalar>(
    setup: &PoseSetup,
    capsules: &[CapsuleVars<D>],
    infill: &D,
    densities: Densities,
    min_angle: f64,
    out: &mut Vec<D>,
) {
    let anchors: Vec<_> = setup
        .goals
        .iter()
        .filter_map(|goal| anchor(goal, setup))
        .collect();
    if anchors.is_empty() {
        return;
    }
    let weighed: Vec<&CapsuleVars<D>> = capsules
        .iter()
        .filter(|c| c.component < setup.printed.len())
        .collect();
    let fixed = material(setup, capsules, infill, densities);
    let mut ends = Vec::with_capacity(weighed.len());
    let mut axes = Vec::with_capacity(weighed.len());
    let mut wanted = Vec::with_capacity(weighed.len());
    let mut masses = Vec::with_capacity(weighed.len());
    for capsule in &weighed {
        let frame = setup.frame(capsule.component);
        ends.push([capsule.p.transformed(&frame), capsule.q.transformed(&frame)]);
        let axis = capsule.q.sub(&capsule.p);
        let length = axis.norm();
        axes.push(if length.re() > 0.0 {
            axis.rotated(&frame).scale(&length.recip())
        } else {
            V3::constant(&nalgebra::Vector3::zeros())
        });
        let z = axis_cosine(capsule, &setup.gravity_in(capsule.component));
        wanted.push(z.re() >= 0.0);
        masses.push(ball_mass(&capsule.r, densities));
    }
    let threshold = (min_angle + SLACK_DEGREES).to_radians().sin()
        + (weighed.len().max(1) as f64).ln() / SHARPNESS;
    let sets = flip_sets(weighed.len(), MAX_CONSTRAINED_BALLS);
    for anchor in &anchors {
        for set in &sets[1..] {
            let mut at_to = wanted.clone();
            for &i in set {
                at_to[i] = !at_to[i];
            }
            let mut sums = fixed.clone();
            for ((end, mass), &to) in ends.iter().zip(&masses).zip(&at_to) {
                sums.add(mass, &end[usize::from(to)]);
            }
            let offset = sums.centre(setup).sub_constant(anchor);
            let length = (offset.norm_squared() + setup.epsilon * setup.epsilon).sqrt();
            let gravity = offset.scale(&length.recip());
            let leaving: Vec<D> = axes
                .iter()
                .zip(&at_to)
                .map(|(axis, &to)| {
                    let along = axis.dot(&gravity);
                    if to {
                        -along
                    } else {
                        along
                    }
                })
                .collect();
            out.push(smooth_max(&leaving, SHARPNESS) - threshold);
        }
    }
}
