//! Each goal's smooth objective (paper eq. 1, 2 and 4), in radians: at most 0 when the goal is
//! met, larger the further it is from met.

use nalgebra::Vector3;

use super::mass::SmoothTotals;
use super::scalar::{Scalar, V3};
use super::setup::{Footing, GoalSetup, PoseSetup};
use super::smooth::{angle_to, atan2, smooth_min, soft_abs};
use crate::balance::support::{SupportLine, NO_SUPPORT};

/// The objective of `goal` in the pose of `setup`, for a design whose totals are `totals`.
///
/// - stand (eq. 1): `margin − smin_β(θᵢ)`, the toppling angles `θᵢ = atan2(−dᵢ, h)` of the
///   pose's fixed support polygon (signed distance `dᵢ` of the centre's foot from edge `i`,
///   positive outside, and the centre's height `h` above the ground; the paper's `θᵢ` with the
///   sign flipped so positive is stable), smooth-minimised with sharpness `edge_sharpness`;
/// - imbalance: its negation, `smin_β(θᵢ) + margin`;
/// - suspend (eq. 2): the angle between `c − s` and gravity, less the tolerance;
/// - immerse (eq. 4): the angle between `c_buo − c` and up, less the tolerance.
pub(crate) fn goal_objective<D: Scalar>(
    goal: &GoalSetup,
    setup: &PoseSetup,
    totals: &SmoothTotals<D>,
    edge_sharpness: f64,
) -> D {
    match goal {
        GoalSetup::Stand { margin } => {
            -smooth_tilt(setup, &totals.centre, edge_sharpness) + *margin
        }
        GoalSetup::Imbalance { margin } => {
            smooth_tilt(setup, &totals.centre, edge_sharpness) + *margin
        }
        GoalSetup::Suspend {
            point, tolerance, ..
        } => {
            let string = totals.centre.sub_constant(point);
            angle_to(&string, &-setup.up, setup.epsilon) - *tolerance
        }
        GoalSetup::Immerse { tolerance, .. } => {
            let offset = V3::constant(&setup.buoyancy_centre.coords).sub(&totals.centre);
            angle_to(&offset, &setup.up, setup.epsilon) - *tolerance
        }
    }
}

/// The smooth tilt margin of the pose's support for the centre of mass `centre`, radians:
/// `smin_β(θᵢ)`; −π/2 without a support, as the exact evaluation reports.
pub(crate) fn smooth_tilt<D: Scalar>(setup: &PoseSetup, centre: &V3<D>, sharpness: f64) -> D {
    let Some(footing) = &setup.support else {
        return D::from(NO_SUPPORT.to_radians());
    };
    let angles = toppling_angles(footing, centre, &setup.up, setup.epsilon);
    if angles.is_empty() {
        return D::from(NO_SUPPORT.to_radians());
    }
    smooth_min(&angles, sharpness)
}

/// `atan2(−dᵢ, h)` for every (pseudo-)edge of `footing`, radians. The distances from a point or
/// a segment's side are rounded off over `epsilon` (`√(t² + ε²)` for `|t|`).
fn toppling_angles<D: Scalar>(
    footing: &Footing,
    centre: &V3<D>,
    up: &Vector3<f64>,
    epsilon: f64,
) -> Vec<D> {
    let height = centre.dot_constant(up) - footing.ground;
    let fx = centre.dot_constant(&footing.e1);
    let fy = centre.dot_constant(&footing.e2);
    footing
        .lines
        .iter()
        .map(|line| {
            let distance = match line {
                SupportLine::Linear { origin, normal } => {
                    (fx.clone() - origin.x) * normal.x + (fy.clone() - origin.y) * normal.y
                }
                SupportLine::Side { origin, normal } => soft_abs(
                    (fx.clone() - origin.x) * normal.x + (fy.clone() - origin.y) * normal.y,
                    epsilon,
                ),
                SupportLine::Point { origin } => {
                    let dx = fx.clone() - origin.x;
                    let dy = fy.clone() - origin.y;
                    (dx.clone() * dx + dy.clone() * dy + epsilon * epsilon).sqrt()
                }
            };
            atan2(-distance, height.clone())
        })
        .collect()
}
