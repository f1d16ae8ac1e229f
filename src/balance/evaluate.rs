//! One pose evaluated: the per-stage results wired together.

use nalgebra::{Point3, Vector3};

use super::support::GroundPlane;
use super::tilt::{RollingBall, TiltedModel};
use super::{ball, equilibria, goals, mass, rest, rocking, support, BallMove, BallPlacement};
use super::{mass::MassTotals, ComponentBody, PoseEvaluation, Support};
use crate::design::Design;
use crate::geometry::{convex_hull_among, ConvexHull};
use crate::spec::model::{Pose, Project};

/// What `design` does in `pose`: mass and centre of mass, where each ball rests, the support on
/// the ground with its toppling angles, and the outcome of each of the pose's goals (with every
/// stable state of a hanging or floating goal).
///
/// A pose with a `stand` or `imbalance` goal is first settled onto its hull
/// (`rest`) with the design's centre of mass in the written pose, and everything is
/// evaluated in the settled pose; [`PoseEvaluation::resting`] says which facet and how far the
/// written rotation was from it. An `imbalance` pose must topple: its tilt margin is that of a
/// model that may rock onto a neighbouring facet within
/// [`ROCKING_DEGREES`](super::ROCKING_DEGREES) and stand there (docs/physics.md, "Rocking is not toppling").
///
/// `bodies` is indexed like [`Project::components`]. Component `i` is placed in world by
/// `pose.transform * pose.component_transforms[i]`, or by `pose.transform` alone when the pose has
/// no transform for it. A capsule naming a component without a body is placed but left out of the
/// mass (see [`BallPlacement::mass`](super::BallPlacement::mass)). The design's infill is used,
/// not the project's. Never panics; finite inputs give finite outputs.
pub fn evaluate_pose(
    project: &Project,
    bodies: &[ComponentBody],
    design: &Design,
    pose: &Pose,
) -> PoseEvaluation {
    let written = evaluate_placed(project, bodies, design, pose, false);
    let settled = rest::settle_pose(project, bodies, pose, &written.centre_of_mass.into());
    let rocks = rest::rule(pose) == Some(rest::Rule::FirstFacet);
    let mut evaluation = match settled.resting {
        Some(_) => evaluate_placed(project, bodies, design, &settled.pose, rocks),
        None => written,
    };
    evaluation.resting = settled.resting;
    evaluation
}

/// What `design` does in `pose` exactly as placed, without settling on the hull; when `rocks`
/// (an `imbalance` pose on its facet), with the tilt margin of a model that may rock
/// (docs/physics.md, "Rocking is not toppling").
fn evaluate_placed(
    project: &Project,
    bodies: &[ComponentBody],
    design: &Design,
    pose: &Pose,
    rocks: bool,
) -> PoseEvaluation {
    let up = project.up.unit_vector();
    let cubic = project.units.cubic_in_cm3();
    let balls: Vec<_> = design
        .capsules
        .iter()
        .map(|capsule| {
            let frame = pose.component_frame(capsule.component);
            ball::place_ball(capsule, &frame, &up, &project.ball, cubic)
        })
        .collect();
    let totals = mass::mass_totals(project, bodies, design, pose, &balls);
    let vertices = posed_vertices(bodies, pose);
    let mut support = support::support(
        &vertices,
        project.up,
        support::contact_tolerance(pose)
            .unwrap_or_else(|| rest::default_contact_tolerance(&vertices)),
        &totals.centre_of_mass,
    );
    with_rolling_balls(
        &mut support,
        project,
        bodies.len(),
        design,
        pose,
        &balls,
        &totals,
    );
    if rocks && support.tilt_margin < 0.0 {
        let first = support.tilt_direction.map(Vector3::from);
        let rocked = first.and_then(|first| {
            rocking::gentlest_rocking_slope(
                project,
                bodies,
                design,
                pose,
                &vertices,
                -support.tilt_margin,
                &first,
            )
        });
        if let Some((slope, direction)) = rocked {
            // It stands, rocked onto another facet, on a gentler slope than on its own (0: on
            // level ground).
            support.tilt_margin = -slope;
            support.tilt_direction = Some(direction.into());
            support.ball_moves.clear();
        }
    }
    let coincidence = 1e-9 * extent(&vertices);
    let model = equilibria::Model::new(bodies, design, pose, project, &balls, &totals, coincidence);
    let measured = goals::Measured {
        pose,
        up,
        totals: &totals,
        tilt_margin: support.tilt_margin,
        coincidence,
        cubic_in_cm3: cubic,
        model: &model,
    };
    let goals = pose
        .goals
        .iter()
        .map(|goal| goals::evaluate_goal(&goal.value, &measured))
        .collect();
    PoseEvaluation {
        pose: pose.name.value.clone(),
        mass: totals.mass,
        volume: totals.volume,
        centre_of_mass: totals.centre_of_mass.into(),
        balls,
        support,
        resting: None,
        goals,
        component_frames: (0..bodies.len()).map(|i| pose.component_frame(i)).collect(),
    }
}

