//! Poses placed by `down`: the facet the direction names, put on the ground, once the meshes are
//! loaded (the front end knows no meshes).

use nalgebra::Isometry3;

use crate::balance::facets::{facet_along, facet_margin, model_frame};
use crate::balance::rest::solid_centre;
use crate::balance::{facet_rotation, ComponentBody};
use crate::diagnostic::Problem;
use crate::spec::model::{Goal, Project};

/// The warning code of a `down` that names a facet the solid model rolls off in a `stand` pose.
pub const UNSTABLE_DOWN: &str = "ballast::pose::unstable_down";
/// The problem code of a `down` in a project whose model has no volume, hence no hull.
pub const NO_HULL: &str = "ballast::pose::no_hull";

/// Sets the transform of every pose with `down` to the rotation that puts the facet it names on
/// the ground: the hull facet (of the model as the pose places its components) that the ray from
/// the solid model's centre of mass along `down` leaves through, turned by the shortest rotation
/// that takes its outward normal to `−up` ([`facet_rotation`]). An error at `down` when the model
/// has no hull; a warning when the pose has a `stand` goal and the solid model would roll off that
/// facet (the design's capsules must then hold it there).
pub fn place_down_poses(project: &mut Project, bodies: &[ComponentBody]) -> Vec<Problem> {
    let mut problems = Vec::new();
    let up = project.up;
    for pose in &mut project.poses {
        let Some(down) = pose.down.clone() else {
            continue;
        };
        let frame = model_frame(pose);
        let centre = solid_centre(bodies, &frame);
        let Some((points, hull)) =
            crate::balance::evaluate::posed_vertices_and_hull(bodies, &frame)
        else {
            problems.push(
                Problem::error(NO_HULL, "the model has no volume, so `down` names no facet")
                    .with_label(down.span, "this direction"),
            );
            continue;
        };
        let Some(index) = facet_along(&hull, &centre, &down.value) else {
            continue;
        };
        let facet = &hull.facets[index];
        let stands = pose
            .goals
            .iter()
            .any(|goal| matches!(goal.value, Goal::Stand { .. }));
        let margin = facet_margin(facet, &points, &centre);
        if stands && margin <= 0.0 {
            problems.push(
                Problem::warning(
                    UNSTABLE_DOWN,
                    format!(
                        "in pose `{}`, `down` names a facet the solid model rolls off: its centre of mass is {:.2}° beyond the facet's edge, so only the capsules' balls can hold it there",
                        pose.name.value, -margin
                    ),
                )
                .with_label(down.span, "this direction")
                .with_help("`ballast poses` lists the facets the model rests on stably, with their `down` directions"),
            );
        }
        pose.transform =
            Isometry3::from_parts(Default::default(), facet_rotation(&facet.normal, up));
    }
    problems
}
