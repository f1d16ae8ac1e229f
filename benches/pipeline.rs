//! The per-mesh pipeline on a real model: load, mass properties, evaluating poses with two
//! capsules, and enumerating the stable states of a hanging pose with up to 12, each beside a baseline (one pass summing every vertex coordinate) measured in the
//! same process so results can be read as ratios. `docs/benchmarks.md` describes the figures.
//!
//! The convex hull of the same meshes and of a 1M-triangle sphere (`-- hull`).
//!
//! Run with `cargo bench --bench pipeline`. Meshes come from `../shared/meshes` beside the
//! checkout; a mesh that is missing is skipped with a note. The stable states use the example
//! hammer in `examples/meshes` (`cargo bench --bench pipeline -- equilibria`).

mod support;

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Duration;

use ballast::balance::{evaluate_pose, ComponentBody};
use ballast::design::{Design, PlacedCapsule};
use ballast::geometry::{
    convex_hull, distance_to_point, load_mesh, mass_properties, DistanceGrid, MeshSelector,
    Skeleton, TriMesh, TriangleTree,
};
use ballast::spec::model::{
    Axis, Ball, Component, Goal, Infill, Material, MeshFrame, Output, Pose, Print, Project,
    Spanned, Units,
};
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use support::sum_coordinates;

/// The meshes measured: (label, path under `../shared/meshes`).
const MESHES: [(&str, &str); 2] = [
    ("hammer_60k", "hammer.obj"),
    ("hammer_240k", "large/hammer_240k.obj"),
];

fn shared_mesh(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/meshes")
        .join(relative)
}

/// A one-component project in centimetres, z up, PLA and steel balls.
fn project() -> Project {
    let span = miette::SourceSpan::from((0, 0));
    Project {
        units: Units::Centimetre,
        up: Axis::Z,
        material: Material {
            name: "PLA".to_string(),
            density: 1.24,
        },
        ball: Ball {
            density: 7.85,
            clearance: 0.02,
            pause_clearance: 0.02,
            min_angle: 3.0,
            diameters: Vec::new(),
        },
        infill: Infill {
            value: 1.0,
            range: None,
        },
        wall: 0.1,
        print: Print::defaults(Units::Millimetre),
        components: vec![Component {
            name: Spanned::new("hammer".to_string(), span),
            mesh: Spanned::new(PathBuf::from("hammer.obj"), span),
            selector: MeshSelector::Whole,
            frame: MeshFrame::project(Units::Centimetre, Axis::Z),
            print: None,
            span,
        }],
        poses: Vec::new(),
        capsules: Vec::new(),
        optimize: None,
        output: Output {
            gltf: PathBuf::from("hammer.glb"),
            report: PathBuf::from("hammer.json"),
            solution: PathBuf::from("hammer.solution.kdl"),
            stl: PathBuf::from("hammer-stl"),
            prusa: PathBuf::from("hammer.3mf"),
            sheet: PathBuf::from("hammer.insertion.md"),
        },
    }
}

/// Two capsules through the centroid: one along z, one along x.
fn design(centroid: Point3<f64>) -> Design {
    let capsule = |name: &str, axis: Vector3<f64>| PlacedCapsule {
        name: name.to_string(),
        component: 0,
        from: centroid - axis,
        to: centroid + axis,
        radius: 0.15,
        ball_radius: 0.13,
    };
    Design {
        capsules: vec![
            capsule("shaft", Vector3::new(0.0, 0.0, 1.0)),
            capsule("head", Vector3::new(0.6, 0.0, 0.3)),
        ],
        infill: 0.8,
    }
}

/// `count` short capsules around `centroid`, each tilted a different way, so their balls roll at
/// different tilts.
fn capsules_around(centroid: Point3<f64>, count: usize) -> Design {
    let capsules = (0..count)
        .map(|i| {
            let turn = i as f64 * 2.4;
            let axis = Vector3::new(turn.cos(), turn.sin(), 0.05 + 0.02 * i as f64) * 0.3;
            let centre = centroid + Vector3::new(0.0, 0.0, 0.1 * i as f64 - 0.8);
            PlacedCapsule {
                name: format!("c{i}"),
                component: 0,
                from: centre - axis,
                to: centre + axis,
                radius: 0.15,
                ball_radius: 0.13,
            }
        })
        .collect();
    Design {
        capsules,
        infill: 0.8,
    }
}

