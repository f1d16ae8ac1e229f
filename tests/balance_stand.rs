//! Support polygons and toppling angles against hand computations.

mod balance_support;
mod geometry_support;

use std::f64::consts::PI;

use balance_support::*;
use ballast::balance::{GoalOutcome, PoseEvaluation, Support};
use ballast::geometry::TriMesh;
use ballast::spec::model::{Axis, Goal};
use geometry_support::{box_mesh, icosphere, prism};
use nalgebra::{Isometry3, Point3, Vector3};

fn degrees_atan(y: f64, x: f64) -> f64 {
    y.atan2(x).to_degrees()
}

/// Twice the signed area of the support polygon seen from above (`up`): positive when it is
/// counter-clockwise.
fn signed_area(support: &Support, up: Vector3<f64>) -> f64 {
    let n = support.polygon.len();
    (0..n)
        .map(|i| {
            let a = Vector3::from(support.polygon[i]);
            let b = Vector3::from(support.polygon[(i + 1) % n]);
            a.cross(&b).dot(&up)
        })
        .sum()
}

fn met(result: &PoseEvaluation) -> Vec<bool> {
    result.goals.iter().map(|goal| goal.met).collect()
}

#[test]
fn a_standing_box_survives_the_tilt_towards_its_narrow_side() {
    // 40 × 60 × 100: half-widths 20 and 30, centre 50 high.
    let result = evaluate(
        &project(&["box"]),
        &[box_mesh(40.0, 60.0, 100.0)],
        &design(vec![]),
        &rest_pose(1, vec![stand(21.0), stand(22.0)]),
    );
    let support = &result.support;
    assert_close("ground", support.ground_height, 0.0, 0.0);
    assert_close("height", support.centre_height, 50.0, 1e-9);
    assert_eq!(support.contacts.len(), 4);
    assert_eq!(
        support.polygon,
        vec![
            [0.0, 0.0, 0.0],
            [40.0, 0.0, 0.0],
            [40.0, 60.0, 0.0],
            [0.0, 60.0, 0.0]
        ]
    );
    let angles: Vec<f64> = support.edges.iter().map(|e| e.toppling_angle).collect();
    let narrow = degrees_atan(20.0, 50.0);
    let wide = degrees_atan(30.0, 50.0);
    for (angle, expected) in angles.iter().zip([wide, narrow, wide, narrow]) {
        assert_close("edge angle", *angle, expected, 1e-9);
    }
    assert_close("distance", support.edges[1].distance, -20.0, 1e-9);
    assert_close("tilt margin", support.tilt_margin, narrow, 1e-9);
    // atan(0.4) = 21.8°.
    assert_eq!(met(&result), vec![true, false]);
    match &result.goals[0].outcome {
        GoalOutcome::Stand {
            tilt_margin,
            margin,
        } => {
            assert_close("goal margin", *tilt_margin, narrow, 1e-9);
            assert_close("required", *margin, 21.0, 0.0);
        }
        other => panic!("expected a stand outcome, got {other:?}"),
    }
}

#[test]
fn an_off_centre_ball_shifts_the_margin_as_by_hand() {
    // A 40 mm cube with a short vertical capsule at x = 10, y = 20 from z = 10 to 12 (r = 4)
    // holding a 3.5 mm ball, which rests at (10, 20, 10 − 0.5). The steel outweighs the
    // material the void removes.
    let c = capsule(
        0,
        Point3::new(10.0, 20.0, 10.0),
        Point3::new(10.0, 20.0, 12.0),
        4.0,
        3.5,
    );
    let result = evaluate(
        &project(&["cube"]),
        &[box_mesh(40.0, 40.0, 40.0)],
        &design(vec![c]),
        &rest_pose(1, vec![stand(0.0)]),
    );
    let void = PI * 16.0 * 2.0 + 4.0 / 3.0 * PI * 64.0;
    let material = PLA * (64_000.0 - void) / 1000.0;
    let ball = STEEL * ball_volume(3.5) / 1000.0;
    assert!(ball > PLA * void / 1000.0);
    let mass = material + ball;
    let x = (PLA / 1000.0 * (64_000.0 * 20.0 - void * 10.0) + ball * 10.0) / mass;
    let z = (PLA / 1000.0 * (64_000.0 * 20.0 - void * 11.0) + ball * 9.5) / mass;
    assert_point("centre", result.centre_of_mass, [x, 20.0, z], 1e-9);
    // The ball pulls the centre towards x = 0 (the last edge): that edge is now the critical one.
    assert!(x < 20.0);
    assert_close(
        "balls-held margin",
        result.support.fixed_ball_margin,
        degrees_atan(x, z),
        1e-9,
    );
    assert_eq!(
        result.support.fixed_ball_margin,
        result.support.edges[3].toppling_angle
    );
    assert_close(
        "side edge",
        result.support.edges[0].toppling_angle,
        degrees_atan(20.0, z),
        1e-9,
    );
    assert_close(
        "opposite edge",
        result.support.edges[1].toppling_angle,
        degrees_atan(40.0 - x, z),
        1e-9,
    );
}

