//! Fabrication checks on capsules placed in boxes: containment, walls, overlaps, lengths, balls,
//! insertion windows.

mod geometry_support;

use ballast::design::{Design, PlacedCapsule};
use ballast::fabrication::{check_design, CapsuleIssue, LayerGrid, PrintSetup};
use ballast::geometry::TriMesh;
use geometry_support::box_mesh;
use nalgebra::{Isometry3, Point3, Vector3};

const WALL: f64 = 1.0;
const CLEARANCE: f64 = 0.2;

fn p(x: f64, y: f64, z: f64) -> Point3<f64> {
    Point3::new(x, y, z)
}

/// A capsule of radius 4 holding a ball of radius 3.8 (the largest that leaves the clearance).
fn capsule(component: usize, from: Point3<f64>, to: Point3<f64>) -> PlacedCapsule {
    PlacedCapsule {
        name: "c".to_string(),
        component,
        from,
        to,
        radius: 4.0,
        ball_radius: 3.8,
    }
}

fn design(capsules: Vec<PlacedCapsule>) -> Design {
    Design {
        capsules,
        infill: 1.0,
    }
}

/// The box [0,40]×[0,20]×[0,20].
fn box_a() -> TriMesh {
    box_mesh(40.0, 20.0, 20.0)
}

/// `mesh` moved by `(x, y, z)`.
fn shifted(mesh: &TriMesh, x: f64, y: f64, z: f64) -> TriMesh {
    mesh.transformed(&Isometry3::translation(x, y, z))
}

/// Box A and, 20 beyond it along x, box B = [60,100]×[0,20]×[0,20].
fn two_boxes() -> Vec<TriMesh> {
    vec![box_a(), shifted(&box_a(), 60.0, 0.0, 0.0)]
}

/// Every component printed along `up` on layers of 0.35 mm, then 0.3 mm (boundaries off whole
/// millimetres).
fn printed_along(up: Vector3<f64>, components: usize) -> PrintSetup {
    PrintSetup {
        up: vec![up.normalize(); components],
        grid: LayerGrid {
            first_layer_height: 0.35,
            layer_height: 0.3,
            pause_clearance: 0.2,
        },
    }
}

/// The issues of `capsules` with every component printed along `up`.
fn check_printed(
    meshes: &[TriMesh],
    capsules: Vec<PlacedCapsule>,
    up: Vector3<f64>,
) -> Vec<CapsuleIssue> {
    let print = printed_along(up, meshes.len());
    check_design(meshes, &design(capsules), WALL, CLEARANCE, &print)
}

/// The issues of `capsules` printed along +x, the direction most capsules here lie in (so their
/// balls can go in).
fn check(meshes: &[TriMesh], capsules: Vec<PlacedCapsule>) -> Vec<CapsuleIssue> {
    check_printed(meshes, capsules, Vector3::x())
}

fn assert_close(actual: f64, expected: f64) {
    assert!(
        (actual - expected).abs() < 1e-9,
        "{actual} is not {expected}"
    );
}

/// The one issue in `issues`, which must be a `TooCloseToSurface` on capsule 0 in component
/// `component`; returns its distance and required distance.
fn too_close(issues: &[CapsuleIssue], component: usize) -> (f64, f64) {
    match issues {
        [CapsuleIssue::TooCloseToSurface {
            capsule: 0,
            component: c,
            distance,
            required,
        }] if *c == component => (*distance, *required),
        other => panic!("expected one TooCloseToSurface on component {component}, got {other:?}"),
    }
}

#[test]
fn capsule_well_inside_a_box_passes() {
    // The axis is 10 from every face; 5 (radius + wall) is needed.
    let issues = check(
        &[box_a()],
        vec![capsule(0, p(10.0, 10.0, 10.0), p(30.0, 10.0, 10.0))],
    );
    assert_eq!(issues, vec![]);
}

