//! The facets of a model's convex hull it can rest on, and the rotation that puts one on the
//! ground.

use nalgebra::{Isometry3, Point3, Unit, UnitQuaternion, Vector3};
use serde::Serialize;

use super::rest::solid_centre;
use super::{evaluate_pose, ComponentBody};
use crate::design::Design;
use crate::geometry::{ConvexHull, HullFacet};
use crate::spec::model::{Axis, Goal, Pose, Project, Spanned};

/// One facet of the hull and how the model rests on it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RestingFacet {
    /// The facet's outward unit normal, model frame.
    pub normal: [f64; 3],
    /// A `down` direction that picks this facet: the normal when the solid model rests on the
    /// facet stably (the ray from its centre along the normal then meets the facet), else the
    /// unit direction from the solid centre to the mean of the facet's corners.
    pub down: [f64; 3],
    /// Its area, square project units.
    pub area: f64,
    /// The number of its corners.
    pub corners: usize,
    /// The solid model's tilt margin on it, degrees: `atan` of the distance from the foot of its
    /// centre of mass to the facet's nearest edge over the centre's height above the facet.
    /// Positive: it rests there stably.
    pub solid_margin: f64,
    /// With the design's capsules and balls, the stand margin `evaluate_pose` reports on this
    /// facet, degrees, when a design is given and the model stays on the facet; `None` otherwise.
    pub design_margin: Option<f64>,
}

/// The model as `pose` places its components, before the pose's own transform: the frame `down`
/// is written in.
pub(crate) fn model_frame(pose: &Pose) -> Pose {
    Pose {
        transform: Isometry3::identity(),
        ..pose.clone()
    }
}

/// The facet the ray from `centre` along `direction` leaves `hull` through: the smallest
/// positive crossing among the facets facing along it. `None` for a zero direction.
pub(crate) fn facet_along(
    hull: &ConvexHull,
    centre: &Point3<f64>,
    direction: &Vector3<f64>,
) -> Option<usize> {
    let direction = direction.try_normalize(0.0)?;
    hull.facets
        .iter()
        .enumerate()
        .filter_map(|(i, facet)| {
            let facing = facet.normal.dot(&direction);
            (facing > 0.0).then(|| {
                (
                    i,
                    (facet.offset - facet.normal.dot(&centre.coords)) / facing,
                )
            })
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
}

/// The tilt margin of a rigid model with centre of mass `centre` resting on `facet` of the hull of
/// `points`, degrees: `atan2(d, h)` with `d` the distance from the centre's foot to the nearest
/// edge line (negative outside the facet) and `h` the centre's height above the facet.
pub(crate) fn facet_margin(facet: &HullFacet, points: &[Point3<f64>], centre: &Point3<f64>) -> f64 {
    let height = facet.offset - facet.normal.dot(&centre.coords);
    let n = facet.corners.len();
    let inside = (0..n)
        .map(|k| {
            let a = points[facet.corners[k]];
            let b = points[facet.corners[(k + 1) % n]];
            let edge = (b - a).normalize();
            // Counter-clockwise seen from outside: inward is normal × edge.
            facet.normal.cross(&edge).dot(&(centre - a))
        })
        .fold(f64::INFINITY, f64::min);
    inside.atan2(height).to_degrees() + 0.0
}

/// The shortest rotation taking `normal` to `−up`; when `normal` points straight up, the half
/// turn about the ground's first horizontal axis (y for up x, z for up y, x for up z).
pub fn facet_rotation(normal: &Vector3<f64>, up: Axis) -> UnitQuaternion<f64> {
    let down = -up.unit_vector();
    UnitQuaternion::rotation_between(normal, &down).unwrap_or_else(|| {
        let first = match up {
            Axis::X => Vector3::y_axis(),
            Axis::Y => Vector3::z_axis(),
            Axis::Z => Vector3::x_axis(),
        };
        UnitQuaternion::from_axis_angle(
            &Unit::new_unchecked(first.into_inner()),
            std::f64::consts::PI,
        )
    })
}

/// Every facet of the hull of the model as `pose` places its components (see `model_frame`),
/// with the solid model's margin on it (`bodies` before capsules are cut) and, given a `design`
/// with its bodies (the design's voids cut, [`PartPrints::bodies`](super::PartPrints::bodies)),
/// the design's; most stable first
/// (by the design's margin when there is one, then the solid's). `None` when the model has no
/// volume.
pub fn resting_facets(
    project: &Project,
    bodies: &[ComponentBody],
    pose: &Pose,
    design: Option<(&Design, &[ComponentBody])>,
) -> Option<Vec<RestingFacet>> {
    let frame = model_frame(pose);
    let (points, hull) = super::evaluate::posed_vertices_and_hull(bodies, &frame)?;
    let centre = solid_centre(bodies, &frame);
    let mut facets: Vec<RestingFacet> = hull
        .facets
        .iter()
        .map(|facet| {
            let solid_margin = facet_margin(facet, &points, &centre);
            let down = if solid_margin > 0.0 {
                facet.normal
            } else {
                let corners = facet.corners.iter().map(|&i| points[i].coords);
                let mean = corners.sum::<Vector3<f64>>() / facet.corners.len() as f64;
                (mean - centre.coords)
                    .try_normalize(0.0)
                    .unwrap_or(facet.normal)
            };
            RestingFacet {
                normal: facet.normal.into(),
                down: down.into(),
                area: facet.area,
                corners: facet.corners.len(),
                solid_margin,
                design_margin: design
                    .and_then(|(design, cut)| design_margin(project, cut, &frame, design, facet)),
            }
        })
        .collect();
    let key = |f: &RestingFacet| (f.design_margin.unwrap_or(f64::NEG_INFINITY), f.solid_margin);
    facets.sort_by(|a, b| {
        let (ka, kb) = (key(a), key(b));
        kb.0.total_cmp(&ka.0).then(kb.1.total_cmp(&ka.1))
    });
    Some(facets)
}

/// The stand margin of `design` with `facet` of the model in `frame` put on the ground; `None`
/// when the model does not stay on that facet (it rolls to another).
fn design_margin(
    project: &Project,
    bodies: &[ComponentBody],
    frame: &Pose,
    design: &Design,
    facet: &HullFacet,
) -> Option<f64> {
    let pose = Pose {
        transform: Isometry3::from_parts(
            Default::default(),
            facet_rotation(&facet.normal, project.up),
        ),
        goals: vec![Spanned::new(
            Goal::Stand {
                margin: 0.0,
                contact_tolerance: None,
            },
            frame.span,
        )],
        ..frame.clone()
    };
    let evaluation = evaluate_pose(project, bodies, design, &pose);
    let stays = evaluation
        .resting
        .as_ref()
        .is_some_and(|resting| resting.correction < super::rest::SNAP_WARNING);
    stays.then_some(evaluation.support.tilt_margin)
}
