//! Where a capsule's ball rests in a pose (paper eq. 19-20, without the smoothing of eq. 21).

use nalgebra::{Isometry3, Point3, Vector3};

use super::{BallPlacement, BallRest};
use crate::design::PlacedCapsule;
use crate::spec::model::Ball;

/// Places the ball of `capsule`, whose component has the rest-frame-to-world transform `frame`,
/// under gravity `−up` (`up` a unit vector).
///
/// In the component frame gravity is `g = R⁻¹(−up)`. When the axis `â` rises at least
/// `ball.min_angle` above horizontal (`asin |â·g|`), the ball rolls to the lower end `e` and rests
/// against the bottom of that end's spherical cap: centre `e + (r − b) g` for capsule radius `r`
/// and ball radius `b` (`r − b` taken as 0 if negative). Otherwise it is on the axis midpoint. A
/// zero-length axis is a spherical cavity: the ball rests at its bottom, reported as
/// [`BallRest::From`] with elevation 90.
///
/// The mass is `ball.density` (g/cm³) × ball volume × `cubic_in_cm3` (cm³ per cubic unit).
pub(crate) fn place_ball(
    capsule: &PlacedCapsule,
    frame: &Isometry3<f64>,
    up: &Vector3<f64>,
    ball: &Ball,
    cubic_in_cm3: f64,
) -> BallPlacement {
    let gravity = frame.rotation.inverse() * -up;
    let drop = (capsule.radius - capsule.ball_radius).max(0.0);
    let (rest, elevation, centre) = match (capsule.to - capsule.from).try_normalize(0.0) {
        None => (BallRest::From, 90.0, capsule.from + gravity * drop),
        Some(axis) => {
            let along = axis.dot(&gravity);
            let elevation = along.abs().min(1.0).asin().to_degrees();
            if elevation < ball.min_angle || along == 0.0 {
                let middle = nalgebra::center(&capsule.from, &capsule.to);
                (BallRest::Undetermined, elevation, middle)
            } else if along > 0.0 {
                (BallRest::To, elevation, capsule.to + gravity * drop)
            } else {
                (BallRest::From, elevation, capsule.from + gravity * drop)
            }
        }
    };
    let centre_world: Point3<f64> = frame * centre;
    BallPlacement {
        capsule: capsule.name.clone(),
        component: capsule.component,
        rest,
        elevation,
        centre: centre.into(),
        centre_world: centre_world.into(),
        mass: ball.density * capsule.ball_volume() * cubic_in_cm3,
    }
}