#[test]
fn capsule_exactly_one_wall_from_a_face_passes() {
    let issues = check(
        &[box_a()],
        vec![capsule(0, p(10.0, 10.0, 5.0), p(30.0, 10.0, 5.0))],
    );
    assert_eq!(issues, vec![]);
}

#[test]
fn capsule_too_close_to_the_floor_reports_the_distance() {
    let issues = check(
        &[box_a()],
        vec![capsule(0, p(10.0, 10.0, 4.5), p(30.0, 10.0, 4.5))],
    );
    let (distance, required) = too_close(&issues, 0);
    assert_close(distance, 4.5);
    assert_close(required, 5.0);
}

#[test]
fn slanted_capsule_reports_its_closest_approach() {
    // From the middle of the box towards the face y = 20, ending 3.5 short of it; every other
    // face is at least 10 away from the axis.
    let issues = check(
        &[box_a()],
        vec![capsule(0, p(10.0, 10.0, 10.0), p(30.0, 16.5, 10.0))],
    );
    let (distance, required) = too_close(&issues, 0);
    assert_close(distance, 3.5);
    assert_close(required, 5.0);
}

#[test]
fn capsule_poking_out_of_the_box_crosses_the_surface() {
    // The middle (x = 27.5) is inside; the end x = 45 is outside the face x = 40.
    let issues = check(
        &[box_a()],
        vec![capsule(0, p(10.0, 10.0, 10.0), p(45.0, 10.0, 10.0))],
    );
    let (distance, required) = too_close(&issues, 0);
    assert_eq!(distance, 0.0);
    assert_close(required, 5.0);
}

#[test]
fn capsule_in_the_other_box_names_it() {
    let in_b = capsule(0, p(70.0, 10.0, 10.0), p(90.0, 10.0, 10.0));
    let in_a = capsule(1, p(10.0, 10.0, 10.0), p(30.0, 10.0, 10.0));
    let issues = check(&two_boxes(), vec![in_b, in_a]);
    assert_eq!(
        issues,
        vec![
            CapsuleIssue::InOtherComponent {
                capsule: 0,
                assigned: 0,
                actual: 1
            },
            CapsuleIssue::InOtherComponent {
                capsule: 1,
                assigned: 1,
                actual: 0
            },
        ]
    );
}

#[test]
fn of_several_other_components_the_deepest_is_named() {
    // Box B and a bigger box around it both hold the capsule's middle; the bigger one leaves
    // more room, whichever order the two come in.
    let small = shifted(&box_a(), 60.0, 0.0, 0.0);
    let big = shifted(&box_mesh(60.0, 40.0, 40.0), 50.0, -10.0, -10.0);
    let placed = || vec![capsule(0, p(70.0, 10.0, 10.0), p(90.0, 10.0, 10.0))];
    for (meshes, expected) in [
        (vec![box_a(), small.clone(), big.clone()], 2),
        (vec![box_a(), big, small], 1),
    ] {
        assert_eq!(
            check(&meshes, placed()),
            vec![CapsuleIssue::InOtherComponent {
                capsule: 0,
                assigned: 0,
                actual: expected
            }]
        );
    }
}

#[test]
fn capsule_outside_both_boxes() {
    let between = capsule(1, p(45.0, 10.0, 10.0), p(55.0, 10.0, 10.0));
    let beyond = capsule(0, p(-30.0, 10.0, 10.0), p(-10.0, 10.0, 10.0));
    let issues = check(&two_boxes(), vec![between, beyond]);
    assert_eq!(
        issues,
        vec![
            CapsuleIssue::Outside {
                capsule: 0,
                component: 1
            },
            CapsuleIssue::Outside {
                capsule: 1,
                component: 0
            },
        ]
    );
}

/// Two capsules of radius 4 along x in the box [0,60]×[0,40]×[0,40], `gap` apart along y.
fn parallel_pair(gap: f64) -> Vec<CapsuleIssue> {
    let room = box_mesh(60.0, 40.0, 40.0);
    let y = 20.0 - gap / 2.0;
    check(
        &[room],
        vec![
            capsule(0, p(10.0, y, 20.0), p(50.0, y, 20.0)),
            capsule(0, p(10.0, y + gap, 20.0), p(50.0, y + gap, 20.0)),
        ],
    )
}

