//! One pose evaluated: the per-stage results wired together.

use nalgebra::Point3;

use super::{ball, goals, mass, rest, support, ComponentBody, PoseEvaluation};
use crate::design::Design;
use crate::spec::model::{Pose, Project};

/// What `design` does in `pose`: mass and centre of mass, where each ball rests, the support on
/// the ground with its toppling angles, and the outcome of each of the pose's goals.
///
/// A pose with a `stand` or `imbalance` goal is first settled onto its hull
/// ([`rest`](super::rest)) with the design's centre of mass in the written pose, and everything is
/// evaluated in the settled pose; [`PoseEvaluation::resting`] says which facet and how far the
/// written rotation was from it.
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
    let written = evaluate_placed(project, bodies, design, pose);
    let settled = rest::settle_pose(project, bodies, pose, &written.centre_of_mass.into());
    let mut evaluation = match settled.resting {
        Some(_) => evaluate_placed(project, bodies, design, &settled.pose),
        None => written,
    };
    evaluation.resting = settled.resting;
    evaluation
}

/// What `design` does in `pose` exactly as placed, without settling on the hull.
fn evaluate_placed(
    project: &Project,
    bodies: &[ComponentBody],
    design: &Design,
    pose: &Pose,
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
    let support = support::support(
        &vertices,
        project.up,
        support::contact_tolerance(pose)
            .unwrap_or_else(|| rest::default_contact_tolerance(&vertices)),
        &totals.centre_of_mass,
    );
    let measured = goals::Measured {
        pose,
        up,
        totals: &totals,
        tilt_margin: support.tilt_margin,
        coincidence: 1e-9 * extent(&vertices),
        cubic_in_cm3: cubic,
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
    }
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