/// Replaces the fixed-ball tilt margin of `support` by the margin with every ball rolling (see
/// [`super::tilt`]) when the support is a polygon and the model has a positive mass above it.
/// `balls` are the design's balls as placed at rest; those whose component has no body (one of
/// `body_count`) are not in the mass and do not roll.
fn with_rolling_balls(
    support: &mut Support,
    project: &Project,
    body_count: usize,
    design: &Design,
    pose: &Pose,
    balls: &[BallPlacement],
    totals: &MassTotals,
) {
    let plane = GroundPlane::new(project.up);
    let polygon: Vec<_> = support
        .polygon
        .iter()
        .map(|p| plane.project(&Point3::from(*p)))
        .collect();
    let mut fixed_moment = totals.centre_of_mass.coords * totals.mass;
    let mut fixed_mass = totals.mass;
    let mut rolling = Vec::new();
    let mut names = Vec::new();
    for (capsule, ball) in design.capsules.iter().zip(balls) {
        if capsule.component >= body_count {
            continue;
        }
        fixed_moment -= Point3::from(ball.centre_world).coords * ball.mass;
        fixed_mass -= ball.mass;
        let frame = pose.component_frame(capsule.component);
        rolling.push(RollingBall {
            from: frame * capsule.from,
            to: frame * capsule.to,
            drop: (capsule.radius - capsule.ball_radius).max(0.0),
            mass: ball.mass,
        });
        names.push(&capsule.name);
    }
    let model = TiltedModel {
        plane: &plane,
        ground: support.ground_height,
        polygon: &polygon,
        fixed_mass,
        fixed_moment,
        balls: &rolling,
    };
    let Some(tilt) = model.worst_tilt() else {
        return;
    };
    support.tilt_margin = tilt.margin;
    support.tilt_direction = Some(tilt.direction.into());
    support.ball_moves = tilt
        .moves
        .into_iter()
        .map(|m| BallMove {
            capsule: names[m.ball].clone(),
            tilt: m.tilt,
            to: m.to,
        })
        .collect();
}

/// Every vertex of every component, in world, component by component.
pub(crate) fn posed_vertices(bodies: &[ComponentBody], pose: &Pose) -> Vec<Point3<f64>> {
    let total = bodies.iter().map(|body| body.mesh.positions.len()).sum();
    let mut vertices = Vec::with_capacity(total);
    for (i, body) in bodies.iter().enumerate() {
        let frame = pose.component_frame(i);
        vertices.extend(body.mesh.positions.iter().map(|p| frame * p));
    }
    vertices
}

/// The convex hull of the model as `pose` places `bodies`, its corners indices into
/// `vertices` ([`posed_vertices`] of the same pose): one component's rest-frame hull moved into
/// place; for several, the hull of their hull vertices so placed (a body given no hull
/// contributes all its vertices, rather than a hull computed only for them). `None` when the
/// model spans no volume.
pub(crate) fn posed_hull(
    bodies: &[ComponentBody],
    pose: &Pose,
    vertices: &[Point3<f64>],
) -> Option<ConvexHull> {
    if let [body] = bodies {
        return Some(body.rest_hull()?.moved(&pose.component_frame(0)));
    }
    let mut candidates = Vec::new();
    let mut first = 0;
    for body in bodies {
        let count = body.mesh.positions.len();
        match body.hull {
            Some(hull) => candidates.extend(hull.vertices.iter().map(|&i| first + i)),
            None => candidates.extend(first..first + count),
        }
        first += count;
    }
    convex_hull_among(vertices, &candidates)
}

/// Every vertex of the model as `pose` places `bodies` ([`posed_vertices`]) and their convex
/// hull ([`posed_hull`]); `None` when the model spans no volume.
pub(crate) fn posed_vertices_and_hull(
    bodies: &[ComponentBody],
    pose: &Pose,
) -> Option<(Vec<Point3<f64>>, ConvexHull)> {
    let vertices = posed_vertices(bodies, pose);
    let hull = posed_hull(bodies, pose, &vertices)?;
    Some((vertices, hull))
}

/// Diagonal of the bounding box of `points`; 0 when there are none.
pub(crate) fn extent(points: &[Point3<f64>]) -> f64 {
    let Some(first) = points.first() else {
        return 0.0;
    };
    let (lo, hi) = points
        .iter()
        .fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    (hi - lo).norm()
}
