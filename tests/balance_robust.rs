//! Degenerate and inconsistent inputs: no panic, no NaN, documented stand-ins; and the JSON shape.

mod balance_support;
mod geometry_support;

use balance_support::*;
use ballast::balance::{evaluate_pose, BallRest, ComponentBody, PoseEvaluation};
use ballast::geometry::TriMesh;
use ballast::spec::model::Goal;
use geometry_support::box_mesh;
use nalgebra::{Isometry3, Point3, Vector3};

/// One goal of every kind.
fn every_goal() -> Vec<Goal> {
    vec![
        stand(0.0),
        imbalance(0.0),
        Goal::Suspend {
            point: Point3::new(0.0, 0.0, 10.0),
            component: 0,
            tolerance: 1.0,
            unique: false,
        },
        Goal::Immerse {
            fluid_density: 1.0,
            min_distance: 1.0,
            tolerance: 10.0,
            mass_tolerance: Some(1.0),
            unique: false,
        },
    ]
}

/// Asserts that the evaluation serialises without a null anywhere: serde_json writes NaN and
/// infinities as null.
fn assert_all_finite(result: &PoseEvaluation) {
    fn walk(value: &serde_json::Value, path: &str) {
        match value {
            serde_json::Value::Null => panic!("null (a non-finite number) at {path}"),
            serde_json::Value::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    walk(item, &format!("{path}[{i}]"));
                }
            }
            serde_json::Value::Object(fields) => {
                for (key, item) in fields {
                    walk(item, &format!("{path}.{key}"));
                }
            }
            _ => {}
        }
    }
    walk(&serde_json::to_value(result).unwrap(), "$");
}

fn empty_mesh() -> TriMesh {
    TriMesh {
        positions: vec![],
        triangles: vec![],
    }
}

#[test]
fn an_empty_mesh_has_no_mass_and_no_support() {
    let c = capsule(
        0,
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(0.0, 0.0, 1.0),
        1.0,
        0.5,
    );
    let result = evaluate(
        &project(&["nothing"]),
        &[empty_mesh()],
        &design(vec![c]),
        &rest_pose(1, every_goal()),
    );
    assert_all_finite(&result);
    assert_eq!(result.volume, 0.0);
    assert!(result.support.polygon.is_empty());
    assert!(result.support.edges.is_empty());
    assert_eq!(result.support.tilt_margin, -90.0);
    // Without support it cannot stand, and it does fall.
    assert_eq!(
        result.goals.iter().map(|g| g.met).collect::<Vec<_>>()[..2],
        [false, true]
    );
}

#[test]
fn a_flat_mesh_has_zero_volume_and_finite_centres() {
    // One triangle, both sides: zero volume; its centroid falls back to the bounding-box centre.
    let flat = TriMesh {
        positions: vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(2.0, 0.0, 0.0),
            Point3::new(0.0, 2.0, 0.0),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 1]],
    };
    let result = evaluate(
        &project(&["flat"]),
        &[flat],
        &design(vec![]),
        &rest_pose(1, every_goal()),
    );
    assert_all_finite(&result);
    assert_eq!(result.mass, 0.0);
    assert_point("centre", result.centre_of_mass, [1.0, 1.0, 0.0], 1e-12);
    assert_eq!(result.support.polygon.len(), 3);
    // The centre of mass is on the ground: every edge is at ±90°.
    assert!(result.support.tilt_margin.abs() <= 90.0);
}

#[test]
fn zero_infill_leaves_the_balls_alone() {
    let c = capsule(
        0,
        Point3::new(10.0, 10.0, 5.0),
        Point3::new(10.0, 10.0, 15.0),
        2.0,
        1.5,
    );
    let mut d = design(vec![c]);
    d.infill = 0.0;
    let result = evaluate(
        &project(&["cube"]),
        &[box_mesh(20.0, 20.0, 20.0)],
        &d,
        &rest_pose(1, every_goal()),
    );
    assert_all_finite(&result);
    assert_close(
        "mass",
        result.mass,
        STEEL * ball_volume(1.5) / 1000.0,
        1e-12,
    );
    assert_point("centre", result.centre_of_mass, [10.0, 10.0, 4.5], 1e-9);
}

#[test]
fn zero_infill_and_no_balls_fall_back_to_the_centroids() {
    let mut d = design(vec![]);
    d.infill = 0.0;
    let result = evaluate(
        &project(&["cube"]),
        &[box_mesh(20.0, 20.0, 20.0)],
        &d,
        &rest_pose(1, every_goal()),
    );
    assert_all_finite(&result);
    assert_eq!(result.mass, 0.0);
    assert_point("centre", result.centre_of_mass, [10.0, 10.0, 10.0], 1e-12);
}

