//! Each goal of a pose measured against what it requires (paper eq. 1-5, unsmoothed), with the
//! stable states of hanging and floating goals.

use nalgebra::Vector3;

use super::equilibria::Model;
use super::mass::MassTotals;
use super::{GoalEvaluation, GoalOutcome};
use crate::spec::model::{Goal, Pose};

/// Angle reported when a direction is undefined because two points coincide: neither towards nor
/// away from gravity.
const NEUTRAL: f64 = 90.0;

/// What the goals of one pose are measured against.
pub(crate) struct Measured<'a> {
    /// The pose, for the frame of a suspension point's component.
    pub pose: &'a Pose,
    /// Unit up vector, world.
    pub up: Vector3<f64>,
    /// Mass, volume and the two centres.
    pub totals: &'a MassTotals,
    /// The support's tilt margin, degrees.
    pub tilt_margin: f64,
    /// Two points closer than this coincide (project units).
    pub coincidence: f64,
    /// cm³ per cubic project unit.
    pub cubic_in_cm3: f64,
    /// The model turning freely, for the stable states of hanging and floating goals.
    pub model: &'a Model<'a>,
}

/// The outcome of `goal` in the measured pose.
pub(crate) fn evaluate_goal(goal: &Goal, measured: &Measured) -> GoalEvaluation {
    let centre = measured.totals.centre_of_mass;
    match *goal {
        Goal::Stand { margin, .. } => {
            let tilt_margin = measured.tilt_margin;
            GoalEvaluation {
                met: tilt_margin > 0.0 && tilt_margin >= margin,
                outcome: GoalOutcome::Stand {
                    tilt_margin,
                    margin,
                },
            }
        }
        Goal::Imbalance { margin, .. } => {
            let tilt_margin = measured.tilt_margin;
            GoalEvaluation {
                met: tilt_margin < 0.0 && tilt_margin < -margin,
                outcome: GoalOutcome::Imbalance {
                    tilt_margin,
                    margin,
                },
            }
        }
        Goal::Suspend {
            point,
            component,
            tolerance,
            unique,
        } => {
            let point = measured.pose.component_frame(component) * point;
            let angle = angle_to(&(centre - point), &-measured.up, measured.coincidence);
            let equilibria = measured.model.states(&point);
            let alone = !unique || equilibria.unwanted().next().is_none();
            GoalEvaluation {
                met: angle <= tolerance && alone,
                outcome: GoalOutcome::Suspend {
                    angle,
                    tolerance,
                    point: point.into(),
                    unique,
                    equilibria,
                },
            }
        }
        Goal::Immerse {
            fluid_density,
            min_distance,
            tolerance,
            mass_tolerance,
            unique,
        } => {
            let buoyancy = measured.totals.buoyancy_centre;
            let offset = buoyancy - centre;
            let angle = angle_to(&offset, &measured.up, measured.coincidence);
            let distance = offset.norm();
            let displaced_mass = fluid_density * measured.totals.volume * measured.cubic_in_cm3;
            let mass_residual = measured.totals.mass - displaced_mass;
            let mass_ok = mass_tolerance.is_none_or(|allowed| mass_residual.abs() <= allowed);
            let equilibria = measured.model.states(&buoyancy);
            let alone = !unique || equilibria.unwanted().next().is_none();
            GoalEvaluation {
                met: angle <= tolerance && distance >= min_distance && mass_ok && alone,
                outcome: GoalOutcome::Immerse {
                    angle,
                    tolerance,
                    distance,
                    min_distance,
                    buoyancy_centre: buoyancy.into(),
                    displaced_mass,
                    mass_residual,
                    mass_tolerance,
                    unique,
                    equilibria,
                },
            }
        }
    }
}

/// Angle between `v` and the unit vector `direction`, degrees in [0, 180]; [`NEUTRAL`] when `v`
/// is no longer than `coincidence`.
fn angle_to(v: &Vector3<f64>, direction: &Vector3<f64>, coincidence: f64) -> f64 {
    let length = v.norm();
    if length <= coincidence || length == 0.0 || !length.is_finite() {
        return NEUTRAL;
    }
    (v.dot(direction) / length)
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}
