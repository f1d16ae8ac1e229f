//! Every fabrication check on every capsule of a design.

use super::frame::PrintSetup;
use super::insertion::{has_window, required_rise};
use super::issue::CapsuleIssue;
use super::overlap::overlaps_with_later;
use super::placement::placement_issue;
use super::tolerance::falls_short;
use crate::design::{Design, PlacedCapsule};
use crate::geometry::TriMesh;

/// The fabrication problems of `design`'s capsules: each must be long enough to take its ball
/// during the print pause, hold a ball that fits with `clearance` around it, lie inside its
/// component with at least `wall` of material to the surface, take its ball at a pause on the
/// layer grid with its component printed as `print` says, and keep `wall` from every other
/// capsule of its component.
///
/// `meshes` are the components, indexed by [`PlacedCapsule::component`]; meshes and capsules are
/// all in the one shared rest frame, in the same units as `wall` and `clearance`. A value that
/// misses its limit only by rounding (a relative 10⁻⁹) passes.
///
/// Issues come in capsule order; for one capsule in the order the [`CapsuleIssue`] variants are
/// declared, overlaps last, by the other capsule's index. A capsule has at most one placement
/// issue ([`UnknownComponent`](CapsuleIssue::UnknownComponent),
/// [`Outside`](CapsuleIssue::Outside), [`InOtherComponent`](CapsuleIssue::InOtherComponent) or
/// [`TooCloseToSurface`](CapsuleIssue::TooCloseToSurface)). An overlap is reported once, on the
/// capsule with the lower index. The insertion window is checked only for a capsule whose ball
/// fits and that lies in its own component (no placement issue, or too close to its surface):
/// heights in another component mean nothing.
///
/// Cost: per capsule, one winding number and at most one segment distance on its component's
/// mesh (each linear in the triangle count); the other meshes only when the middle of the axis
/// is outside its own component; plus one segment–segment distance per pair of capsules in the
/// same component; one pass over the component's vertices for its bed height. Empty meshes, zero-length axes and any number of capsules are fine: an empty
/// mesh contains nothing.
///
/// # Panics
/// If a mesh has a triangle index out of range (see [`TriMesh`]).
pub fn check_design(
    meshes: &[TriMesh],
    design: &Design,
    wall: f64,
    clearance: f64,
    print: &PrintSetup,
) -> Vec<CapsuleIssue> {
    let mut issues = Vec::new();
    for (index, capsule) in design.capsules.iter().enumerate() {
        let shape: Vec<CapsuleIssue> = shape_issues(index, capsule, clearance).collect();
        let fits = !shape
            .iter()
            .any(|issue| matches!(issue, CapsuleIssue::BallDoesNotFit { .. }));
        issues.extend(shape);
        let placement = placement_issue(meshes, index, capsule, wall);
        let inside = matches!(
            placement,
            None | Some(CapsuleIssue::TooCloseToSurface { .. })
        );
        issues.extend(placement);
        if let (true, true, Some(mesh)) = (fits, inside, meshes.get(capsule.component)) {
            let frame = print.frame(capsule.component, mesh);
            if !has_window(capsule, &frame, &print.grid) {
                let (rise, required) = required_rise(capsule, &frame, &print.grid);
                issues.push(CapsuleIssue::NoInsertionWindow {
                    capsule: index,
                    rise,
                    required,
                });
            }
        }
        issues.extend(overlaps_with_later(&design.capsules, index, wall));
    }
    issues
}

/// The problems of capsule number `index` on its own, without the meshes: too short an axis
/// (eq. 16), then a ball that does not fit.
fn shape_issues(
    index: usize,
    capsule: &PlacedCapsule,
    clearance: f64,
) -> impl Iterator<Item = CapsuleIssue> {
    let length = capsule.axis_length();
    let too_short = falls_short(length, capsule.radius).then_some(CapsuleIssue::TooShort {
        capsule: index,
        length,
        radius: capsule.radius,
    });
    let max = capsule.radius - clearance;
    let ball_radius = capsule.ball_radius;
    let ball = (ball_radius <= 0.0 || falls_short(max, ball_radius)).then_some(
        CapsuleIssue::BallDoesNotFit {
            capsule: index,
            ball_radius,
            max,
        },
    );
    too_short.into_iter().chain(ball)
}
