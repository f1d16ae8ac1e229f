//! When each ball can go in: the insertion window of a capsule in its component's print
//! direction, the pauses on the layer grid that serve every capsule of a component, and the
//! span of each void's ceiling (`docs/fabrication.md`, "When a ball can go in").
//!
//! Heights are measured along the print direction `up` from the bed, the lowest point of the
//! component along `up`. A capsule's ends sit at heights `z_P ≤ z_Q`; with void radius `r`, ball
//! radius `b < r`, layer height `h` and pause clearance `g`, the print may pause at any height in
//! `[z_P − r + 2b + h + g, z_Q + r − b]`.

use super::frame::{LayerGrid, PrintFrame};
use super::plan::{CapsuleInsertion, Pause};
use crate::design::PlacedCapsule;

/// The steepest overhang a slicer prints without bridging, degrees from vertical.
const SELF_SUPPORTING_DEGREES: f64 = 45.0;

/// The ends of `capsule`'s axis as heights above the bed, lower first.
fn end_heights(capsule: &PlacedCapsule, frame: &PrintFrame) -> (f64, f64) {
    let (a, b) = (frame.height(&capsule.from), frame.height(&capsule.to));
    (a.min(b), a.max(b))
}

/// The heights at which the print may pause to drop `capsule`'s ball in, `(low, high)`, or
/// `None` when there are none (or the ball does not fit).
///
/// Low: the ball, rolled to the lowest point of the void (its centre `r − b` below the lower end
/// `P`), tops out at `z_P − r + 2b` on the void's smooth end. The printed floor is a stack of
/// layers, which holds the ball higher, by less than a layer height `h` (0.11-0.18 mm at 0.3 mm
/// layers, `tests/ball_rest_examples.rs`), and the ball's top must lie the grid's pause
/// clearance `g` below the printed height: the window starts at `z_P − r + 2b + h + g`. High: a
/// ball centred on the plane of the printed height at most `r − b` from the axis is inside the
/// void with its upper half in the open, and rolls down the convex set of ball centres to its
/// rest; that plane meets the set up to `z_Q + r − b`. The high end is sufficient, not necessary
/// (a ball narrower than the opening passes a little higher).
pub fn insertion_window(
    capsule: &PlacedCapsule,
    frame: &PrintFrame,
    grid: &LayerGrid,
) -> Option<(f64, f64)> {
    let (r, b) = (capsule.radius, capsule.ball_radius);
    if !(b > 0.0 && b < r) {
        return None;
    }
    let (low_end, high_end) = end_heights(capsule, frame);
    let window = (rest_top(low_end, r, b, grid), high_end + r - b);
    (window.0 <= window.1).then_some(window)
}

/// The least printed height above which a ball of radius `b`, dropped into a void of radius `r`
/// whose lower axis end is at `low_end`, rests with the grid's clearance: its top on the void's
/// smooth end, raised by a layer height for the stepped floor and by the pause clearance.
fn rest_top(low_end: f64, r: f64, b: f64, grid: &LayerGrid) -> f64 {
    low_end - r + 2.0 * b + grid.layer_height + grid.pause_clearance
}

/// Whether `capsule`'s ball can go in at some pause on `grid`: its window holds a layer
/// boundary (what [`plan_insertions`] gives a pause).
pub fn has_window(capsule: &PlacedCapsule, frame: &PrintFrame, grid: &LayerGrid) -> bool {
    insertion_window(capsule, frame, grid)
        .and_then(|(low, high)| grid.boundaries_in(low, high))
        .is_some()
}

/// How far `capsule`'s axis rises along the print direction, and how far it must rise, with its
/// lower end where it is, for its window to hold a boundary of `grid`.
pub fn required_rise(capsule: &PlacedCapsule, frame: &PrintFrame, grid: &LayerGrid) -> (f64, f64) {
    let (r, b) = (capsule.radius, capsule.ball_radius);
    let (low_end, high_end) = end_heights(capsule, frame);
    let low = rest_top(low_end, r, b, grid);
    // The window's high end, `z_Q + r − b`, must reach the first boundary from its low end.
    let needed = grid.boundary_from(low) - low_end - (r - b);
    (high_end - low_end, needed)
}

