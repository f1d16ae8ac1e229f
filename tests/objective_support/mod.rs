//! Models, seeded random designs and a finite-difference checker for the objective tests.
#![allow(dead_code)]

use ballast::balance::ComponentBody;
use ballast::design::{Design, PlacedCapsule};
use ballast::geometry::TriMesh;
use ballast::objective::{DesignLayout, Objective, Parameters};
use ballast::random::SplitMix64;
use ballast::spec::model::{Goal, Pose, Project};
use nalgebra::{Isometry3, Point3, Vector3};

use crate::balance_support::{project, rotation_about};
use crate::geometry_support::box_mesh;

/// The 40 × 60 × 100 mm box [0,40]×[0,60]×[0,100].
pub fn tall_box() -> TriMesh {
    box_mesh(40.0, 60.0, 100.0)
}

/// The two-part model of the balance tests: a 20 mm base cube and a 10 × 10 × 60 arm standing
/// on it from z = 20.
pub fn two_parts() -> Vec<TriMesh> {
    vec![
        box_mesh(20.0, 20.0, 20.0),
        box_mesh(10.0, 10.0, 60.0).transformed(&Isometry3::translation(5.0, 5.0, 20.0)),
    ]
}

/// The arm of [`two_parts`] swung by `degrees` about y around its joint (10, 10, 25).
pub fn arm_swung(degrees: f64) -> Isometry3<f64> {
    rotation_about(Vector3::y(), degrees, Point3::new(10.0, 10.0, 25.0))
}

/// A named pose.
pub fn named_pose(
    name: &str,
    transform: Isometry3<f64>,
    components: Vec<Isometry3<f64>>,
    goals: Vec<Goal>,
) -> Pose {
    let mut pose = crate::balance_support::pose(transform, components, goals);
    pose.name.value = name.to_string();
    pose
}

/// A project with the given components and poses.
pub fn project_with(components: &[&str], poses: Vec<Pose>) -> Project {
    let mut project = project(components);
    project.poses = poses;
    project
}

/// `immerse fluid-density=… min-distance=… tolerance=… mass-tolerance=…`.
pub fn immerse(fluid_density: f64, min_distance: f64, mass_tolerance: Option<f64>) -> Goal {
    Goal::Immerse {
        fluid_density,
        min_distance,
        tolerance: 10.0,
        mass_tolerance,
        unique: false,
    }
}

/// `suspend x y z component=… tolerance=5`.
pub fn suspend(point: Point3<f64>, component: usize) -> Goal {
    Goal::Suspend {
        point,
        component,
        tolerance: 5.0,
        unique: false,
    }
}

/// `goal` with `unique=#true` (a `suspend` or `immerse` goal; others are returned as they are).
pub fn unique(mut goal: Goal) -> Goal {
    if let Goal::Suspend { unique, .. } | Goal::Immerse { unique, .. } = &mut goal {
        *unique = true;
    }
    goal
}

/// A capsule of component `component` with random ends inside `[lo, hi]` (shrunk by 8 mm) and a
/// random radius in [2, 5]; when `steep`, its axis is within about 30° of z.
pub fn random_capsule(
    rng: &mut SplitMix64,
    component: usize,
    lo: Point3<f64>,
    hi: Point3<f64>,
    steep: bool,
) -> PlacedCapsule {
    let point = |rng: &mut SplitMix64| {
        Point3::new(
            rng.uniform(lo.x + 8.0, hi.x - 8.0),
            rng.uniform(lo.y + 8.0, hi.y - 8.0),
            rng.uniform(lo.z + 8.0, hi.z - 8.0),
        )
    };
    let from = point(rng);
    let mut to = point(rng);
    if steep {
        let rise = (hi.z - lo.z) * 0.5;
        to = Point3::new(
            from.x + rng.uniform(-0.25, 0.25) * rise,
            from.y + rng.uniform(-0.25, 0.25) * rise,
            from.z
                + if from.z > (lo.z + hi.z) / 2.0 {
                    -rise
                } else {
                    rise
                },
        );
    }
    let radius = rng.uniform(2.0, 5.0);
    PlacedCapsule {
        name: format!("c{component}"),
        component,
        from,
        to,
        radius,
        ball_radius: radius - 0.2,
    }
}

/// The objective of `project` for `design` with the meshes `meshes`.
pub fn objective(
    project: &Project,
    meshes: &[TriMesh],
    design: &Design,
    parameters: Parameters,
) -> Objective {
    let bodies: Vec<ComponentBody> = meshes
        .iter()
        .map(|mesh| ComponentBody::for_project(mesh, project))
        .collect();
    Objective::new(
        project,
        &bodies,
        DesignLayout::for_design(project, design),
        parameters,
    )
}

/// The relative error `|g − g_fd| / max(|g_fd|, floor)` of `gradient` against central finite
/// differences of `f` at `x` (step `1e-6 · max(1, |xᵢ|)`), with `floor` guarding gradients
/// that are zero.
pub fn finite_difference_error(
    f: &dyn Fn(&[f64]) -> f64,
    x: &[f64],
    gradient: &[f64],
    floor: f64,
) -> f64 {
    assert_eq!(gradient.len(), x.len(), "gradient length");
    let numeric: Vec<f64> = (0..x.len())
        .map(|i| {
            let h = 1e-6 * x[i].abs().max(1.0);
            let mut plus = x.to_vec();
            let mut minus = x.to_vec();
            plus[i] += h;
            minus[i] -= h;
            (f(&plus) - f(&minus)) / (plus[i] - minus[i])
        })
        .collect();
    let difference: f64 = gradient
        .iter()
        .zip(&numeric)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt();
    let scale = numeric.iter().map(|v| v * v).sum::<f64>().sqrt();
    difference / scale.max(floor)
}
