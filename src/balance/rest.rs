//! Where a posed model comes to rest: the facet of its convex hull it lies on.
//!
//! A rigid print on flat ground lies on a facet of its convex hull. When the written rotation
//! puts a facet on the ground (three or more hull vertices, not in a line, within the hull's
//! coplanarity tolerance of the lowest), that is the facet, stable or not: the goals judge it.
//! Otherwise the model touches at a vertex or along an edge and rolls, quasi-statically, driven by
//! its centre of mass: about the contact point (or edge) nearest the centre's foot, in the
//! direction that lowers the centre, until another hull vertex touches; again until a facet is
//! down; and, for a `stand` pose, on over the edge the foot lies beyond until the foot lies inside
//! the facet. An `imbalance` pose stops on the first facet down, the one it lands on before it
//! falls.
//!
//! The rolling only decides the facet. The correction is the shortest rotation taking that
//! facet's outward normal (in the written pose) exactly to `−up`, about its lowest corner, the
//! same rotation `down` computes: what happens on the ground depends only on which way gravity
//! points in the model, not on a turn about the vertical that a real roll may add. The evaluation
//! applies it to the pose's transform, so every component frame, ball and centre is computed in
//! the settled pose, and its angle is how far the written rotation was off.

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector2, Vector3};
use serde::Serialize;

use super::facets::facet_rotation;
use super::support::{support_lines, GroundPlane};
use super::ComponentBody;
use crate::geometry::polygon::convex_hull as convex_hull_2d;
use crate::geometry::{ConvexHull, HullFacet, COPLANAR};
use crate::spec::model::{Axis, Goal, Pose, Project};

/// Settling that turns a pose by more than this, degrees, deserves a warning: the written rotation
/// does not put a facet on the ground.
pub const SNAP_WARNING: f64 = 0.05;

/// The facet a pose rests on and how far the written rotation was from it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Resting {
    /// Angle of the correction from the written rotation to the settled one, degrees.
    pub correction: f64,
    /// The facet's outward normal in the pose's model frame (components placed by the pose, the
    /// pose's own transform not applied): the direction `down` names to choose this facet.
    pub down: [f64; 3],
    /// The facet's area, square project units.
    pub area: f64,
    /// The number of the facet's corners.
    pub corners: usize,
}

/// A pose after settling on its hull.
#[derive(Debug, Clone)]
pub(crate) struct Settled {
    /// The pose with the correction applied to its transform (the written pose when it does not
    /// settle).
    pub pose: Pose,
    /// The facet it rests on; `None` for a pose without a `stand` or `imbalance` goal, a model
    /// without volume, or one balanced exactly on an edge or a vertex.
    pub resting: Option<Resting>,
}

/// How far a pose rolls.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Rule {
    /// On to a facet the centre's foot is inside (a `stand` pose).
    Stable,
    /// To the first facet down (an `imbalance` pose).
    FirstFacet,
    /// From a facet already down, on to one the centre's foot is inside, giving up once the
    /// model has turned more than [`ROCKING_DEGREES`]: whether an `imbalance` pose on a slope
    /// only rocks.
    Rocking,
}

/// How far a model may rock, degrees, and not count as toppled: an `imbalance` pose that comes to
/// rest on a hull facet within this turn of where it was set down has not toppled.
pub const ROCKING_DEGREES: f64 = 3.0;

/// The rule of `pose`: from its first `stand` or `imbalance` goal; `None` when it has neither.
pub(crate) fn rule(pose: &Pose) -> Option<Rule> {
    pose.goals.iter().find_map(|goal| match goal.value {
        Goal::Stand { .. } => Some(Rule::Stable),
        Goal::Imbalance { .. } => Some(Rule::FirstFacet),
        Goal::Suspend { .. } | Goal::Immerse { .. } => None,
    })
}

/// The contact tolerance of a model with world vertices `vertices` when its goal names none:
/// the hull's coplanarity tolerance, [`COPLANAR`] times their extent.
pub(crate) fn default_contact_tolerance(vertices: &[Point3<f64>]) -> f64 {
    COPLANAR * super::evaluate::extent(vertices)
}