/// The widest span across the ceiling of a void of `radius` that overhangs more than 45°: what
/// a slicer bridges.
///
/// The ceiling's surface steeper than 45° is where the outward normal is within 45° of up; seen
/// from above it lies within `r sin 45°` of the axis, and it reaches that far on both sides of it
/// over the upper cap, whatever the axis's tilt. A bridge crosses the region the short way, so
/// the span is `2 r sin 45° = √2 r` (its length along a tilted axis is in
/// `docs/fabrication.md`).
pub fn ceiling_bridge(radius: f64) -> f64 {
    2.0 * radius * SELF_SUPPORTING_DEGREES.to_radians().sin()
}

/// The insertion plan of one component: each capsule's window, ceiling and pause, and the
/// fewest pauses on `grid` that take every ball with a window holding a layer boundary.
///
/// `capsules` are `(index in the design, capsule)`, all of one component printed in `frame`.
/// The result's [`CapsuleInsertion`]s follow `capsules`' order; the pauses are lowest first and
/// name capsules by design index. Grouping is interval stabbing on the grid: greedy by the
/// highest boundary of each window (ties by design index), which is optimal, and each pause then
/// sits in the middle of the boundaries its capsules share (the lower one of two middles), away
/// from both ends of every window it serves. `describe` turns a ball diameter into words for the
/// printer's message ("8 mm").
pub fn plan_insertions(
    capsules: &[(usize, &PlacedCapsule)],
    frame: &PrintFrame,
    grid: &LayerGrid,
    describe: &dyn Fn(f64) -> String,
) -> (Vec<CapsuleInsertion>, Vec<Pause>) {
    let mut insertions: Vec<CapsuleInsertion> = capsules
        .iter()
        .map(|(index, capsule)| CapsuleInsertion {
            capsule: *index,
            window: insertion_window(capsule, frame, grid),
            pause: None,
            ceiling_bridge: ceiling_bridge(capsule.radius),
        })
        .collect();
    // (last, first, position in `capsules`) of each window that holds a boundary.
    let mut open: Vec<(usize, usize, usize)> = insertions
        .iter()
        .enumerate()
        .filter_map(|(position, insertion)| {
            let (low, high) = insertion.window?;
            let (first, last) = grid.boundaries_in(low, high)?;
            Some((last, first, position))
        })
        .collect();
    open.sort_by_key(|&(last, _, position)| (last, capsules[position].0));
    let mut pauses = Vec::new();
    let mut served = vec![false; capsules.len()];
    for &(last, _, position) in &open {
        if served[position] {
            continue;
        }
        let group: Vec<(usize, usize)> = open
            .iter()
            .filter(|&&(_, first, position)| !served[position] && first <= last)
            .map(|&(_, first, position)| (first, position))
            .collect();
        let Some(shared_first) = group.iter().map(|&(first, _)| first).max() else {
            continue;
        };
        let layers_done = (shared_first + last) / 2;
        let mut members: Vec<usize> = group.iter().map(|&(_, position)| position).collect();
        members.sort_by_key(|&position| capsules[position].0);
        for &position in &members {
            served[position] = true;
            insertions[position].pause = Some(pauses.len());
        }
        let balls: Vec<(&str, f64)> = members
            .iter()
            .map(|&p| (capsules[p].1.name.as_str(), 2.0 * capsules[p].1.ball_radius))
            .collect();
        let height = grid.boundary(layers_done);
        pauses.push(Pause {
            layers_done,
            height,
            resume_height: height + grid.layer_height,
            capsules: members.iter().map(|&p| capsules[p].0).collect(),
            message: insert_message(&balls, describe),
        });
    }
    (insertions, pauses)
}

