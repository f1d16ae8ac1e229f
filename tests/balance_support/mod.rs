//! Projects, poses and designs built in code, for the physics tests.
#![allow(dead_code)]

use std::path::PathBuf;

use ballast::balance::{evaluate_pose, ComponentBody, PoseEvaluation};
use ballast::design::{Design, PlacedCapsule};
use ballast::geometry::{MeshSelector, TriMesh};
use ballast::spec::model::{
    Axis, Ball, Component, Goal, Infill, MassModel, Material, MeshFrame, Output, Pose, Print,
    Project, Spanned, Units,
};
use miette::SourceSpan;
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

/// Density of the printed material in these tests (PLA), g/cm³.
pub const PLA: f64 = 1.24;
/// Density of the balls (steel), g/cm³.
pub const STEEL: f64 = 7.85;
/// The projects' minimum capsule elevation, degrees.
pub const MIN_ANGLE: f64 = 3.0;

/// An empty span: these projects have no source text.
pub fn span() -> SourceSpan {
    (0, 0).into()
}

/// A project in millimetres with z up, PLA, steel balls, solid infill, and one component per
/// name. It has no poses or capsules: the tests pass those to `evaluate_pose` directly.
pub fn project(components: &[&str]) -> Project {
    Project {
        units: Units::Millimetre,
        up: Axis::Z,
        material: Material {
            name: "PLA".to_string(),
            density: PLA,
        },
        ball: Ball {
            density: STEEL,
            clearance: 0.2,
            pause_clearance: 0.2,
            min_angle: MIN_ANGLE,
            diameters: Vec::new(),
        },
        infill: Infill {
            value: 1.0,
            range: None,
        },
        wall: 1.0,
        // The hand computations here are of uniform material at the infill fraction.
        print: Print {
            model: MassModel::Uniform,
            ..Print::defaults(Units::Millimetre)
        },
        components: components
            .iter()
            .map(|name| Component {
                name: Spanned::new(name.to_string(), span()),
                mesh: Spanned::new(PathBuf::from(format!("{name}.obj")), span()),
                selector: MeshSelector::Whole,
                frame: MeshFrame::project(Units::Millimetre, Axis::Z),
                print: None,
                span: span(),
            })
            .collect(),
        poses: Vec::new(),
        capsules: Vec::new(),
        optimize: None,
        output: Output {
            gltf: PathBuf::from("out.glb"),
            report: PathBuf::from("report.json"),
            solution: PathBuf::from("solution.kdl"),
            stl: PathBuf::from("stl"),
            prusa: PathBuf::from("model.3mf"),
            sheet: PathBuf::from("insertion.md"),
        },
    }
}

/// A pose with the whole-model transform `transform`, per-component transforms and goals.
pub fn pose(transform: Isometry3<f64>, components: Vec<Isometry3<f64>>, goals: Vec<Goal>) -> Pose {
    Pose {
        name: Spanned::new("pose".to_string(), span()),
        transform,
        down: None,
        component_transforms: components,
        goals: goals.into_iter().map(|g| Spanned::new(g, span())).collect(),
        span: span(),
    }
}

/// The rest pose of a model with `components` components, with `goals`.
pub fn rest_pose(components: usize, goals: Vec<Goal>) -> Pose {
    pose(
        Isometry3::identity(),
        vec![Isometry3::identity(); components],
        goals,
    )
}

/// A rotation by `degrees` about `axis` through the origin.
pub fn rotation(axis: Vector3<f64>, degrees: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), degrees.to_radians()),
    )
}

/// A rotation by `degrees` about the line through `pivot` along `axis`.
pub fn rotation_about(axis: Vector3<f64>, degrees: f64, pivot: Point3<f64>) -> Isometry3<f64> {
    Isometry3::translation(pivot.x, pivot.y, pivot.z)
        * rotation(axis, degrees)
        * Isometry3::translation(-pivot.x, -pivot.y, -pivot.z)
}

/// A capsule in component `component` with a ball of `ball_radius`.
pub fn capsule(
    component: usize,
    from: Point3<f64>,
    to: Point3<f64>,
    radius: f64,
    ball_radius: f64,
) -> PlacedCapsule {
    PlacedCapsule {
        name: format!("c{component}"),
        component,
        from,
        to,
        radius,
        ball_radius,
    }
}

/// A design with solid infill.
pub fn design(capsules: Vec<PlacedCapsule>) -> Design {
    Design {
        capsules,
        infill: 1.0,
    }
}

/// `stand margin=… contact-tolerance=0.05`.
pub fn stand(margin: f64) -> Goal {
    Goal::Stand {
        margin,
        contact_tolerance: Some(0.05),
    }
}

/// `imbalance margin=… contact-tolerance=0.05`.
pub fn imbalance(margin: f64) -> Goal {
    Goal::Imbalance {
        margin,
        contact_tolerance: Some(0.05),
    }
}

/// Evaluates `pose` of the model made of `meshes` (component i from mesh i).
pub fn evaluate(
    project: &Project,
    meshes: &[TriMesh],
    design: &Design,
    pose: &Pose,
) -> PoseEvaluation {
    let bodies: Vec<ComponentBody> = meshes
        .iter()
        .map(|mesh| ComponentBody::for_project(mesh, project))
        .collect();
    evaluate_pose(project, &bodies, design, pose)
}

/// Volume of a ball of radius `r`.
pub fn ball_volume(r: f64) -> f64 {
    4.0 / 3.0 * std::f64::consts::PI * r.powi(3)
}

/// Asserts `|actual − expected| ≤ tolerance`, naming `what`.
pub fn assert_close(what: &str, actual: f64, expected: f64, tolerance: f64) {
    assert!(
        (actual - expected).abs() <= tolerance,
        "{what}: got {actual}, expected {expected} (± {tolerance})"
    );
}

/// Asserts two points agree to `tolerance` in every coordinate.
pub fn assert_point(what: &str, actual: [f64; 3], expected: [f64; 3], tolerance: f64) {
    for axis in 0..3 {
        assert_close(
            &format!("{what}[{axis}]"),
            actual[axis],
            expected[axis],
            tolerance,
        );
    }
}
