//! The example meshes in `examples/meshes`: every one is a closed, outward-oriented solid, and
//! each has the size, volume and balance its generator (`generate.py`) states.

use std::f64::consts::PI;
use std::path::PathBuf;

use ballast::geometry::{
    check_mesh, load_mesh, mass_properties, MassProperties, MeshSelector, TriMesh,
};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

fn folder() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/meshes")
}

fn load(file: &str, selector: MeshSelector) -> TriMesh {
    let path = folder().join(file);
    load_mesh(&path, &selector).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn properties(file: &str) -> MassProperties {
    mass_properties(&load(file, MeshSelector::Whole))
}

fn part(name: &str) -> TriMesh {
    load("hinged_arm.obj", MeshSelector::ObjObject(name.to_string()))
}

fn assert_close(actual: f64, expected: f64, tolerance: f64) {
    assert!(
        (actual - expected).abs() <= tolerance,
        "{actual} is not {expected} (± {tolerance})"
    );
}

fn assert_point(actual: Point3<f64>, expected: [f64; 3]) {
    for (a, e) in actual.iter().zip(expected) {
        assert_close(*a, e, 1e-4);
    }
}

fn bounds(mesh: &TriMesh) -> [[f64; 3]; 2] {
    let (lo, hi) = mesh.bounding_box().expect("mesh has vertices");
    [lo.into(), hi.into()]
}

#[test]
fn every_example_mesh_is_a_closed_outward_solid() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(folder())
        .expect("examples/meshes is readable")
        .map(|entry| entry.expect("directory entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "obj"))
        .collect();
    files.sort();
    let names: Vec<_> = files.iter().filter_map(|p| p.file_name()).collect();
    assert_eq!(
        names,
        [
            "blub_fish.obj",
            "hammer.obj",
            "hinged_arm.obj",
            "sheared_cylinder.obj",
            "spot.obj",
            "t_shape.obj"
        ]
    );
    for path in &files {
        let mesh = load_mesh(path, &MeshSelector::Whole)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let check = check_mesh(&mesh);
        let name = path.display();
        assert!(check.is_closed(), "{name}: {check:?}");
        assert!(check.is_oriented(), "{name}: {check:?}");
        assert!(!check.is_inverted(), "{name}: {check:?}");
        assert!(check.degenerate_triangles.is_empty(), "{name}: {check:?}");
        assert!(check.signed_volume > 0.0, "{name}: {check:?}");
    }
}

#[test]
fn t_shape_has_its_stated_size_volume_and_centre_of_mass() {
    let mesh = load("t_shape.obj", MeshSelector::Whole);
    assert_eq!(bounds(&mesh), [[-65.0, -10.0, 0.0], [65.0, 10.0, 40.0]]);
    let t = mass_properties(&mesh);
    // Stem 50 × 30 and bar 130 × 10, 20 deep.
    assert_close(t.volume, 20.0 * (50.0 * 30.0 + 130.0 * 10.0), 1e-6);
    assert_point(t.centroid, [0.0, 0.0, 170.0 / 7.0]);
}

#[test]
fn t_shape_stands_on_both_ends_but_falls_off_its_sides() {
    let c = properties("t_shape.obj").centroid;
    // Upright on the stem foot |x| ≤ 25; upside down on the bar top |x| ≤ 65.
    assert!(c.x.abs() < 25.0, "{c}");
    // On a side face, from the stem foot edge (±25, 0) to the bar end edge (±65, 30): the
    // centre of mass projects beyond the stem foot, so the T tips back onto its foot.
    for side in [1.0, -1.0] {
        let (foot, end) = (
            Vector3::new(25.0 * side, 0.0, 0.0),
            Vector3::new(65.0 * side, 0.0, 30.0),
        );
        let along = (c.coords - foot).dot(&(end - foot)) / (end - foot).norm();
        assert_close(along, -38.0 / 7.0, 1e-4);
        assert!(along < -5.0, "side {side}: {along}");
    }
    // Rotated a quarter turn onto the bar end alone (z in [30, 40]) it falls as well.
    assert!(c.z < 30.0, "{c}");
}

#[test]
fn sheared_cylinder_has_its_stated_volume_and_stands_on_neither_end() {
    let mesh = load("sheared_cylinder.obj", MeshSelector::Whole);
    let [lo, hi] = bounds(&mesh);
    assert_eq!((lo[0], lo[2], hi[0], hi[2]), (-15.0, 0.0, 55.0, 80.0));
    assert_close(lo[1], -15.0, 1e-4);
    assert_close(hi[1], 15.0, 1e-4);
    // A 64-gon prism of circumradius 15 and height 80; shearing keeps the volume.
    let expected = 32.0 * 15.0 * 15.0 * (2.0 * PI / 64.0).sin() * 80.0;
    let s = mass_properties(&mesh);
    assert_close(s.volume, expected, 1e-6 * expected);
    assert_point(s.centroid, [20.0, 0.0, 40.0]);
    // Standing needs the centre of mass over the end disc: the bottom one is centred at x = 0,
    // the top one at x = 40, both of radius 15.
    assert!(s.centroid.x.abs() > 15.0);
    assert!((s.centroid.x - 40.0).abs() > 15.0);
}

/// Total volume and centre of mass of `parts` (one density).
fn combined(parts: &[&TriMesh]) -> (f64, Point3<f64>) {
    let props: Vec<MassProperties> = parts.iter().map(|m| mass_properties(m)).collect();
    let volume: f64 = props.iter().map(|p| p.volume).sum();
    let moment: Vector3<f64> = props.iter().map(|p| p.centroid.coords * p.volume).sum();
    (volume, Point3::from(moment / volume))
}

#[test]
fn hinged_arm_stands_with_the_arm_over_the_base_and_topples_when_it_is_turned() {
    let (base, arm) = (part("base"), part("arm"));
    assert_eq!(bounds(&base), [[-30.0, -20.0, 0.0], [30.0, 20.0, 20.0]]);
    assert_eq!(bounds(&arm), [[-30.0, -10.0, 21.0], [110.0, 10.0, 37.0]]);
    assert!(check_mesh(&base).is_closed() && check_mesh(&arm).is_closed());

    let (volume, rest) = combined(&[&base, &arm]);
    assert_close(volume, 48000.0 + 44800.0, 1e-6);
    assert_close(rest.x, 44800.0 * 40.0 / 92800.0, 1e-6);
    // Inside the base's footprint |x| ≤ 30, by more than 10.
    assert!(rest.x.abs() < 30.0 - 10.0, "{rest}");

    // Half a turn about the vertical hinge axis through the pivot (-22, 0, 20).
    let pivot = Vector3::new(-22.0, 0.0, 20.0);
    let turn = Translation3::from(pivot)
        * Isometry3::from_parts(
            Translation3::identity(),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), PI),
        )
        * Translation3::from(-pivot);
    let turned = arm.transformed(&turn);
    let [lo, hi] = bounds(&turned);
    assert_close(lo[0], -154.0, 1e-9);
    assert_close(hi[0], -14.0, 1e-9);
    let (_, toppled) = combined(&[&base, &turned]);
    assert_close(toppled.x, 44800.0 * -84.0 / 92800.0, 1e-6);
    // Beyond the base's edge x = -30, by more than 10.
    assert!(toppled.x < -30.0 - 10.0, "{toppled}");
}
