//! Mesh checks: holes, orientation, inversion, degenerate triangles.

mod geometry_support;

use ballast::geometry::{check_mesh, load_mesh, load_mesh_with, MeshSelector, ReadPolicy, TriMesh};
use geometry_support::{icosphere, shared_mesh, unit_cube};
use nalgebra::Point3;

#[test]
fn closed_cube_is_clean() {
    let check = check_mesh(&unit_cube());
    assert!(check.is_closed() && check.is_oriented() && !check.is_inverted());
    assert!(check.boundary_edges.is_empty());
    assert!(check.non_manifold_edges.is_empty());
    assert!(check.misoriented_edges.is_empty());
    assert!(check.degenerate_triangles.is_empty());
    assert_eq!(check.signed_volume, 1.0);
}

#[test]
fn cube_missing_a_triangle_has_three_boundary_edges() {
    let mut cube = unit_cube();
    let [a, b, c] = cube.triangles.remove(4);
    let check = check_mesh(&cube);
    let mut expected = vec![
        [a.min(b), a.max(b)],
        [b.min(c), b.max(c)],
        [c.min(a), c.max(a)],
    ];
    expected.sort();
    assert_eq!(check.boundary_edges, expected);
    assert!(!check.is_closed());
    assert!(check.is_oriented());
    assert!(check.non_manifold_edges.is_empty());
}

#[test]
fn cube_with_one_flipped_triangle_is_misoriented() {
    let mut cube = unit_cube();
    cube.triangles[0].swap(1, 2);
    let check = check_mesh(&cube);
    assert!(check.is_closed(), "every edge still has two triangles");
    assert!(!check.is_oriented());
    // All three edges of the flipped triangle now run the same way as their neighbours'.
    let [a, b, c] = cube.triangles[0];
    let mut expected = vec![
        [a.min(b), a.max(b)],
        [b.min(c), b.max(c)],
        [c.min(a), c.max(a)],
    ];
    expected.sort();
    assert_eq!(check.misoriented_edges, expected);
}

#[test]
fn fully_flipped_cube_is_inverted_but_consistent() {
    let mut cube = unit_cube();
    for t in &mut cube.triangles {
        t.swap(0, 1);
    }
    let check = check_mesh(&cube);
    assert!(check.is_closed() && check.is_oriented());
    assert!(check.is_inverted());
    assert_eq!(check.signed_volume, -1.0);
}

#[test]
fn degenerate_triangles_are_reported() {
    let mut cube = unit_cube();
    let n = cube.positions.len() as u32;
    // A sliver on three collinear points, one with a repeated index, one past the positions.
    cube.positions.push(Point3::new(2.0, 0.0, 0.0));
    cube.positions.push(Point3::new(3.0, 0.0, 0.0));
    cube.positions.push(Point3::new(4.0, 0.0, 0.0));
    cube.triangles.push([n, n + 1, n + 2]);
    cube.triangles.push([0, 0, 1]);
    cube.triangles.push([0, 1, 99]);
    let check = check_mesh(&cube);
    assert_eq!(check.degenerate_triangles, vec![12, 13, 14]);
    // The collinear triangle still has edges, all on the boundary.
    assert_eq!(
        check.boundary_edges,
        vec![[n, n + 1], [n, n + 2], [n + 1, n + 2]]
    );
    assert_eq!(check.signed_volume, 1.0);
}

#[test]
fn fin_on_a_cube_edge_is_non_manifold() {
    let mut cube = unit_cube();
    // A flap hanging off the cube's edge 0–1 (x axis): the edge now has three triangles.
    cube.positions.push(Point3::new(0.5, -1.0, -1.0));
    cube.triangles.push([0, 1, 8]);
    let check = check_mesh(&cube);
    assert_eq!(check.non_manifold_edges, vec![[0, 1]]);
    assert!(!check.is_closed());
}

#[test]
fn edge_lists_are_sorted_and_deterministic() {
    let mut sphere = icosphere(3, 1.0, Point3::origin());
    sphere
        .triangles
        .retain(|t| !t.contains(&0) && !t.contains(&7));
    let first = check_mesh(&sphere);
    assert!(first.boundary_edges.len() > 5);
    assert!(first.boundary_edges.windows(2).all(|w| w[0] < w[1]));
    assert!(first.boundary_edges.iter().all(|e| e[0] < e[1]));
    for _ in 0..3 {
        assert_eq!(check_mesh(&sphere), first);
    }
}

