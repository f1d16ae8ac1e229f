//! The triangle tree gives exactly the distances of the brute-force queries.

mod geometry_support;

use ballast::geometry::{
    distance_to_point, distance_to_segment, load_mesh, MeshSelector, TriMesh, TriangleTree,
};
use geometry_support::{box_mesh, icosphere};
use nalgebra::{Point3, Vector3};

/// Deterministic points spread over (and around) the mesh's bounding box.
fn probes(mesh: &TriMesh, count: usize) -> Vec<Point3<f64>> {
    let (lo, hi) = mesh.bounding_box().unwrap();
    let margin = (hi - lo) * 0.25;
    let (lo, hi) = (lo - margin, hi + margin);
    // A low-discrepancy sequence: fractional parts of multiples of irrational steps.
    let steps = Vector3::new(0.618_033_988_75, 0.414_213_562_37, 0.732_050_807_57);
    (1..=count)
        .map(|i| {
            let t = (steps * i as f64).map(|x| x.fract());
            lo + (hi - lo).component_mul(&t)
        })
        .collect()
}

fn assert_same_distances(mesh: &TriMesh, count: usize) {
    let tree = TriangleTree::new(mesh);
    let points = probes(mesh, count);
    for p in &points {
        assert_eq!(
            tree.distance_to_point(p),
            distance_to_point(mesh, p),
            "at {p}"
        );
    }
    for pair in points.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        assert_eq!(
            tree.distance_to_segment(a, b),
            distance_to_segment(mesh, a, b),
            "from {a} to {b}"
        );
    }
}

#[test]
fn box_distances_match_brute_force() {
    assert_same_distances(&box_mesh(10.0, 20.0, 30.0), 300);
}

#[test]
fn sphere_distances_match_brute_force_and_the_closed_form() {
    let sphere = icosphere(3, 5.0, Point3::new(1.0, 2.0, 3.0));
    assert_same_distances(&sphere, 300);
    // Far from a fine sphere the distance is |p − c| − r, less the facets' sag.
    let tree = TriangleTree::new(&sphere);
    let d = tree.distance_to_point(&Point3::new(21.0, 2.0, 3.0));
    assert!((d - 15.0).abs() < 0.05, "{d}");
    // A segment through the sphere crosses its surface.
    let crossing =
        tree.distance_to_segment(&Point3::new(1.0, 2.0, 3.0), &Point3::new(20.0, 2.0, 3.0));
    assert_eq!(crossing, 0.0);
}

#[test]
fn real_mesh_distances_match_brute_force() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes/hammer.obj");
    let hammer = load_mesh(&path, &MeshSelector::Whole).unwrap();
    assert_same_distances(&hammer, 40);
}

#[test]
fn an_empty_mesh_is_infinitely_far() {
    let empty = TriMesh {
        positions: Vec::new(),
        triangles: Vec::new(),
    };
    let tree = TriangleTree::new(&empty);
    assert_eq!(tree.distance_to_point(&Point3::origin()), f64::INFINITY);
    assert_eq!(
        tree.distance_to_segment(&Point3::origin(), &Point3::new(1.0, 0.0, 0.0)),
        f64::INFINITY
    );
}