#[test]
fn references_past_the_end_are_tolerated() {
    // No bodies at all; a capsule and a suspension point in components that do not exist; a
    // pose without component transforms.
    let project = project(&["ghost"]);
    let c = capsule(
        3,
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(0.0, 0.0, 1.0),
        1.0,
        0.5,
    );
    let mut goals = every_goal();
    goals.push(Goal::Suspend {
        point: Point3::new(1.0, 2.0, 3.0),
        component: 7,
        tolerance: 1.0,
        unique: false,
    });
    let pose = pose(Isometry3::translation(0.0, 0.0, 1.0), vec![], goals);
    let result = evaluate_pose(&project, &[], &design(vec![c]), &pose);
    assert_all_finite(&result);
    assert_eq!(result.mass, 0.0);
    assert_eq!(result.centre_of_mass, [0.0, 0.0, 0.0]);
    // The ball is still placed for the report, with the pose's own transform.
    assert_eq!(result.balls.len(), 1);
    assert_point("ball", result.balls[0].centre_world, [0.0, 0.0, 0.5], 1e-12);
}

#[test]
fn missing_component_transforms_default_to_the_identity() {
    let meshes = [box_mesh(10.0, 10.0, 10.0), box_mesh(20.0, 20.0, 20.0)];
    let project = project(&["a", "b"]);
    let bodies: Vec<ComponentBody> = meshes
        .iter()
        .map(|mesh| ComponentBody::for_project(mesh, &project))
        .collect();
    let short = pose(Isometry3::identity(), vec![Isometry3::identity()], vec![]);
    let full = rest_pose(2, vec![]);
    let a = evaluate_pose(&project, &bodies, &design(vec![]), &short);
    let b = evaluate_pose(&project, &bodies, &design(vec![]), &full);
    assert_eq!(a.centre_of_mass, b.centre_of_mass);
}

#[test]
fn odd_capsules_still_place_their_balls() {
    let zero_length = capsule(
        0,
        Point3::new(10.0, 10.0, 10.0),
        Point3::new(10.0, 10.0, 10.0),
        3.0,
        2.0,
    );
    let oversized_ball = capsule(
        0,
        Point3::new(5.0, 5.0, 5.0),
        Point3::new(5.0, 5.0, 15.0),
        1.0,
        2.0,
    );
    let result = evaluate(
        &project(&["cube"]),
        &[box_mesh(20.0, 20.0, 20.0)],
        &design(vec![zero_length, oversized_ball.clone()]),
        &pose(
            rotation(Vector3::x(), 90.0),
            vec![Isometry3::identity()],
            every_goal(),
        ),
    );
    assert_all_finite(&result);
    // A spherical cavity: the ball sits at its bottom. Turned 90° about x, gravity in the rest
    // frame is −y.
    let sphere = &result.balls[0];
    assert_eq!(sphere.rest, BallRest::From);
    assert_point("sphere", sphere.centre, [10.0, 9.0, 10.0], 1e-12);
    // Here the second capsule's axis is level.
    assert_eq!(result.balls[1].rest, BallRest::Undetermined);

    // Upright, a ball larger than its capsule stays at the axis end instead of rising above it.
    let upright = evaluate(
        &project(&["cube"]),
        &[box_mesh(20.0, 20.0, 20.0)],
        &design(vec![oversized_ball]),
        &rest_pose(1, vec![]),
    );
    assert_eq!(upright.balls[0].rest, BallRest::From);
    assert_point("oversized", upright.balls[0].centre, [5.0, 5.0, 5.0], 0.0);
}

#[test]
fn a_negative_contact_tolerance_counts_as_zero() {
    let result = evaluate(
        &project(&["box"]),
        &[box_mesh(10.0, 10.0, 10.0)],
        &design(vec![]),
        &rest_pose(
            1,
            vec![Goal::Stand {
                margin: 0.0,
                contact_tolerance: Some(-1.0),
            }],
        ),
    );
    assert_eq!(result.support.contact_tolerance, 0.0);
    assert_eq!(result.support.contacts.len(), 4);
    assert!(result.goals[0].met);
}

#[test]
fn the_evaluation_serialises_with_named_kinds() {
    let c = capsule(
        0,
        Point3::new(10.0, 10.0, 5.0),
        Point3::new(10.0, 10.0, 15.0),
        2.0,
        1.5,
    );
    let mut goals = every_goal();
    goals.push(Goal::Immerse {
        fluid_density: 1.0,
        min_distance: 0.0,
        tolerance: 10.0,
        mass_tolerance: None,
        unique: false,
    });
    let result = evaluate(
        &project(&["cube"]),
        &[box_mesh(20.0, 20.0, 20.0)],
        &design(vec![c]),
        &rest_pose(1, goals),
    );
    let json = serde_json::to_value(&result).unwrap();
    assert_eq!(json["pose"], "pose");
    assert_eq!(json["balls"][0]["rest"], "from");
    let kinds: Vec<&str> = json["goals"]
        .as_array()
        .unwrap()
        .iter()
        .map(|goal| goal["kind"].as_str().unwrap())
        .collect();
    assert_eq!(
        kinds,
        ["stand", "imbalance", "suspend", "immerse", "immerse"]
    );
    assert_eq!(json["goals"][0]["met"], true);
    assert_eq!(json["goals"][3]["mass_tolerance"], 1.0);
    assert!(json["goals"][4].get("mass_tolerance").is_none());
    assert_eq!(json["support"]["polygon"].as_array().unwrap().len(), 4);
    assert!(json["support"]["tilt_margin"].is_f64());
}