#[test]
fn empty_mesh_has_nothing_to_report() {
    let check = check_mesh(&TriMesh {
        positions: vec![],
        triangles: vec![],
    });
    assert_eq!(check, Default::default());
}

#[test]
fn poppy_abdomen_is_open_and_loads_capped() {
    let Some(path) = shared_mesh("poppy_humanoid_parts/abdomen.obj") else {
        return;
    };
    let loaded = load_mesh_with(
        &path,
        &MeshSelector::Whole,
        &ReadPolicy::within(path.parent().unwrap()),
    )
    .unwrap();
    assert!(!loaded.repairs.holes.is_empty());
    let check = check_mesh(&loaded.mesh);
    assert!(check.is_closed(), "{check:?}");
}

#[test]
fn real_single_body_meshes_are_clean() {
    for name in [
        "bunny.obj",
        "fandisk.obj",
        "rocker_arm.obj",
        "blub_fish.obj",
        "boat.obj",
    ] {
        let Some(path) = shared_mesh(name) else {
            return;
        };
        let check = check_mesh(&load_mesh(&path, &MeshSelector::Whole).unwrap());
        assert!(
            check.is_closed() && check.is_oriented() && !check.is_inverted(),
            "{name}"
        );
        assert!(check.degenerate_triangles.is_empty(), "{name}");
    }
}

fn solid_fixture(name: &str) -> TriMesh {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/compile/err/meshes")
        .join(name);
    load_mesh(&path, &MeshSelector::Whole).unwrap()
}

#[test]
fn overlapping_cubes_cross_and_their_signed_volume_is_not_the_solid_s() {
    let check = check_mesh(&solid_fixture("overlapping_cubes.obj"));
    // Closed and oriented, so the old checks pass; the signed volume counts the overlap twice.
    assert!(check.is_closed() && check.is_oriented() && !check.is_inverted());
    assert!((check.signed_volume - 2000.0).abs() < 1e-9);
    assert!(!check.is_solid());
    assert!(!check.crossing_triangles.is_empty());
    assert!(!check.shells_unchecked);
    // Every crossing pair joins the two cubes (triangles 0-11 and 12-23).
    for &[a, b] in &check.crossing_triangles {
        assert!(a < 12 && b >= 12, "{a} {b}");
    }
}

#[test]
fn a_cube_inside_a_cube_both_outward_is_a_nesting_fault() {
    let check = check_mesh(&solid_fixture("nested_cubes.obj"));
    assert!((check.signed_volume - 1216.0).abs() < 1e-9);
    assert!(check.crossing_triangles.is_empty());
    assert_eq!(
        check.shell_faults,
        vec![ballast::geometry::ShellFault {
            triangle: 12,
            winding: 2
        }]
    );
    assert!(!check.is_solid());
}

#[test]
fn a_cavity_facing_inwards_is_a_solid() {
    let check = check_mesh(&solid_fixture("hollow_cube.obj"));
    assert!((check.signed_volume - 784.0).abs() < 1e-9);
    assert!(check.is_solid(), "{check:?}");
    assert!(!check.shells_unchecked);
}

#[test]
fn separate_parts_and_an_inward_shell_alone() {
    // Two cubes side by side: a valid solid of two shells.
    let mut two = geometry_support::box_mesh(1.0, 1.0, 1.0);
    let other = geometry_support::box_mesh(1.0, 1.0, 1.0);
    let offset = two.positions.len() as u32;
    two.positions.extend(
        other
            .positions
            .iter()
            .map(|p| p + nalgebra::Vector3::new(3.0, 0.0, 0.0)),
    );
    two.triangles
        .extend(other.triangles.iter().map(|t| t.map(|i| i + offset)));
    assert!(check_mesh(&two).is_solid());
    // The second one inside out, beside the first: -1 inside it.
    let first_of_second = unit_cube().triangles.len();
    for t in &mut two.triangles[first_of_second..] {
        t.swap(1, 2);
    }
    let check = check_mesh(&two);
    assert_eq!(check.shell_faults.len(), 1);
    assert_eq!(check.shell_faults[0].winding, -1);
}

#[test]
fn the_example_meshes_are_solids() {
    let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes");
    let mut checked = 0;
    for entry in std::fs::read_dir(folder).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "obj") {
            let check = check_mesh(&load_mesh(&path, &MeshSelector::Whole).unwrap());
            assert!(check.is_solid(), "{}: {check:?}", path.display());
            assert!(!check.shells_unchecked, "{}", path.display());
            checked += 1;
        }
    }
    assert!(checked >= 5);
}