#[test]
fn a_box_tilted_onto_its_edge_settles_back_onto_its_base() {
    // 10° about y: the box touches along the edge x = 40, z = 0; its centre (20, 30, 50) goes to
    // x = 20 cos θ + 50 sin θ, 11 short of the edge at 40 cos θ, so it rolls back by 10° onto its
    // base, where the centre is 20 from the nearest edge and 50 high.
    let result = evaluate(
        &project(&["box"]),
        &[box_mesh(40.0, 60.0, 100.0)],
        &design(vec![]),
        &pose(
            rotation(Vector3::y(), 10.0),
            vec![Isometry3::identity()],
            vec![imbalance(5.0), imbalance(12.0), stand(0.0)],
        ),
    );
    let resting = result.resting.as_ref().expect("settles");
    assert_close("correction", resting.correction, 10.0, 1e-9);
    assert_point("down", resting.down, [0.0, 0.0, -1.0], 1e-12);
    assert_close("area", resting.area, 40.0 * 60.0, 1e-9);
    let support = &result.support;
    assert_eq!(support.contacts.len(), 4);
    assert_eq!(support.polygon.len(), 4);
    assert_close("height", support.centre_height, 50.0, 1e-9);
    assert_close(
        "tilt margin",
        support.tilt_margin,
        degrees_atan(20.0, 50.0),
        1e-9,
    );
    assert_eq!(met(&result), vec![false, false, true]);
}

/// A 20 mm cube base and a 10 × 10 × 60 arm standing on it, rest frame.
fn base_and_arm() -> Vec<TriMesh> {
    vec![
        box_mesh(20.0, 20.0, 20.0),
        box_mesh(10.0, 10.0, 60.0).transformed(&Isometry3::translation(5.0, 5.0, 20.0)),
    ]
}

#[test]
fn an_arm_swung_out_topples_the_model() {
    let meshes = base_and_arm();
    let project = project(&["base", "arm"]);
    let upright = evaluate(
        &project,
        &meshes,
        &design(vec![]),
        &rest_pose(2, vec![stand(5.0)]),
    );
    // Centre (10, 10, (8000·10 + 6000·50)/14000), 10 from every edge.
    let z = (8000.0 * 10.0 + 6000.0 * 50.0) / 14_000.0;
    assert_close(
        "upright margin",
        upright.support.tilt_margin,
        degrees_atan(10.0, z),
        1e-9,
    );
    assert!(upright.goals[0].met);

    // The arm swung 90° about y around (10, 10, 25) lies along +x at height 20-30, its centroid
    // at (35, 10, 25): the centre of mass passes the base's edge x = 20.
    let arm = rotation_about(Vector3::y(), 90.0, Point3::new(10.0, 10.0, 25.0));
    let swung = evaluate(
        &project,
        &meshes,
        &design(vec![]),
        &pose(
            Isometry3::identity(),
            vec![Isometry3::identity(), arm],
            vec![imbalance(1.0), stand(0.0)],
        ),
    );
    let x = (8000.0 * 10.0 + 6000.0 * 35.0) / 14_000.0;
    let z = (8000.0 * 10.0 + 6000.0 * 25.0) / 14_000.0;
    assert_eq!(swung.support.contacts.len(), 4);
    assert_close(
        "swung margin",
        swung.support.tilt_margin,
        -degrees_atan(x - 20.0, z),
        1e-9,
    );
    assert_eq!(met(&swung), vec![true, false]);
}

