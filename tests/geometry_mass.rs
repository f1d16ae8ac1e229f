//! Mass properties against closed forms and the reference volumes of real meshes.

mod geometry_support;

use std::f64::consts::PI;

use ballast::geometry::{check_mesh, load_mesh, mass_properties, MeshSelector, TriMesh};
use geometry_support::{box_mesh, icosphere, prism, shared_mesh, unit_cube};
use nalgebra::{Isometry3, Matrix3, Point3, Translation3, UnitQuaternion, Vector3};

fn assert_close(actual: f64, expected: f64, tol: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= tol,
        "{what}: {actual} vs {expected} (tolerance {tol})"
    );
}

/// ∫ x xᵀ dV over the box [lo, hi] (axis-aligned), about the origin.
fn box_second_moment(lo: Point3<f64>, hi: Point3<f64>) -> Matrix3<f64> {
    let len = hi - lo;
    let m1 = (hi.coords.component_mul(&hi.coords) - lo.coords.component_mul(&lo.coords)) / 2.0;
    let m2 = hi.coords.map(|x| x.powi(3)) - lo.coords.map(|x| x.powi(3));
    Matrix3::from_fn(|i, j| {
        if i == j {
            let k = (i + 1) % 3;
            let l = (i + 2) % 3;
            m2[i] / 3.0 * len[k] * len[l]
        } else {
            let k = 3 - i - j;
            m1[i] * m1[j] * len[k]
        }
    })
}

#[test]
fn unit_cube_is_exact() {
    let m = mass_properties(&unit_cube());
    assert_eq!(m.volume, 1.0);
    assert_eq!(m.centroid, Point3::new(0.5, 0.5, 0.5));
    let expected = Matrix3::from_fn(|i, j| if i == j { 1.0 / 3.0 } else { 0.25 });
    assert!(
        (m.second_moment - expected).abs().max() < 1e-15,
        "{}",
        m.second_moment
    );
}

#[test]
fn box_a_b_c_is_exact() {
    let (a, b, c) = (2.0, 3.0, 5.0);
    let m = mass_properties(&box_mesh(a, b, c));
    assert_close(m.volume, a * b * c, 1e-13, "volume");
    assert!((m.centroid - Point3::new(a / 2.0, b / 2.0, c / 2.0)).norm() < 1e-14);
    let expected = box_second_moment(Point3::origin(), Point3::new(a, b, c));
    // ∫x² = a³bc/3 = 40, ∫xy = a²b²c/4 = 45.
    assert_close(expected[(0, 0)], 40.0, 1e-12, "closed form ∫x²");
    assert_close(expected[(0, 1)], 45.0, 1e-12, "closed form ∫xy");
    assert!(
        (m.second_moment - expected).abs().max() < 1e-12,
        "{} vs {}",
        m.second_moment,
        expected
    );
}

#[test]
fn box_far_from_the_origin_keeps_its_precision() {
    let lo = Point3::new(1000.0, -2000.0, 3000.0);
    let size = Vector3::new(0.5, 0.25, 2.0);
    let mesh =
        box_mesh(size.x, size.y, size.z).transformed(&Isometry3::translation(lo.x, lo.y, lo.z));
    let m = mass_properties(&mesh);
    assert_close(m.volume, 0.25, 1e-15, "volume");
    assert!(
        (m.centroid - (lo + size / 2.0)).norm() < 1e-12,
        "{}",
        m.centroid
    );
    let expected = box_second_moment(lo, lo + size);
    let rel = (m.second_moment - expected).abs().max() / expected.abs().max();
    assert!(rel < 1e-14, "relative error {rel}");
}

#[test]
fn inverted_mesh_has_negative_volume() {
    let mut mesh = box_mesh(1.0, 2.0, 3.0);
    for t in &mut mesh.triangles {
        t.swap(1, 2);
    }
    let m = mass_properties(&mesh);
    assert_close(m.volume, -6.0, 1e-14, "volume");
    // The centroid is still the centre: both moments change sign.
    assert!((m.centroid - Point3::new(0.5, 1.0, 1.5)).norm() < 1e-14);
}

#[test]
fn faceted_cylinder_volume_is_exact() {
    for n in [3, 4, 7, 32, 500] {
        let (r, h) = (0.7, 2.5);
        let m = mass_properties(&prism(n, r, h));
        let exact = f64::from(n) / 2.0 * r * r * (2.0 * PI / f64::from(n)).sin() * h;
        assert_close(m.volume, exact, 1e-13 * exact, &format!("n = {n}"));
        assert!(
            (m.centroid - Point3::new(0.0, 0.0, h / 2.0)).norm() < 1e-13,
            "n = {n}: {}",
            m.centroid
        );
    }
}