/// "Insert one 8 mm steel ball into capsule `keel`", or for several
/// "Insert 2 steel balls: 8 mm into `keel`, 6 mm into `tail`".
fn insert_message(balls: &[(&str, f64)], describe: &dyn Fn(f64) -> String) -> String {
    match balls {
        [(name, diameter)] => {
            format!(
                "Insert one {} steel ball into capsule `{name}`",
                describe(*diameter)
            )
        }
        _ => {
            let each: Vec<String> = balls
                .iter()
                .map(|(name, diameter)| format!("{} into `{name}`", describe(*diameter)))
                .collect();
            format!("Insert {} steel balls: {}", balls.len(), each.join(", "))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::TriMesh;
    use nalgebra::{Point3, Vector3};

    const GRID: LayerGrid = LayerGrid {
        first_layer_height: 0.35,
        layer_height: 0.3,
        pause_clearance: 0.2,
    };

    /// The bed at z = 0, printed along +z.
    fn flat() -> PrintFrame {
        PrintFrame {
            up: Vector3::z(),
            bed: 0.0,
        }
    }

    fn capsule(name: &str, from: [f64; 3], to: [f64; 3], radius: f64, ball: f64) -> PlacedCapsule {
        PlacedCapsule {
            name: name.to_string(),
            component: 0,
            from: Point3::from(from),
            to: Point3::from(to),
            radius,
            ball_radius: ball,
        }
    }

    fn mm(diameter: f64) -> String {
        format!("{diameter} mm")
    }

    fn close(actual: (f64, f64), expected: (f64, f64)) {
        assert!(
            (actual.0 - expected.0).abs() < 1e-9 && (actual.1 - expected.1).abs() < 1e-9,
            "{actual:?} is not {expected:?}"
        );
    }

    #[test]
    fn a_vertical_capsule_opens_from_the_ball_top_to_its_upper_end() {
        // P at 10, Q at 20, r 4, b 3.8: the ball rests with its bottom at 6 and top at 13.6 on
        // the smooth end, 14.1 with a layer (0.3) for the stepped floor and the 0.2 clearance; a
        // ball centred at Q's height + 0.2 still sits inside the void.
        let c = capsule("v", [5.0, 5.0, 20.0], [5.0, 5.0, 10.0], 4.0, 3.8);
        close(insertion_window(&c, &flat(), &GRID).unwrap(), (14.1, 20.2));
        // With b = r (no clearance) the window is [z_P + r + h + g, z_Q]: eq. 16, |q − p| ≥ r,
        // with the floor and the clearance.
        let tight = capsule("t", [0.0, 0.0, 10.0], [0.0, 0.0, 14.5], 4.0, 4.0 - 1e-12);
        let (low, high) = insertion_window(&tight, &flat(), &GRID).unwrap();
        assert!((low - 14.5).abs() < 1e-9 && (high - 14.5).abs() < 1e-9);
    }

    #[test]
    fn a_horizontal_capsule_has_no_window_and_needs_a_rise() {
        // Both ends at 10: the window starts at 14.1, the opening closes above 10.2.
        let c = capsule("h", [0.0, 0.0, 10.0], [30.0, 0.0, 10.0], 4.0, 3.8);
        assert_eq!(insertion_window(&c, &flat(), &GRID), None);
        // The first boundary at or above 14.1 is 0.35 + 46 × 0.3 = 14.15: the axis must rise
        // until Q's height + 0.2 reaches it, 14.15 − 10 − 0.2 = 3.95.
        let (rise, needed) = required_rise(&c, &flat(), &GRID);
        close((rise, needed), (0.0, 3.95));
    }

    #[test]
    fn a_tilted_capsule_opens_by_its_rise_along_up() {
        // 30° above horizontal, 20 long: Q is 10 higher than P; printed along +z from a bed at
        // z = −2 (so heights are z + 2).
        let (cos, sin) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let c = capsule(
            "t",
            [0.0, 0.0, 5.0],
            [20.0 * cos, 0.0, 5.0 + 20.0 * sin],
            3.0,
            2.5,
        );
        let frame = PrintFrame {
            up: Vector3::z(),
            bed: -2.0,
        };
        close(
            insertion_window(&c, &frame, &GRID).unwrap(),
            (7.0 - 3.0 + 5.0 + 0.5, 17.0 + 0.5),
        );
        // The same capsule printed along x (the bed at x = −1): P at 1, Q at 1 + 20 cos 30°.
        let side = PrintFrame {
            up: Vector3::x(),
            bed: -1.0,
        };
        close(
            insertion_window(&c, &side, &GRID).unwrap(),
            (1.0 + 2.0 + 0.5, 1.0 + 20.0 * cos + 0.5),
        );
        // The frame of a mesh puts the bed at its lowest vertex along a normalised up.
        let mesh = TriMesh {
            positions: vec![Point3::new(0.0, 0.0, 3.0), Point3::new(1.0, 0.0, -2.0)],
            triangles: vec![],
        };
        let frame = PrintFrame::new(&mesh, Vector3::new(0.0, 0.0, 5.0));
        assert_eq!(
            frame,
            PrintFrame {
                up: Vector3::z(),
                bed: -2.0
            }
        );
    }

    #[test]
    fn a_window_without_a_layer_boundary_gets_no_pause() {
        // Vertical, r 4, b 3.8, P at 10.06 and Q at 14.16: the window [14.16, 14.36] lies
        // between the boundaries 14.15 and 14.45.
        let c = capsule("n", [0.0, 0.0, 10.06], [0.0, 0.0, 14.16], 4.0, 3.8);
        close(
            insertion_window(&c, &flat(), &GRID).unwrap(),
            (14.16, 14.36),
        );
        let (insertions, pauses) = plan_insertions(&[(0, &c)], &flat(), &GRID, &mm);
        assert_eq!(insertions[0].pause, None);
        assert!(pauses.is_empty());
        let (rise, needed) = required_rise(&c, &flat(), &GRID);
        assert!(needed > rise);
        close((rise, needed), (4.1, 14.45 - 10.06 - 0.2));
    }

    #[test]
    fn capsules_share_the_fewest_pauses() {
        // Windows (vertical, r 4, b 3.8, so [z_P + 3.6 + 0.5, z_Q + 0.2]):
        // a [14.1, 30.2], c [29.1, 40.2], d [15.1, 16.2]; b (ball 3) [19.5, 26]. As layer
        // counts (boundary of layer n at 0.35 + 0.3 (n − 1)): a 47 ..= 100, b 65 ..= 86,
        // c 97 ..= 133, d 51 ..= 53; d, b and c are pairwise disjoint, so three pauses are the
        // fewest.
        let a = capsule("a", [0.0, 0.0, 10.0], [0.0, 0.0, 30.0], 4.0, 3.8);
        let b = capsule("b", [20.0, 0.0, 25.0], [20.0, 0.0, 17.0], 4.0, 3.0);
        let c = capsule("c", [40.0, 0.0, 25.0], [40.0, 0.0, 40.0], 4.0, 3.8);
        let d = capsule("d", [60.0, 0.0, 11.0], [60.0, 0.0, 16.0], 4.0, 3.8);
        close(insertion_window(&b, &flat(), &GRID).unwrap(), (19.5, 26.0));
        let list = [(0, &a), (1, &b), (2, &c), (3, &d)];
        let (insertions, pauses) = plan_insertions(&list, &flat(), &GRID, &mm);
        // d closes first: a and d share 51 ..= 53, paused in its middle; then b alone, in the
        // middle of 65 ..= 86; a is served, so c alone, in the middle of 97 ..= 133.
        let layers: Vec<usize> = pauses.iter().map(|p| p.layers_done).collect();
        let groups: Vec<Vec<usize>> = pauses.iter().map(|p| p.capsules.clone()).collect();
        assert_eq!(groups, vec![vec![0, 3], vec![1], vec![2]]);
        assert_eq!(layers, vec![52, 75, 115]);
        let pause_of: Vec<Option<usize>> = insertions.iter().map(|i| i.pause).collect();
        assert_eq!(pause_of, vec![Some(0), Some(1), Some(2), Some(0)]);
        for (insertion, capsule) in insertions.iter().zip([&a, &b, &c, &d]) {
            let pause = &pauses[insertion.pause.unwrap()];
            let (low, high) = insertion.window.unwrap();
            assert!(
                low <= pause.height && pause.height <= high,
                "{}",
                capsule.name
            );
            assert!((pause.height - GRID.boundary(pause.layers_done)).abs() < 1e-12);
            assert!((pause.resume_height - pause.height - 0.3).abs() < 1e-12);
        }
        assert!(pauses.windows(2).all(|w| w[0].height < w[1].height));
        assert_eq!(
            pauses[0].message,
            "Insert 2 steel balls: 7.6 mm into `a`, 7.6 mm into `d`"
        );
        assert_eq!(
            pauses[1].message,
            "Insert one 6 mm steel ball into capsule `b`"
        );
    }

    #[test]
    fn the_ceiling_bridge_is_the_width_of_the_steep_region() {
        assert!((ceiling_bridge(4.0) - 4.0 * 2f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn the_grid_lists_its_boundaries_in_a_range() {
        assert_eq!(GRID.boundary(1), 0.35);
        assert_eq!(GRID.boundaries_in(0.0, 0.35), Some((1, 1)));
        assert_eq!(GRID.boundaries_in(0.36, 0.64), None);
        assert_eq!(GRID.boundaries_in(0.36, 0.65), Some((2, 2)));
        assert_eq!(GRID.boundaries_in(-5.0, 0.2), None);
        assert!((GRID.boundary_from(0.36) - 0.65).abs() < 1e-12);
        assert_eq!(GRID.boundary_from(-1.0), 0.35);
    }
}