#[test]
fn a_sphere_balanced_on_a_vertex_cannot_stand() {
    let sphere = icosphere(2, 10.0, Point3::new(0.0, 0.0, 10.0));
    let result = evaluate(
        &project(&["ball"]),
        std::slice::from_ref(&sphere),
        &design(vec![]),
        &rest_pose(1, vec![stand(0.0)]),
    );
    // The centre is straight above the lowest vertex: no way to roll, evaluated as written.
    assert_eq!(result.resting, None);
    let support = &result.support;
    assert_eq!(support.contacts.len(), 1);
    assert_eq!(support.polygon.len(), 1);
    assert_eq!(support.edges.len(), 1);
    assert!(support.tilt_margin <= 0.0, "{}", support.tilt_margin);
    assert!(support.tilt_margin > -1e-6);
    assert!(!result.goals[0].met);

    // A ball off the axis moves the centre off the vertex: the sphere rolls onto a triangle of
    // the vertex's fan and stays there (an icosphere's triangle spans about 15° at this level).
    let c = capsule(
        0,
        Point3::new(3.0, 0.0, 5.0),
        Point3::new(3.0, 0.0, 12.0),
        2.0,
        1.5,
    );
    let result = evaluate(
        &project(&["ball"]),
        &[sphere],
        &design(vec![c]),
        &rest_pose(1, vec![stand(0.0)]),
    );
    let resting = result.resting.as_ref().expect("settles");
    assert_eq!(resting.corners, 3);
    assert!(resting.correction > 1.0 && resting.correction < 20.0);
    // The correction is the angle between the facet's normal and the written down, −z.
    assert_close(
        "correction",
        resting.correction,
        (-resting.down[2]).acos().to_degrees(),
        1e-9,
    );
    assert_eq!(result.support.polygon.len(), 3);
    assert!(result.support.tilt_margin > 0.0);
    assert!(result.goals[0].met);
}

#[test]
fn a_lying_cylinder_rolls_onto_a_side_when_its_centre_is_off_the_line() {
    // A 32-sided prism of radius 10 and length 50 turned onto its side: (x, y, z) → (x, −z, y).
    // It touches along the line x = 0, z = −10, right below the solid centre: balanced, so it is
    // evaluated as written and cannot stand.
    let lying = rotation(Vector3::x(), 90.0);
    let cylinder = prism(32, 10.0, 50.0);
    let result = evaluate(
        &project(&["cylinder"]),
        std::slice::from_ref(&cylinder),
        &design(vec![]),
        &pose(lying, vec![Isometry3::identity()], vec![stand(0.0)]),
    );
    let support = &result.support;
    assert_eq!(result.resting, None);
    assert_eq!(support.contacts.len(), 2);
    assert_eq!(support.polygon.len(), 2);
    assert!(support.tilt_margin <= 0.0, "{}", support.tilt_margin);
    assert!(!result.goals[0].met);

    // A capsule along the cylinder's axis, 4 off it: horizontal, so its ball sits at the
    // midpoint, where the void is too. The void weighs more than the ball, so the centre moves
    // by |x| to −x and the prism rolls by φ = 180°/32 onto the side face left of the line. On it
    // the centre is a − |x| sin φ high (a = 10 cos φ, the apothem) and |x| cos φ from the face's
    // middle line, whose long edges are w = 10 sin φ away.
    let c = capsule(
        0,
        Point3::new(4.0, 0.0, 10.0),
        Point3::new(4.0, 0.0, 40.0),
        3.0,
        2.5,
    );
    let void = c.volume();
    let result = evaluate(
        &project(&["cylinder"]),
        &[cylinder],
        &design(vec![c]),
        &pose(
            lying,
            vec![Isometry3::identity()],
            vec![imbalance(0.5), stand(1.0)],
        ),
    );
    let volume = 16.0 * 100.0 * (2.0 * PI / 32.0).sin() * 50.0;
    let ball = STEEL * ball_volume(2.5) / 1000.0;
    let mass = PLA * (volume - void) / 1000.0 + ball;
    let x = ((ball * 4.0 - PLA / 1000.0 * void * 4.0) / mass).abs();
    assert!(x > 0.1);
    let phi = PI / 32.0;
    let resting = result.resting.as_ref().expect("settles");
    assert_close("correction", resting.correction, phi.to_degrees(), 1e-9);
    assert_eq!(resting.corners, 4);
    assert_close(
        "tilt margin",
        result.support.tilt_margin,
        degrees_atan(
            10.0 * phi.sin() - x * phi.cos(),
            10.0 * phi.cos() - x * phi.sin(),
        ),
        1e-9,
    );
    assert_eq!(met(&result), vec![false, true]);
}