#[test]
fn overlapping_capsules_in_one_component() {
    match parallel_pair(8.5).as_slice() {
        [CapsuleIssue::Overlap {
            first: 0,
            second: 1,
            distance,
            required,
        }] => {
            assert_close(*distance, 8.5);
            assert_close(*required, 9.0);
        }
        other => panic!("expected one overlap, got {other:?}"),
    }
}

#[test]
fn capsules_that_keep_the_wall_between_them_pass() {
    // Radii 4 + 4 and a wall of 1: axes 9 apart are just enough.
    assert_eq!(parallel_pair(9.0), vec![]);
    assert_eq!(parallel_pair(9.25), vec![]);
}

#[test]
fn crossing_capsules_overlap_at_distance_zero() {
    let room = box_mesh(60.0, 40.0, 40.0);
    // Printed along the diagonal of x and y, both axes rise.
    let issues = check_printed(
        &[room],
        vec![
            capsule(0, p(10.0, 20.0, 20.0), p(50.0, 20.0, 20.0)),
            capsule(0, p(30.0, 8.0, 20.0), p(30.0, 32.0, 20.0)),
        ],
        Vector3::new(1.0, 1.0, 0.0),
    );
    assert_eq!(
        issues,
        vec![CapsuleIssue::Overlap {
            first: 0,
            second: 1,
            distance: 0.0,
            required: 9.0
        }]
    );
}

#[test]
fn capsules_of_different_components_are_not_compared() {
    // Two components that occupy the same box, one capsule in each, in the same place.
    let placed = |component| capsule(component, p(10.0, 10.0, 10.0), p(30.0, 10.0, 10.0));
    let issues = check(&[box_a(), box_a()], vec![placed(0), placed(1)]);
    assert_eq!(issues, vec![]);
}

#[test]
fn axis_shorter_than_the_radius_is_too_short() {
    let issues = check(
        &[box_a()],
        vec![capsule(0, p(18.0, 10.0, 10.0), p(21.0, 10.0, 10.0))],
    );
    // Rising 3 along the print direction, it has no insertion window either.
    assert_eq!(
        issues[0],
        CapsuleIssue::TooShort {
            capsule: 0,
            length: 3.0,
            radius: 4.0
        }
    );
    let (rise, required) = no_window(&issues[1..]);
    assert_close(rise, 3.0);
    assert_close(required, 4.05);
    // 4.1 long: as long as its radius, and its window [22.1, 22.3] holds the boundary 22.25.
    let long_enough = check(
        &[box_a()],
        vec![capsule(0, p(18.0, 10.0, 10.0), p(22.1, 10.0, 10.0))],
    );
    assert_eq!(long_enough, vec![]);
}

#[test]
fn zero_length_axis_is_too_short_and_still_placed() {
    let point = p(20.0, 10.0, 2.0);
    let issues = check(&[box_a()], vec![capsule(0, point, point)]);
    assert_eq!(issues.len(), 3, "{issues:?}");
    assert_eq!(
        issues[0],
        CapsuleIssue::TooShort {
            capsule: 0,
            length: 0.0,
            radius: 4.0
        }
    );
    let (distance, _) = too_close(&issues[1..2], 0);
    // Too close to the floor, it is still inside: its window is checked. The bed at x = 0; the
    // ball tops out at 20 − 4 + 7.6 = 23.6 on the smooth end, 24.1 with a layer for the stepped
    // floor and the 0.2 pause clearance; the next boundary is 24.35, which the window's high end
    // 20 + 0.2 reaches after a rise of 4.15.
    let (rise, required) = no_window(&issues[2..]);
    assert_close(rise, 0.0);
    assert_close(required, 4.15);
    assert_close(distance, 2.0);
}

