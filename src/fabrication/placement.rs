//! Where a capsule lies relative to the component meshes: inside its own component with a wall
//! around it, too close to that component's surface, in another component, or in none.

use super::issue::CapsuleIssue;
use super::tolerance::falls_short;
use crate::design::PlacedCapsule;
use crate::geometry::{distance_to_segment, winding_number, TriMesh};

/// A point whose winding number is at least this is inside a mesh.
const INSIDE: f64 = 0.5;

/// The placement problem of capsule number `index`, or `None` when it lies inside its assigned
/// component with at least `wall` of material around it.
///
/// The capsule is inside its component when the middle of its axis is inside the mesh (winding
/// number at least 0.5) and the axis stays at least `radius + wall` from the surface; then the
/// whole capsule and its wall are inside. The assigned mesh costs one winding number and, when
/// the middle is inside, one segment distance; the other meshes are only looked at when the
/// middle is outside the assigned one.
pub(super) fn placement_issue(
    meshes: &[TriMesh],
    index: usize,
    capsule: &PlacedCapsule,
    wall: f64,
) -> Option<CapsuleIssue> {
    let assigned = capsule.component;
    let Some(mesh) = meshes.get(assigned) else {
        return Some(CapsuleIssue::UnknownComponent {
            capsule: index,
            component: assigned,
        });
    };
    let middle = nalgebra::center(&capsule.from, &capsule.to);
    if winding_number(mesh, &middle) >= INSIDE {
        let distance = distance_to_segment(mesh, &capsule.from, &capsule.to);
        let required = capsule.radius + wall;
        return falls_short(distance, required).then_some(CapsuleIssue::TooCloseToSurface {
            capsule: index,
            component: assigned,
            distance,
            required,
        });
    }
    let holding: Vec<usize> = (0..meshes.len())
        .filter(|&k| k != assigned && winding_number(&meshes[k], &middle) >= INSIDE)
        .collect();
    Some(match holding.as_slice() {
        [] => CapsuleIssue::Outside {
            capsule: index,
            component: assigned,
        },
        [only] => CapsuleIssue::InOtherComponent {
            capsule: index,
            assigned,
            actual: *only,
        },
        several => CapsuleIssue::InOtherComponent {
            capsule: index,
            assigned,
            actual: deepest(meshes, several, capsule),
        },
    })
}

/// Of the `candidates` (indices into `meshes`, at least one), the one whose surface is farthest
/// from the capsule's axis; the lowest index on a tie.
fn deepest(meshes: &[TriMesh], candidates: &[usize], capsule: &PlacedCapsule) -> usize {
    let clearance = |k: usize| distance_to_segment(&meshes[k], &capsule.from, &capsule.to);
    let first = (candidates[0], clearance(candidates[0]));
    candidates[1..]
        .iter()
        .map(|&k| (k, clearance(k)))
        .fold(
            first,
            |best, next| if next.1 > best.1 { next } else { best },
        )
        .0
}