/// `pose` of the model made of `bodies`, settled onto its hull with the centre of mass `centre`
/// (world, written pose); see the module documentation.
pub(crate) fn settle_pose(
    project: &Project,
    bodies: &[ComponentBody],
    pose: &Pose,
    centre: &Point3<f64>,
) -> Settled {
    let unsettled = || Settled {
        pose: pose.clone(),
        resting: None,
    };
    let Some(rule) = rule(pose) else {
        return unsettled();
    };
    let Some((vertices, hull)) = super::evaluate::posed_vertices_and_hull(bodies, pose) else {
        return unsettled();
    };
    let gravity = -project.up.unit_vector();
    let Some(facet) = roll(&hull, &vertices, project.up, centre, &gravity, rule) else {
        return unsettled();
    };
    let facet = &hull.facets[facet];
    let correction = correction(facet, &vertices, project.up);
    let down = pose.transform.rotation.inverse() * facet.normal;
    let mut settled = pose.clone();
    settled.transform = correction * pose.transform;
    Settled {
        pose: settled,
        resting: Some(Resting {
            correction: correction.rotation.angle().to_degrees(),
            down: down.into(),
            area: facet.area,
            corners: facet.corners.len(),
        }),
    }
}

/// The centre of the solid model (uniform density, no capsules) in `pose`, world: the
/// volume-weighted mean of the components' centroids, or their plain mean when the volumes cancel
/// (the origin without bodies).
pub(crate) fn solid_centre(bodies: &[ComponentBody], pose: &Pose) -> Point3<f64> {
    let placed: Vec<(f64, Point3<f64>)> = bodies
        .iter()
        .enumerate()
        .map(|(i, body)| {
            (
                body.mass.volume,
                pose.component_frame(i) * body.mass.centroid,
            )
        })
        .collect();
    let volume: f64 = placed.iter().map(|(v, _)| v).sum();
    let magnitude: f64 = placed.iter().map(|(v, _)| v.abs()).sum();
    if volume != 0.0 && volume.abs() > 1e-12 * magnitude {
        Point3::from(
            placed
                .iter()
                .map(|(v, c)| c.coords * *v)
                .sum::<Vector3<f64>>()
                / volume,
        )
    } else if placed.is_empty() {
        Point3::origin()
    } else {
        Point3::from(
            placed.iter().map(|(_, c)| c.coords).sum::<Vector3<f64>>() / placed.len() as f64,
        )
    }
}

