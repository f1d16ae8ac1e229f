//! Whether a model that must topple only rocks. Set down on a slope on the facet its pose rests
//! on, an `imbalance` pose may roll over that facet's edge onto a neighbouring facet a degree
//! away and stand there, as a rounded back does. Rocking that little is no toppling, so the tilt
//! margin of an `imbalance` pose is minus the gentlest slope on which it comes to rest within
//! [`ROCKING_DEGREES`] of where it was set down (docs/physics.md, "Rocking is not toppling").

use nalgebra::{Point3, Unit, UnitQuaternion, Vector3};

use super::rest::{roll, Rule, ROCKING_DEGREES};
use super::support::GroundPlane;
use super::{ball, mass, ComponentBody};
use crate::design::Design;
use crate::spec::model::{Pose, Project};

/// Downhill directions tried, evenly spaced about up from the first.
const DIRECTIONS: usize = 24;
/// Slopes tried in each direction, this many degrees apart, before bisecting.
const STEP: f64 = 0.5;
/// Bisections between the last slope it rolled away on and the first it stood on.
const HALVINGS: usize = 6;

/// The gentlest slope, degrees, with its downhill direction (a horizontal unit vector, world),
/// on which `pose` of the model made of `bodies` (its vertices posed, `vertices`), settled on a
/// facet of its hull and set down
/// on the slope with every ball at the end the slope's gravity sends it to, comes to rest
/// within [`ROCKING_DEGREES`] of where it was set down. Directions are tried from `first`
/// around, slopes below `limit` (the one that brings the centre of mass over the facet's own
/// edge); 0 when it stands rocked on level ground; `None` when it rolls further on every slope
/// tried, or the hull has no other facet within the rocking turn.
pub(crate) fn gentlest_rocking_slope(
    project: &Project,
    bodies: &[ComponentBody],
    design: &Design,
    pose: &Pose,
    vertices: &[Point3<f64>],
    limit: f64,
    first: &Vector3<f64>,
) -> Option<(f64, Vector3<f64>)> {
    let hull = super::evaluate::posed_hull(bodies, pose, vertices)?;
    let plane = GroundPlane::new(project.up);
    let down = -plane.up;
    let within = ROCKING_DEGREES.to_radians().cos();
    let near = hull.facets.iter().filter(|f| f.normal.dot(&down) >= within);
    if near.count() < 2 {
        return None;
    }
    let cubic = project.units.cubic_in_cm3();
    let stands = |direction: &Vector3<f64>, slope: f64| {
        let (sin, cos) = slope.to_radians().sin_cos();
        let gravity = down * cos + direction * sin;
        let balls: Vec<_> = design
            .capsules
            .iter()
            .map(|capsule| {
                let frame = pose.component_frame(capsule.component);
                ball::place_ball(capsule, &frame, &-gravity, &project.ball, cubic)
            })
            .collect();
        let centre = mass::mass_totals(project, bodies, design, pose, &balls).centre_of_mass;
        roll(
            &hull,
            vertices,
            project.up,
            &centre,
            &gravity,
            Rule::Rocking,
        )
        .is_some_and(|facet| hull.facets[facet].normal.dot(&down) >= within)
    };
    if stands(first, 0.0) {
        // It rocks onto a neighbour and stands there on level ground.
        return Some((0.0, *first));
    }
    let axis = Unit::new_unchecked(plane.up);
    let mut best: Option<(f64, Vector3<f64>)> = None;
    for k in 0..DIRECTIONS {
        let turn = UnitQuaternion::from_axis_angle(
            &axis,
            std::f64::consts::TAU * k as f64 / DIRECTIONS as f64,
        );
        let direction = turn * first;
        let below = best.map_or(limit, |(slope, _)| slope);
        let mut rolled = 0.0;
        let mut slope = STEP;
        while slope < below {
            if stands(&direction, slope) {
                let mut stood = slope;
                for _ in 0..HALVINGS {
                    let middle = 0.5 * (rolled + stood);
                    if stands(&direction, middle) {
                        stood = middle;
                    } else {
                        rolled = middle;
                    }
                }
                best = Some((stood, direction));
                break;
            }
            rolled = slope;
            slope += STEP;
        }
    }
    best
}