#[test]
fn icosphere_converges_quadratically_to_the_ball() {
    let (r, centre) = (1.5_f64, Point3::new(0.3, -2.0, 7.0));
    let ball = 4.0 / 3.0 * PI * r.powi(3);
    let errors: Vec<f64> = (0..6)
        .map(|level| {
            let mesh = icosphere(level, r, centre);
            let check = check_mesh(&mesh);
            assert!(
                check.is_closed() && check.is_oriented(),
                "level {level}: {check:?}"
            );
            let m = mass_properties(&mesh);
            assert!(
                (m.centroid - centre).norm() < 1e-12,
                "level {level}: {}",
                m.centroid
            );
            // Inscribed polyhedron: always less than the ball.
            assert!(m.volume < ball);
            ball - m.volume
        })
        .collect();
    // Halving the edge length divides the error by about 4, once past the bare icosahedron
    // (level 0 to 1 gives about 3.1).
    let ratios: Vec<f64> = errors.windows(2).map(|pair| pair[0] / pair[1]).collect();
    assert!(
        ratios[1..].iter().all(|r| (3.6..4.1).contains(r)),
        "{ratios:?}"
    );
    assert!(
        ratios[1..].windows(2).all(|w| w[1] > w[0]),
        "ratios approach 4: {ratios:?}"
    );
    assert!((ratios[4] - 4.0).abs() < 0.01, "{ratios:?}");
    assert!(errors[5] / ball < 1e-3);
}

#[test]
fn rigid_motion_moves_the_centroid_and_keeps_the_volume() {
    let mesh = prism(9, 1.0, 3.0);
    let base = mass_properties(&mesh);
    let iso = Isometry3::from_parts(
        Translation3::new(4.0, -1.0, 2.5),
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), 0.7)
            * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -1.2),
    );
    let moved = mass_properties(&mesh.transformed(&iso));
    assert_close(moved.volume, base.volume, 1e-13, "volume");
    assert!((moved.centroid - iso * base.centroid).norm() < 1e-13);
    // About the centroid, the second moment rotates with the body.
    let central = |m: &ballast::geometry::MassProperties| {
        m.second_moment - m.centroid.coords * m.centroid.coords.transpose() * m.volume
    };
    let rot = iso.rotation.to_rotation_matrix();
    let expected = rot.matrix() * central(&base) * rot.matrix().transpose();
    assert!((central(&moved) - expected).abs().max() < 1e-12);

    let shift = Vector3::new(-3.0, 8.0, 0.25);
    let translated =
        mass_properties(&mesh.transformed(&Isometry3::translation(shift.x, shift.y, shift.z)));
    assert!((translated.centroid - (base.centroid + shift)).norm() < 1e-13);
    assert_close(translated.volume, base.volume, 1e-13, "volume");
}

fn real(relative: &str, selector: &MeshSelector) -> Option<TriMesh> {
    let path = shared_mesh(relative)?;
    Some(load_mesh(&path, selector).unwrap_or_else(|e| panic!("{}: {e}", path.display())))
}

/// Rounds to `digits` significant digits.
fn significant(x: f64, digits: i32) -> f64 {
    let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

#[test]
fn torus_volume() {
    let Some(mesh) = real("torus.obj", &MeshSelector::Whole) else {
        return;
    };
    let v = mass_properties(&mesh).volume;
    assert_eq!((v * 1e4).round() / 1e4, 1.2188, "{v}");
    assert!(check_mesh(&mesh).is_closed());
}

#[test]
fn spot_is_closed_with_its_volume() {
    let Some(mesh) = real("spot.obj", &MeshSelector::Whole) else {
        return;
    };
    // `f v/vt` faces: topology must follow the 2930 positions, not the 3225 texture coordinates.
    assert_eq!(mesh.positions.len(), 2930);
    assert_eq!(mesh.triangles.len(), 5856);
    let check = check_mesh(&mesh);
    assert!(check.is_closed() && check.is_oriented(), "{check:?}");
    assert!(check.degenerate_triangles.is_empty());
    assert_eq!(significant(mass_properties(&mesh).volume, 5), 0.71826);
}

#[test]
fn hammer_volume() {
    let Some(mesh) = real("hammer.obj", &MeshSelector::Whole) else {
        return;
    };
    assert_eq!(significant(mass_properties(&mesh).volume, 5), 3.5397);
    assert!(check_mesh(&mesh).is_closed());
}

#[test]
fn poppy_left_thigh_is_closed_with_its_volume() {
    let Some(mesh) = real("poppy_humanoid_parts/l_thigh.obj", &MeshSelector::Whole) else {
        return;
    };
    let check = check_mesh(&mesh);
    assert!(
        check.is_closed() && check.is_oriented() && !check.is_inverted(),
        "{check:?}"
    );
    assert_eq!(significant(mass_properties(&mesh).volume, 5), 0.00051931);
}

#[test]
fn poppy_head_selected_from_the_whole_robot() {
    let Some(head) = real(
        "poppy_humanoid.obj",
        &MeshSelector::ObjObject("head".into()),
    ) else {
        return;
    };
    assert_eq!(significant(mass_properties(&head).volume, 5), 0.0011134);
    let alone = real("poppy_humanoid_parts/head.obj", &MeshSelector::Whole).unwrap();
    assert_eq!(head, alone);
}