/// Four poses (upright, on its side, upside down, tilted), each with one goal of every kind.
fn poses(suspension: Point3<f64>) -> Vec<(&'static str, Pose)> {
    let span = miette::SourceSpan::from((0, 0));
    let goals = [
        Goal::Stand {
            margin: 2.0,
            contact_tolerance: Some(0.005),
        },
        Goal::Imbalance {
            margin: 2.0,
            contact_tolerance: Some(0.005),
        },
        Goal::Suspend {
            point: suspension,
            component: 0,
            tolerance: 2.0,
            unique: false,
        },
        Goal::Immerse {
            fluid_density: 1.0,
            min_distance: 0.1,
            tolerance: 5.0,
            mass_tolerance: Some(1.0),
            unique: false,
        },
    ];
    let turned = |axis: Vector3<f64>, degrees: f64| {
        Isometry3::from_parts(
            Translation3::identity(),
            UnitQuaternion::from_axis_angle(
                &nalgebra::Unit::new_normalize(axis),
                degrees.to_radians(),
            ),
        )
    };
    [
        ("upright", Isometry3::identity()),
        ("side", turned(Vector3::x(), 90.0)),
        ("upside-down", turned(Vector3::x(), 180.0)),
        ("tilted", turned(Vector3::new(1.0, 1.0, 0.0), 30.0)),
    ]
    .into_iter()
    .map(|(name, transform)| {
        let pose = Pose {
            name: Spanned::new(name.to_string(), span),
            transform,
            down: None,
            component_transforms: vec![Isometry3::identity()],
            goals: goals
                .iter()
                .map(|goal| Spanned::new(goal.clone(), span))
                .collect(),
            span,
        };
        (name, pose)
    })
    .collect()
}

/// Every stable state of a hanging goal (2^n assignments of ball ends) against the same pose
/// without goals, for n capsules, on the example hammer (in the repository, 4 k vertices).
fn equilibria(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes/hammer.obj");
    let mesh = match load_mesh(&path, &MeshSelector::Whole) {
        Ok(mesh) => mesh,
        Err(error) => {
            eprintln!("note: skipping equilibria: {error}");
            return;
        }
    };
    let mass = mass_properties(&mesh);
    let project = project();
    let top = mesh
        .positions
        .iter()
        .map(|p| p.z)
        .fold(f64::NEG_INFINITY, f64::max);
    let poses = poses(Point3::new(mass.centroid.x, mass.centroid.y, top));
    let (hanging, bare) = hanging(&poses[0].1);
    let bodies = [ComponentBody::for_project(&mesh, &project)];
    let mut group = c.benchmark_group("equilibria");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(2));
    for count in [1, 4, 8, 12] {
        let many = fan(mass.centroid, count);
        group.bench_function(format!("{count}/suspend"), |b| {
            b.iter(|| evaluate_pose(&project, black_box(&bodies), &many, &hanging))
        });
        group.bench_function(format!("{count}/no_goal"), |b| {
            b.iter(|| evaluate_pose(&project, black_box(&bodies), &many, &bare))
        });
    }
    group.finish();
}

/// `count` short capsules through the centroid, their axes fanned out from z.
fn fan(centroid: Point3<f64>, count: usize) -> Design {
    let capsules = (0..count)
        .map(|j| {
            let turn = j as f64 * std::f64::consts::TAU / count as f64;
            let axis = Vector3::new(0.3 * turn.cos(), 0.3 * turn.sin(), 0.5);
            PlacedCapsule {
                name: format!("c{j}"),
                component: 0,
                from: centroid - axis,
                to: centroid + axis,
                radius: 0.15,
                ball_radius: 0.13,
            }
        })
        .collect();
    Design {
        capsules,
        infill: 0.8,
    }
}

/// `pose` with only its suspend goal, and without goals.
fn hanging(pose: &Pose) -> (Pose, Pose) {
    let mut hanging = pose.clone();
    hanging
        .goals
        .retain(|goal| matches!(goal.value, Goal::Suspend { .. }));
    let mut bare = pose.clone();
    bare.goals.clear();
    (hanging, bare)
}