#[test]
fn ball_too_large_or_not_positive_does_not_fit() {
    let inside = || capsule(0, p(10.0, 10.0, 10.0), p(30.0, 10.0, 10.0));
    for ball_radius in [3.9, 0.0, -1.0] {
        let issues = check(
            &[box_a()],
            vec![PlacedCapsule {
                ball_radius,
                ..inside()
            }],
        );
        match issues.as_slice() {
            [CapsuleIssue::BallDoesNotFit {
                capsule: 0,
                ball_radius: reported,
                max,
            }] => {
                assert_eq!(*reported, ball_radius);
                assert_close(*max, 3.8);
            }
            other => panic!("ball {ball_radius}: expected BallDoesNotFit, got {other:?}"),
        }
    }
    // Radius minus clearance, as the project model computes it, fits.
    let exact = PlacedCapsule {
        ball_radius: 4.0 - CLEARANCE,
        ..inside()
    };
    assert_eq!(check(&[box_a()], vec![exact]), vec![]);
}

#[test]
fn missing_or_empty_component_does_not_panic() {
    let placed = capsule(3, p(10.0, 10.0, 10.0), p(30.0, 10.0, 10.0));
    assert_eq!(
        check(&[box_a()], vec![placed.clone()]),
        vec![CapsuleIssue::UnknownComponent {
            capsule: 0,
            component: 3
        }]
    );
    assert_eq!(
        check(&[], vec![placed]),
        vec![CapsuleIssue::UnknownComponent {
            capsule: 0,
            component: 3
        }]
    );
    let empty = TriMesh {
        positions: vec![],
        triangles: vec![],
    };
    assert_eq!(
        check(
            &[empty],
            vec![capsule(0, p(1.0, 1.0, 1.0), p(9.0, 1.0, 1.0))]
        ),
        vec![CapsuleIssue::Outside {
            capsule: 0,
            component: 0
        }]
    );
}

#[test]
fn issues_come_by_capsule_then_kind() {
    let bad = PlacedCapsule {
        ball_radius: 5.0,
        ..capsule(0, p(45.0, 10.0, 10.0), p(46.0, 10.0, 10.0))
    };
    let meshes = two_boxes();
    let issues = check(
        &meshes,
        vec![
            bad,
            capsule(0, p(10.0, 10.0, 10.0), p(30.0, 10.0, 10.0)),
            capsule(0, p(10.0, 10.0, 12.0), p(30.0, 10.0, 12.0)),
        ],
    );
    let kinds: Vec<(usize, &str)> = issues
        .iter()
        .map(|issue| {
            let kind = match issue {
                CapsuleIssue::TooShort { .. } => "short",
                CapsuleIssue::BallDoesNotFit { .. } => "ball",
                CapsuleIssue::UnknownComponent { .. } => "unknown",
                CapsuleIssue::Outside { .. } => "outside",
                CapsuleIssue::InOtherComponent { .. } => "other",
                CapsuleIssue::TooCloseToSurface { .. } => "close",
                CapsuleIssue::NoInsertionWindow { .. } => "window",
                CapsuleIssue::Overlap { .. } => "overlap",
            };
            (issue.capsule(), kind)
        })
        .collect();
    // Capsule 0 sits between the boxes, at least 15 from capsules 1 and 2 (9 is needed);
    // capsules 1 and 2 are 2 apart.
    assert_eq!(
        kinds,
        vec![(0, "short"), (0, "ball"), (0, "outside"), (1, "overlap")]
    );
    assert_eq!(
        issues[3],
        CapsuleIssue::Overlap {
            first: 1,
            second: 2,
            distance: 2.0,
            required: 9.0
        }
    );
}

