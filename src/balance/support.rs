//! The support polygon of a posed model on horizontal ground and its toppling angles.

use nalgebra::{Point3, Vector2, Vector3};

use super::{Support, SupportEdge};
use crate::geometry::polygon::convex_hull;
use crate::spec::model::{Axis, Goal, Pose};

/// Toppling angle reported when nothing touches the ground: the model falls whichever way.
pub(crate) const NO_SUPPORT: f64 = -90.0;

/// The contact tolerance `pose` writes: that of its first `stand` or `imbalance` goal, if it gives
/// one (else the hull's, [`default_contact_tolerance`](super::rest::default_contact_tolerance)).
pub(crate) fn contact_tolerance(pose: &Pose) -> Option<f64> {
    pose.goals
        .iter()
        .find_map(|goal| match goal.value {
            Goal::Stand {
                contact_tolerance, ..
            }
            | Goal::Imbalance {
                contact_tolerance, ..
            } => Some(contact_tolerance),
            Goal::Suspend { .. } | Goal::Immerse { .. } => None,
        })
        .flatten()
}

/// How the model with world vertices `vertices` and centre of mass `centre` rests on the ground
/// under the lowest vertex, along `up`.
///
/// A vertex touches when at most `tolerance` (taken as 0 if negative) above the ground. The
/// toppling angle about an edge is `atan2(−d, h)` with `d` the signed distance of the centre's
/// projection from the edge line (positive outside) and `h` the centre's height above the
/// ground; see [`Support::edges`] for the pseudo-edges of a point or a segment.
pub(crate) fn support(
    vertices: &[Point3<f64>],
    up: Axis,
    tolerance: f64,
    centre: &Point3<f64>,
) -> Support {
    let plane = GroundPlane::new(up);
    let tolerance = tolerance.max(0.0);
    let Some(ground) = ground_height(vertices, &plane) else {
        return Support {
            ground_height: 0.0,
            contact_tolerance: tolerance,
            centre_height: plane.height(centre),
            contacts: Vec::new(),
            polygon: Vec::new(),
            edges: Vec::new(),
            fixed_ball_margin: NO_SUPPORT,
            tilt_margin: NO_SUPPORT,
            tilt_direction: None,
            ball_moves: Vec::new(),
        };
    };
    let (contacts, polygon) = footprint(vertices, &plane, ground, tolerance);
    let height = plane.height(centre) - ground;
    let foot = plane.project(centre);
    let lines = support_lines(&polygon);
    let edges: Vec<SupportEdge> = lines
        .iter()
        .map(|(start, end, line)| SupportEdge {
            start: plane.lift(start, ground).into(),
            end: plane.lift(end, ground).into(),
            distance: line.distance(&foot),
            // `+ 0.0` turns −0 into 0.
            toppling_angle: (-line.distance(&foot)).atan2(height).to_degrees() + 0.0,
        })
        .collect();
    let worst = (0..edges.len()).reduce(|best, i| {
        if edges[i].toppling_angle < edges[best].toppling_angle {
            i
        } else {
            best
        }
    });
    let tilt_margin = worst.map_or(NO_SUPPORT, |i| edges[i].toppling_angle);
    let tilt_direction = worst
        .and_then(|i| lines[i].2.outward(&foot))
        .map(|v| (plane.e1 * v.x + plane.e2 * v.y).into());
    Support {
        ground_height: ground,
        contact_tolerance: tolerance,
        centre_height: height,
        contacts: contacts.iter().map(|p| (*p).into()).collect(),
        polygon: polygon
            .iter()
            .map(|q| plane.lift(q, ground).into())
            .collect(),
        edges,
        fixed_ball_margin: tilt_margin,
        tilt_margin,
        tilt_direction,
        ball_moves: Vec::new(),
    }
}

/// The vertices within `tolerance` of the `ground` height (along `plane`'s up) and the convex
/// hull of their projections, counter-clockwise seen from above (see [`convex_hull`]).
pub(crate) fn footprint(
    vertices: &[Point3<f64>],
    plane: &GroundPlane,
    ground: f64,
    tolerance: f64,
) -> (Vec<Point3<f64>>, Vec<Vector2<f64>>) {
    let contacts: Vec<Point3<f64>> = vertices
        .iter()
        .filter(|p| plane.height(p) - ground <= tolerance)
        .copied()
        .collect();
    let projected: Vec<[f64; 2]> = contacts.iter().map(|p| plane.project(p).into()).collect();
    let polygon = convex_hull(&projected)
        .into_iter()
        .map(Vector2::from)
        .collect();
    (contacts, polygon)
}

/// The height of the ground under `vertices`: the lowest along `plane`'s up, or `None` when there
/// are no finite vertices.
pub(crate) fn ground_height(vertices: &[Point3<f64>], plane: &GroundPlane) -> Option<f64> {
    let ground = vertices
        .iter()
        .map(|p| plane.height(p))
        .fold(f64::INFINITY, f64::min);
    (ground != f64::INFINITY).then_some(ground)
}