fn pipeline(c: &mut Criterion) {
    for (label, relative) in MESHES {
        let path = shared_mesh(relative);
        let mesh = match load_mesh(&path, &MeshSelector::Whole) {
            Ok(mesh) => mesh,
            Err(error) => {
                eprintln!("note: skipping {label}: {error}");
                continue;
            }
        };
        eprintln!(
            "{label}: {} vertices, {} triangles",
            mesh.positions.len(),
            mesh.triangles.len()
        );
        let mass = mass_properties(&mesh);
        let project = project();
        let design = design(mass.centroid);
        let top = mesh
            .positions
            .iter()
            .map(|p| p.z)
            .fold(f64::NEG_INFINITY, f64::max);
        let poses = poses(Point3::new(mass.centroid.x, mass.centroid.y, top));
        let bodies = [ComponentBody::for_project(&mesh, &project)];
        for (name, pose) in &poses {
            let result = evaluate_pose(&project, &bodies, &design, pose);
            eprintln!(
                "  {name}: {} contacts, {}-point support, tilt margin {:.2}°",
                result.support.contacts.len(),
                result.support.polygon.len(),
                result.support.tilt_margin
            );
        }

        let mut group = c.benchmark_group(label);
        group
            .sample_size(10)
            .warm_up_time(Duration::from_secs(1))
            .measurement_time(Duration::from_secs(3));
        group.bench_function("baseline", |b| b.iter(|| sum_coordinates(black_box(&mesh))));
        group.bench_function("load", |b| {
            b.iter(|| load_mesh(black_box(&path), &MeshSelector::Whole).map(|m| m.triangles.len()))
        });
        group.bench_function("mass_properties", |b| {
            b.iter(|| mass_properties(black_box(&mesh)))
        });
        for (name, pose) in &poses {
            group.bench_function(format!("evaluate_pose/{name}"), |b| {
                b.iter(|| evaluate_pose(&project, black_box(&bodies), &design, pose))
            });
        }
        // The tilt margin with rolling balls: one stand pose, by capsule count.
        let upright = &poses[0].1;
        let stand_only = Pose {
            goals: upright.goals[..1].to_vec(),
            ..upright.clone()
        };
        for count in [0, 1, 4, 16] {
            let many = capsules_around(mass.centroid, count);
            group.bench_function(format!("evaluate_pose/stand/{count}_capsules"), |b| {
                b.iter(|| evaluate_pose(&project, black_box(&bodies), &many, &stand_only))
            });
        }
        // An imbalance goal alone: a pose that topples on its facet is also set down on slopes,
        // to see whether it only rocks onto a neighbouring facet (balance::rocking).
        for (name, pose) in &poses {
            let toppling = Pose {
                goals: pose.goals[1..2].to_vec(),
                ..pose.clone()
            };
            let result = evaluate_pose(&project, &bodies, &design, &toppling);
            eprintln!(
                "  {name}, imbalance only: tilt margin {:.2}°",
                result.support.tilt_margin
            );
            group.bench_function(format!("evaluate_pose/imbalance/{name}"), |b| {
                b.iter(|| evaluate_pose(&project, black_box(&bodies), &design, &toppling))
            });
        }
        // Distance queries: one point near the centroid, brute force against the tree.
        let probe = mass.centroid + nalgebra::Vector3::new(0.01, 0.02, 0.03);
        group.bench_function("distance/brute_force", |b| {
            b.iter(|| distance_to_point(black_box(&mesh), &probe))
        });
        group.bench_function("distance/tree_build", |b| {
            b.iter(|| TriangleTree::new(black_box(&mesh)))
        });
        let tree = TriangleTree::new(&mesh);
        group.bench_function("distance/tree_query", |b| {
            b.iter(|| tree.distance_to_point(black_box(&probe)))
        });
        // Signed distance grid with 0.5 mm cells (a capsule radius of 1 mm).
        let cell = DistanceGrid::cell_for_radius(0.1);
        let grid = DistanceGrid::new(&mesh, cell);
        eprintln!("  field: {:?} nodes, cell {cell}", grid.dims());
        group.bench_function("field/build", |b| {
            b.iter(|| DistanceGrid::new(black_box(&mesh), cell))
        });
        // Curve skeleton on its own grids (the capsule seeds).
        eprintln!(
            "  skeleton: {} segments",
            Skeleton::new(&mesh).segments.len()
        );
        group.bench_function("skeleton/new", |b| {
            b.iter(|| Skeleton::new(black_box(&mesh)))
        });
        group.finish();
    }
}

/// The vertices of a UV sphere of radius 40 with `rings` rings of `around` points (and its two
/// poles): `2 × rings × around` triangles, every vertex on the convex hull, the hull's worst
/// case for the work per point.
fn sphere(rings: usize, around: usize) -> TriMesh {
    let mut positions = vec![Point3::new(0.0, 0.0, 40.0)];
    for ring in 1..rings {
        let theta = std::f64::consts::PI * ring as f64 / rings as f64;
        for k in 0..around {
            let phi = std::f64::consts::TAU * k as f64 / around as f64;
            positions.push(Point3::new(
                40.0 * theta.sin() * phi.cos(),
                40.0 * theta.sin() * phi.sin(),
                40.0 * theta.cos(),
            ));
        }
    }
    positions.push(Point3::new(0.0, 0.0, -40.0));
    TriMesh {
        positions,
        triangles: Vec::new(),
    }
}

/// The convex hull of the hammers' vertices and of a 1M-triangle sphere's (every vertex on the
/// hull), beside the baseline: that the hull of a million-triangle mesh finishes, and how its
/// time grows with the points (O(n log n)).
fn hull(c: &mut Criterion) {
    let mut sets = vec![("sphere_1m".to_string(), sphere(708, 708))];
    for (label, relative) in MESHES {
        match load_mesh(&shared_mesh(relative), &MeshSelector::Whole) {
            Ok(mesh) => sets.push((label.to_string(), mesh)),
            Err(error) => eprintln!("note: skipping {label}: {error}"),
        }
    }
    let mut group = c.benchmark_group("hull");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    for (label, mesh) in &sets {
        let facets = convex_hull(&mesh.positions).map_or(0, |hull| hull.facets.len());
        eprintln!(
            "{label}: {} points, {facets} hull facets",
            mesh.positions.len()
        );
        group.bench_function(format!("{label}/baseline"), |b| {
            b.iter(|| sum_coordinates(black_box(mesh)))
        });
        group.bench_function(format!("{label}/convex_hull"), |b| {
            b.iter(|| convex_hull(black_box(&mesh.positions)).map(|h| h.facets.len()))
        });
    }
    group.finish();
}

criterion_group!(benches, pipeline, equilibria, hull);
criterion_main!(benches);
