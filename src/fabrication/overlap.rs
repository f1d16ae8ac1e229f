//! Capsules of one component that come too close to each other (eq. 14 with a wall).

use super::issue::CapsuleIssue;
use super::tolerance::falls_short;
use crate::design::PlacedCapsule;
use crate::geometry::segment_segment_distance;

/// The overlaps of capsule number `first` with every later capsule of the same component, in
/// index order: pairs whose axes are closer than the sum of the radii plus `wall`.
///
/// Capsules of different components are never compared: each component is a part of its own,
/// so their capsules never share a wall.
pub(super) fn overlaps_with_later(
    capsules: &[PlacedCapsule],
    first: usize,
    wall: f64,
) -> impl Iterator<Item = CapsuleIssue> + '_ {
    let a = &capsules[first];
    capsules
        .iter()
        .enumerate()
        .skip(first + 1)
        .filter(move |(_, b)| b.component == a.component)
        .filter_map(move |(second, b)| {
            let distance = segment_segment_distance(&a.from, &a.to, &b.from, &b.to);
            let required = a.radius + b.radius + wall;
            falls_short(distance, required).then_some(CapsuleIssue::Overlap {
                first,
                second,
                distance,
                required,
            })
        })
}