/// Rolls the hull of `points` (world) with centre of mass `centre` on the ground below it, as
/// `rule` says, with gravity along the unit vector `gravity` (straight down, `−up`, on level
/// ground; tilted when the ground stands for a slope); the index of the facet it comes to rest
/// on. `None` when the centre is balanced exactly over an edge or a vertex (no way to roll), no
/// facet is reached within a step per facet, or, for [`Rule::Rocking`], the model turns more
/// than [`ROCKING_DEGREES`].
pub(crate) fn roll(
    hull: &ConvexHull,
    points: &[Point3<f64>],
    up: Axis,
    centre: &Point3<f64>,
    gravity: &Vector3<f64>,
    rule: Rule,
) -> Option<usize> {
    let plane = GroundPlane::new(up);
    let tolerance = hull.tolerance;
    let mut moved = Isometry3::identity();
    for step in 0..hull.facets.len() + 4 {
        let corners: Vec<Point3<f64>> = hull.vertices.iter().map(|&i| moved * points[i]).collect();
        let ground = corners
            .iter()
            .map(|p| plane.height(p))
            .fold(f64::INFINITY, f64::min);
        let contacts: Vec<[f64; 2]> = corners
            .iter()
            .filter(|p| plane.height(p) - ground <= tolerance)
            .map(|p| plane.project(p).into())
            .collect();
        let polygon: Vec<Vector2<f64>> = convex_hull_2d(&contacts)
            .into_iter()
            .map(Vector2::from)
            .collect();
        // Where the line through the centre along gravity meets the ground.
        let lifted = moved * centre;
        let fall = (plane.height(&lifted) - ground) / -gravity.dot(&plane.up);
        let foot = plane.project(&(lifted + gravity * fall));
        let lines = support_lines(&polygon);
        let inside = lines.iter().all(|(_, _, line)| line.distance(&foot) <= 0.0);
        let done = match rule {
            Rule::Stable => step == 0 || inside,
            Rule::FirstFacet => true,
            Rule::Rocking => inside,
        };
        if rule == Rule::Rocking && moved.rotation.angle() > ROCKING_DEGREES.to_radians() {
            return None;
        }
        if polygon.len() >= 3 && done {
            return facing_down(hull, &moved, &plane);
        }
        let pivot = nearest_on_boundary(&polygon, &foot)?;
        let offset = foot - pivot;
        if offset.norm() <= 1e-3 * tolerance {
            return None;
        }
        let offset = offset.normalize();
        let toward = plane.e1 * offset.x + plane.e2 * offset.y;
        let origin = plane.lift(&pivot, ground);
        // Turning by θ about `up × toward` lowers a point `x` along `toward` and `y` above the
        // ground to height y cos θ − x sin θ: it touches at θ = atan2(y, x).
        let angle = corners
            .iter()
            .filter_map(|p| {
                let x = toward.dot(&(p - origin));
                (x > tolerance).then(|| (plane.height(p) - ground).atan2(x))
            })
            .reduce(f64::min)?;
        let axis = Unit::new_normalize(plane.up.cross(&toward));
        moved = about(&origin, UnitQuaternion::from_axis_angle(&axis, angle)) * moved;
    }
    None
}

/// The index of the facet of `hull` that `moved` turns most nearly to face `−up` (`None` for a
/// hull without facets).
fn facing_down(hull: &ConvexHull, moved: &Isometry3<f64>, plane: &GroundPlane) -> Option<usize> {
    let down = -plane.up;
    hull.facets
        .iter()
        .map(|facet| (moved.rotation * facet.normal).dot(&down))
        .enumerate()
        .max_by(|(_, a), (_, b)| a.total_cmp(b))
        .map(|(index, _)| index)
}

/// The correction that puts `facet` of the hull of `points` (world) flat on the ground: the
/// shortest rotation taking its outward normal to `−up`, about its lowest corner.
fn correction(facet: &HullFacet, points: &[Point3<f64>], up: Axis) -> Isometry3<f64> {
    let plane = GroundPlane::new(up);
    let lowest = facet
        .corners
        .iter()
        .map(|&i| points[i])
        .min_by(|a, b| plane.height(a).total_cmp(&plane.height(b)))
        .unwrap_or_else(Point3::origin);
    about(&lowest, facet_rotation(&facet.normal, up))
}

/// The rotation `turn` about the point `origin`.
fn about(origin: &Point3<f64>, turn: UnitQuaternion<f64>) -> Isometry3<f64> {
    let shift = origin.coords - turn * origin.coords;
    Isometry3::from_parts(Translation3::from(shift), turn)
}

/// The point of the support `polygon` (a point, a segment or a convex polygon, as from
/// [`convex_hull_2d`]) nearest `foot`, on its boundary; `None` for an empty polygon.
fn nearest_on_boundary(polygon: &[Vector2<f64>], foot: &Vector2<f64>) -> Option<Vector2<f64>> {
    let segment = |a: &Vector2<f64>, b: &Vector2<f64>| {
        let along = b - a;
        let t = if along.norm_squared() > 0.0 {
            ((foot - a).dot(&along) / along.norm_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        a + along * t
    };
    let n = polygon.len();
    let edges = if n <= 2 { n.min(1) } else { n };
    (0..edges)
        .map(|k| segment(&polygon[k], &polygon[(k + 1) % n]))
        .min_by(|p, q| (p - foot).norm().total_cmp(&(q - foot).norm()))
}
