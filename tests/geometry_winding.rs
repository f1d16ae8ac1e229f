//! Generalized winding number: inside, outside, on the surface, and across a hole.

mod geometry_support;

use ballast::geometry::{load_mesh, winding_number, MeshSelector};
use geometry_support::{icosphere, shared_mesh, unit_cube};
use nalgebra::Point3;

fn p(x: f64, y: f64, z: f64) -> Point3<f64> {
    Point3::new(x, y, z)
}

#[test]
fn one_inside_zero_outside_a_cube() {
    let cube = unit_cube();
    for q in [p(0.5, 0.5, 0.5), p(0.01, 0.99, 0.5), p(0.999, 0.001, 0.999)] {
        let w = winding_number(&cube, &q);
        assert!((w - 1.0).abs() < 1e-12, "{q}: {w}");
    }
    for q in [
        p(2.0, 2.0, 2.0),
        p(-0.01, 0.5, 0.5),
        p(0.5, 0.5, 1.001),
        p(-30.0, 4.0, 0.2),
    ] {
        let w = winding_number(&cube, &q);
        assert!(w.abs() < 1e-12, "{q}: {w}");
    }
}

#[test]
fn just_inside_and_just_outside_a_face() {
    let cube = unit_cube();
    assert!((winding_number(&cube, &p(0.3, 0.6, 1e-9)) - 1.0).abs() < 1e-6);
    assert!(winding_number(&cube, &p(0.3, 0.6, -1e-9)).abs() < 1e-6);
}

#[test]
fn on_the_surface_is_the_inside_fraction() {
    let cube = unit_cube();
    // Inside a face, on a face diagonal, on a cube edge, at a corner.
    let cases = [
        (p(0.3, 0.6, 0.0), 0.5),
        (p(0.5, 0.5, 0.0), 0.5),
        (p(0.5, 0.0, 0.0), 0.25),
        (p(0.0, 0.0, 0.0), 0.125),
    ];
    for (q, expected) in cases {
        let w = winding_number(&cube, &q);
        assert!((w - expected).abs() < 1e-12, "{q}: {w}");
    }
}

#[test]
fn inverted_cube_gives_minus_one() {
    let mut cube = unit_cube();
    for t in &mut cube.triangles {
        t.swap(1, 2);
    }
    assert!((winding_number(&cube, &p(0.5, 0.5, 0.5)) + 1.0).abs() < 1e-12);
}

#[test]
fn still_inside_a_cube_with_a_missing_triangle() {
    let mut cube = unit_cube();
    cube.triangles.remove(3);
    for q in [p(0.5, 0.5, 0.5), p(0.2, 0.3, 0.6), p(0.9, 0.9, 0.8)] {
        let w = winding_number(&cube, &q);
        assert!(w > 0.5 && w < 1.0, "{q}: {w}");
    }
    // Seen from the centre, each of the 12 triangles covers 1/12 of the sphere.
    let w = winding_number(&cube, &p(0.5, 0.5, 0.5));
    assert!((w - 11.0 / 12.0).abs() < 1e-12, "{w}");
    assert!(winding_number(&cube, &p(3.0, -1.0, 0.5)).abs() < 0.1);
}

#[test]
fn sphere_inside_and_outside() {
    let sphere = icosphere(3, 2.0, p(1.0, 1.0, 1.0));
    assert!((winding_number(&sphere, &p(1.0, 1.0, 1.0)) - 1.0).abs() < 1e-12);
    assert!((winding_number(&sphere, &p(2.5, 1.5, 0.2)) - 1.0).abs() < 1e-12);
    assert!(winding_number(&sphere, &p(4.0, 1.0, 1.0)).abs() < 1e-12);
}

#[test]
fn torus_hole_is_outside_and_tube_is_inside() {
    let Some(path) = shared_mesh("torus.obj") else {
        return;
    };
    let torus = load_mesh(&path, &MeshSelector::Whole).unwrap();
    // R = 1, r = 0.25 around the y axis.
    assert!(winding_number(&torus, &Point3::origin()).abs() < 1e-9);
    assert!((winding_number(&torus, &p(1.0, 0.0, 0.0)) - 1.0).abs() < 1e-9);
    assert!((winding_number(&torus, &p(0.0, 0.1, -0.9)) - 1.0).abs() < 1e-9);
    assert!(winding_number(&torus, &p(0.0, 0.4, -1.0)).abs() < 1e-9);
}