#[test]
fn y_up_projects_onto_the_xz_plane() {
    let mut project = project(&["box"]);
    project.up = Axis::Y;
    let result = evaluate(
        &project,
        &[box_mesh(40.0, 60.0, 100.0)],
        &design(vec![]),
        &rest_pose(1, vec![stand(0.0)]),
    );
    let support = &result.support;
    assert_eq!(support.polygon.len(), 4);
    assert!(support.polygon.iter().all(|p| p[1] == 0.0));
    assert!(signed_area(support, Vector3::y()) > 0.0);
    // 30 high; 20 from the x edges, 50 from the z edges.
    assert_close(
        "tilt margin",
        support.tilt_margin,
        degrees_atan(20.0, 30.0),
        1e-9,
    );
}

#[test]
fn x_up_is_counter_clockwise_from_above_too() {
    let mut project = project(&["box"]);
    project.up = Axis::X;
    let result = evaluate(
        &project,
        &[box_mesh(40.0, 60.0, 100.0)],
        &design(vec![]),
        &rest_pose(1, vec![]),
    );
    assert!(signed_area(&result.support, Vector3::x()) > 0.0);
    assert_close(
        "tilt margin",
        result.support.tilt_margin,
        degrees_atan(30.0, 20.0),
        1e-9,
    );
}

#[test]
fn the_contact_tolerance_decides_which_vertices_touch() {
    // Lift the corner (40, 0, 0) by 0.01.
    let mut mesh = box_mesh(40.0, 60.0, 100.0);
    mesh.positions[1].z = 0.01;
    let project = project(&["box"]);
    let loose = evaluate(
        &project,
        std::slice::from_ref(&mesh),
        &design(vec![]),
        &rest_pose(1, vec![stand(0.0)]),
    );
    assert_eq!(loose.support.contacts.len(), 4);
    assert_close("tolerance", loose.support.contact_tolerance, 0.05, 0.0);
    // Without a stand goal the hull's tolerance applies, 1e-6 of the extent: three corners.
    let default = evaluate(
        &project,
        std::slice::from_ref(&mesh),
        &design(vec![]),
        &rest_pose(1, vec![]),
    );
    assert_eq!(default.support.contacts.len(), 3);
    let extent = (40.0f64 * 40.0 + 60.0 * 60.0 + 100.0 * 100.0).sqrt();
    assert_close(
        "default tolerance",
        default.support.contact_tolerance,
        1e-6 * extent,
        1e-12,
    );
    // A tight tolerance leaves three corners; the centre lies near their diagonal.
    let tight = evaluate(
        &project,
        &[mesh],
        &design(vec![]),
        &rest_pose(
            1,
            vec![Goal::Stand {
                margin: 0.0,
                contact_tolerance: Some(0.001),
            }],
        ),
    );
    assert_eq!(tight.support.contacts.len(), 3);
    assert_eq!(tight.support.polygon.len(), 3);
    assert!(tight.support.tilt_margin.abs() < 0.1);
    assert!(loose.support.tilt_margin > 21.0);
}
