//! The smooth formulation against the exact evaluation of `balance`: with a very sharp ball
//! sigmoid and capsules far from horizontal, the same centre of mass and the same verdict.

mod balance_support;
mod geometry_support;
mod objective_support;

use balance_support::{rotation, stand};
use ballast::balance::{evaluate_pose, ComponentBody};
use ballast::design::Design;
use ballast::geometry::TriMesh;
use ballast::objective::Parameters;
use ballast::random::SplitMix64;
use ballast::spec::model::{Print, Project, Units};
use nalgebra::{Isometry3, Point3, Vector3};
use objective_support::*;

/// Parameters with a ball sigmoid sharp enough to be a step and sharp edge minima.
fn sharp(project: &Project) -> Parameters {
    Parameters {
        ball_sharpness: 1e6,
        edge_sharpness: 1e5,
        ..Parameters::for_project(project)
    }
}

/// Asserts that the smooth centre of mass of every pose equals the exact one to 1e-6 of the
/// model's size, and returns the exact tilt margins (degrees) with the smooth stand objectives.
fn compare(project: &Project, meshes: &[TriMesh], design: &Design, size: f64) -> Vec<(f64, f64)> {
    let bodies: Vec<ComponentBody> = meshes
        .iter()
        .map(|mesh| ComponentBody::for_project(mesh, project))
        .collect();
    let objective = objective(project, meshes, design, sharp(project));
    let x = objective.layout().to_vector(design);
    let rebuilt = objective
        .layout()
        .to_design(&x, &project.ball, project.infill.value);
    let mut verdicts = Vec::new();
    for (i, pose) in project.poses.iter().enumerate() {
        let exact = evaluate_pose(project, &bodies, &rebuilt, pose);
        let (centre, mass) = objective.mass_properties(i, &x).expect("pose");
        let difference = (centre - Point3::from(exact.centre_of_mass)).norm();
        assert!(
            difference <= 1e-6 * size,
            "{}: centre {centre} vs {:?}",
            pose.name.value,
            exact.centre_of_mass
        );
        assert!((mass - exact.mass).abs() <= 1e-9 * exact.mass.abs().max(1.0));
        let terms = objective.goal_terms(&x);
        verdicts.push((exact.support.tilt_margin, terms[i].0));
    }
    verdicts
}

fn box_project(poses: Vec<(&str, Isometry3<f64>)>) -> Project {
    project_with(
        &["box"],
        poses
            .into_iter()
            .map(|(name, t)| named_pose(name, t, vec![Isometry3::identity()], vec![stand(0.0)]))
            .collect(),
    )
}

#[test]
fn the_box_with_steep_capsules_has_the_exact_centre_and_verdict() {
    let project = box_project(vec![
        ("upright", Isometry3::identity()),
        ("upside down", rotation(Vector3::x(), 180.0)),
    ]);
    for seed in 1..=6 {
        // Even seeds print the box as a slicer does (solid shells, a shell per capsule).
        let mut project = project.clone();
        if seed % 2 == 0 {
            project.print = Print::defaults(Units::Millimetre);
        }
        let mut rng = SplitMix64::new(seed);
        let design = Design {
            capsules: (0..3)
                .map(|_| {
                    random_capsule(
                        &mut rng,
                        0,
                        Point3::origin(),
                        Point3::new(40.0, 60.0, 100.0),
                        true,
                    )
                })
                .collect(),
            infill: 0.3,
        };
        let verdicts = compare(&project, &[tall_box()], &design, 100.0);
        // Both poses put a face on the ground, so both formulations evaluate the same frames (a
        // face turned to the side would lay the steep capsules flat).
        for (pose, (tilt, stand_objective)) in project.poses.iter().zip(verdicts) {
            assert_eq!(
                stand_objective < 0.0,
                tilt > 0.0,
                "{}: tilt margin {tilt}°, smooth objective {stand_objective}",
                pose.name.value
            );
        }
    }
}

#[test]
fn the_two_part_model_has_the_exact_centre_and_verdict() {
    // Within 72° of upright, so no capsule comes within 3.5° of horizontal, and the base's
    // bottom stays the facet on the ground (swung much further, the arm would reach below it and
    // the model would roll); swung past 69°, the solid model's centre passes the base's edge.
    let angles = [0.0, 20.0, 45.0, 60.0, 72.0, -30.0, -60.0, -72.0];
    let project = project_with(
        &["base", "arm"],
        angles
            .iter()
            .map(|a| {
                named_pose(
                    &format!("arm {a}"),
                    Isometry3::identity(),
                    vec![Isometry3::identity(), arm_swung(*a)],
                    vec![stand(0.0)],
                )
            })
            .collect(),
    );
    let mut stands = 0;
    let mut topples = 0;
    // Seed 0: the solid model, which topples with the arm swung 72° either way.
    for seed in 0..=4 {
        let mut rng = SplitMix64::new(seed);
        let design = Design {
            capsules: (seed > 0)
                .then(|| {
                    random_capsule(
                        &mut rng,
                        1,
                        Point3::new(-3.0, -3.0, 20.0),
                        Point3::new(23.0, 23.0, 80.0),
                        true,
                    )
                })
                .into_iter()
                .collect(),
            infill: 1.0,
        };
        for (tilt, stand_objective) in compare(&project, &two_parts(), &design, 80.0) {
            // The smooth objective is at most 0 exactly when the exact margin is positive.
            assert_eq!(
                stand_objective < 0.0,
                tilt > 0.0,
                "tilt margin {tilt}°, smooth objective {stand_objective}"
            );
            if tilt > 0.0 {
                stands += 1;
            } else {
                topples += 1;
            }
        }
    }
    assert!(
        stands > 0 && topples > 0,
        "{stands} stand, {topples} topple"
    );
}

#[test]
fn a_box_on_an_edge_settles_onto_the_same_face_in_both_formulations() {
    // Resting on an edge, the solid box rolls onto a face: the objective (settled with the solid
    // centre) and the exact evaluation (the design's, here the same) put the same face down.
    let project = box_project(vec![("on an edge", rotation(Vector3::x(), 30.0))]);
    let verdicts = compare(
        &project,
        &[tall_box()],
        &Design {
            capsules: vec![],
            infill: 1.0,
        },
        100.0,
    );
    assert!(verdicts[0].0 > 0.0);
    assert!(verdicts[0].1 < 0.0);
}