#[test]
fn many_capsules_are_checked_pairwise() {
    // A row of 40 short capsules along z in a long bar, 10 apart, printed along z: neighbours
    // keep the wall.
    let bar = [box_mesh(420.0, 20.0, 20.0)];
    let capsules: Vec<PlacedCapsule> = (0..40)
        .map(|i| {
            let x = 10.0 + 10.0 * f64::from(i);
            PlacedCapsule {
                radius: 3.0,
                ball_radius: 2.5,
                ..capsule(0, p(x, 10.0, 10.0), p(x, 10.0, 14.0))
            }
        })
        .collect();
    assert_eq!(
        check_design(
            &bar,
            &design(capsules.clone()),
            WALL,
            CLEARANCE,
            &printed_along(Vector3::z(), 1)
        ),
        vec![]
    );
    // Move one capsule next to its neighbour: exactly one overlap, on the lower index.
    let mut crowded = capsules;
    crowded[7].from.x -= 4.0;
    crowded[7].to.x -= 4.0;
    let issues = check_design(
        &bar,
        &design(crowded),
        WALL,
        CLEARANCE,
        &printed_along(Vector3::z(), 1),
    );
    assert_eq!(issues.len(), 1, "{issues:?}");
    assert!(matches!(
        issues[0],
        CapsuleIssue::Overlap {
            first: 6,
            second: 7,
            ..
        }
    ));
}

/// The one `NoInsertionWindow` in `issues`, on capsule 0: its rise and required rise.
fn no_window(issues: &[CapsuleIssue]) -> (f64, f64) {
    match issues {
        [CapsuleIssue::NoInsertionWindow {
            capsule: 0,
            rise,
            required,
        }] => (*rise, *required),
        other => panic!("expected one NoInsertionWindow, got {other:?}"),
    }
}

#[test]
fn an_axis_that_rises_too_little_has_no_insertion_window() {
    // Printed along x from the face x = 0: the ends are at heights 18 and 21 (the axis also
    // climbs 3 along z, so it is longer than its radius). The ball (3.8 in a void of 4) tops out
    // at 18 − 4 + 7.6 = 21.6 on the smooth end, so the window starts a layer (0.3) and the pause
    // clearance (0.2) higher, at 22.1; the opening ends at 21.2. The first boundary from 22.1 is
    // 0.35 + 73 × 0.3 = 22.25, so the axis must rise until 21.2's end reaches it: 4.05.
    let (rise, required) = no_window(&check(
        &[box_a()],
        vec![capsule(0, p(18.0, 10.0, 10.0), p(21.0, 10.0, 13.0))],
    ));
    assert_close(rise, 3.0);
    assert_close(required, 4.05);
    // Rising 4.1, the window [22.1, 22.3] holds the boundary 22.25.
    let enough = check(
        &[box_a()],
        vec![capsule(0, p(18.0, 10.0, 10.0), p(22.1, 10.0, 13.0))],
    );
    assert_eq!(enough, vec![]);
}

#[test]
fn a_long_axis_across_the_print_direction_has_no_window() {
    // 20 long along x, printed along z: it does not rise at all. Its window starts at
    // 10 − 4 + 7.6 + 0.3 + 0.2 = 14.1; the first boundary from there is 14.15, which the
    // window's high end 10 + 0.2 reaches after a rise of 3.95.
    let placed = || vec![capsule(0, p(10.0, 10.0, 10.0), p(30.0, 10.0, 10.0))];
    let (rise, required) = no_window(&check_printed(&[box_a()], placed(), Vector3::z()));
    assert_close(rise, 0.0);
    assert_close(required, 3.95);
    // Printed along the diagonal of x and z it rises 20 / √2 and passes.
    assert_eq!(
        check_printed(&[box_a()], placed(), Vector3::new(1.0, 0.0, 1.0)),
        vec![]
    );
}

#[test]
fn a_capsule_outside_its_component_has_no_window_checked() {
    // Across the print direction but outside every box: only the placement issue.
    let issues = check_printed(
        &two_boxes(),
        vec![capsule(0, p(45.0, 10.0, 10.0), p(55.0, 10.0, 10.0))],
        Vector3::z(),
    );
    assert_eq!(
        issues,
        vec![CapsuleIssue::Outside {
            capsule: 0,
            component: 0
        }]
    );
}