/// How the signed distance of the centre's foot from one (pseudo-)edge depends on the foot `f`
/// (positive outside the support).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum SupportLine {
    /// `(f − origin)·normal`: a polygon edge (`normal` its outward unit normal) or a segment's end
    /// cap (`normal` along the segment, away from it).
    Linear {
        /// A point of the line.
        origin: Vector2<f64>,
        /// Unit normal, outward.
        normal: Vector2<f64>,
    },
    /// `|(f − origin)·normal|`: a side of a segment support, outside on both sides.
    Side {
        /// A point of the segment.
        origin: Vector2<f64>,
        /// Unit normal of the segment.
        normal: Vector2<f64>,
    },
    /// `|f − origin|`: a support that is a single point.
    Point {
        /// The point.
        origin: Vector2<f64>,
    },
}

impl SupportLine {
    /// The horizontal unit vector, plane coordinates, in which `foot` moving increases its
    /// distance; `None` for a point support's own origin.
    pub(crate) fn outward(&self, foot: &Vector2<f64>) -> Option<Vector2<f64>> {
        match self {
            SupportLine::Linear { normal, .. } => Some(*normal),
            SupportLine::Side { origin, normal } => Some(if (foot - origin).dot(normal) < 0.0 {
                -normal
            } else {
                *normal
            }),
            SupportLine::Point { origin } => (foot - origin).try_normalize(0.0),
        }
    }

    /// The signed distance of `foot`, positive outside.
    pub(crate) fn distance(&self, foot: &Vector2<f64>) -> f64 {
        match self {
            SupportLine::Linear { origin, normal } => (foot - origin).dot(normal),
            SupportLine::Side { origin, normal } => (foot - origin).dot(normal).abs(),
            SupportLine::Point { origin } => (foot - origin).norm(),
        }
    }
}

/// The (pseudo-)edges of a convex `polygon` (counter-clockwise, as from [`convex_hull`]), each as
/// its start, end and distance function; see [`Support::edges`].
pub(crate) fn support_lines(
    polygon: &[Vector2<f64>],
) -> Vec<(Vector2<f64>, Vector2<f64>, SupportLine)> {
    match polygon {
        [] => Vec::new(),
        [p] => vec![(*p, *p, SupportLine::Point { origin: *p })],
        [a, b] => {
            let along = (b - a) / (b - a).norm();
            let normal = Vector2::new(along.y, -along.x);
            let side = SupportLine::Side { origin: *a, normal };
            vec![
                (*a, *b, side),
                (*b, *a, side),
                (
                    *a,
                    *a,
                    SupportLine::Linear {
                        origin: *a,
                        normal: -along,
                    },
                ),
                (
                    *b,
                    *b,
                    SupportLine::Linear {
                        origin: *b,
                        normal: along,
                    },
                ),
            ]
        }
        _ => (0..polygon.len())
            .map(|i| {
                let a = polygon[i];
                let b = polygon[(i + 1) % polygon.len()];
                let edge = b - a;
                // Right of a counter-clockwise edge is outside.
                let normal = Vector2::new(edge.y, -edge.x) / edge.norm();
                (a, b, SupportLine::Linear { origin: a, normal })
            })
            .collect(),
    }
}

/// The ground's frame: two horizontal axes `e1`, `e2` with `e1 × e2 = up`, so counter-clockwise
/// in (e1, e2) is counter-clockwise seen from above.
pub(crate) struct GroundPlane {
    pub(crate) e1: Vector3<f64>,
    pub(crate) e2: Vector3<f64>,
    pub(crate) up: Vector3<f64>,
}

impl GroundPlane {
    pub(crate) fn new(up: Axis) -> GroundPlane {
        let (e1, e2) = match up {
            Axis::X => (Vector3::y(), Vector3::z()),
            Axis::Y => (Vector3::z(), Vector3::x()),
            Axis::Z => (Vector3::x(), Vector3::y()),
        };
        GroundPlane {
            e1,
            e2,
            up: up.unit_vector(),
        }
    }

    /// Height of `p` along up.
    pub(crate) fn height(&self, p: &Point3<f64>) -> f64 {
        self.up.dot(&p.coords)
    }

    /// Coordinates of `p` seen from above.
    pub(crate) fn project(&self, p: &Point3<f64>) -> Vector2<f64> {
        Vector2::new(self.e1.dot(&p.coords), self.e2.dot(&p.coords))
    }

    /// The point at plane coordinates `q` and `height`.
    pub(crate) fn lift(&self, q: &Vector2<f64>, height: f64) -> Point3<f64> {
        Point3::from(self.e1 * q.x + self.e2 * q.y + self.up * height)
    }
}
