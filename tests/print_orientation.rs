//! Print orientation per component: declared (`print { down }`, `print { rotate }`) or chosen
//! (the largest flat hull facet), the mass model sliced in it, and the print plan's bed layout.

mod geometry_support;

use std::path::{Path, PathBuf};

use ballast::balance::slicing;
use ballast::compile::{compile, print_setup, Compilation, Report};
use ballast::fabrication::{OrientationChoice, PrintSetup};
use ballast::geometry::{convex_hull, print_volumes, TriMesh};
use geometry_support::{box_mesh, obj_text, prism};
use nalgebra::{Isometry3, Point3, Rotation3, Vector3};

/// Writes `mesh` as an OBJ file.
fn write_obj(mesh: &TriMesh, path: &Path) {
    std::fs::write(path, obj_text(mesh)).unwrap();
}

/// A project in `dir` with one component of `mesh` and the `print` block `print` (may be empty),
/// compiled.
fn one_part(dir: &Path, mesh: &TriMesh, print: &str) -> Result<Compilation, Vec<String>> {
    write_obj(mesh, &dir.join("part.obj"));
    let source = format!(
        "units mm\ncomponent \"part\" mesh=\"part.obj\" {{\n    print {{ {print} }}\n}}\npose \"rest\" {{ stand }}\n"
    );
    let path: PathBuf = dir.join("part.kdl");
    compile(&source, &path)
        .map_err(|problems| problems.iter().map(|p| p.code.to_string()).collect())
}

fn assert_close(a: f64, b: f64, what: &str) {
    assert!(
        (a - b).abs() <= 1e-6 * (1.0 + b.abs()),
        "{what}: {a} vs {b}"
    );
}

/// The lowest and highest z of `mesh` placed by `to_bed`.
fn bed_z(mesh: &TriMesh, to_bed: &Isometry3<f64>) -> (f64, f64) {
    mesh.positions
        .iter()
        .map(|p| (to_bed * p).z)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), z| {
            (lo.min(z), hi.max(z))
        })
}

fn chosen(choice: &OrientationChoice) -> (f64, &str) {
    match choice {
        OrientationChoice::Chosen { area, reason } => (*area, reason),
        OrientationChoice::Declared => panic!("expected a chosen orientation"),
    }
}

#[test]
fn a_declared_down_puts_that_facet_on_the_bed() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = box_mesh(40.0, 30.0, 20.0);
    let compiled = one_part(dir.path(), &mesh, "down 1 0.1 0").unwrap();
    let orientation = &compiled.orientations[0];
    assert_eq!(orientation.choice, OrientationChoice::Declared);
    // The ray along (1, 0.1, 0) from the centre (20, 15, 10) leaves through the face x = 40.
    assert!((orientation.down - Vector3::x()).norm() < 1e-12);
    assert_close(
        orientation.facet_area.unwrap(),
        600.0,
        "area of the x = 40 face",
    );
    assert_close(orientation.height, 40.0, "height");
    let plan = &compiled.print_plan.components[0];
    assert_eq!(plan.orientation, OrientationChoice::Declared);
    let (low, high) = bed_z(&mesh, &plan.to_bed);
    assert!(
        low.abs() < 1e-9 && (high - 40.0).abs() < 1e-9,
        "{low} {high}"
    );
    // The face x = 40 lies on the bed.
    assert!((plan.to_bed * Point3::new(40.0, 7.0, 3.0)).z.abs() < 1e-9);
}

#[test]
fn a_declared_rotate_turns_the_rest_frame_into_the_print_frame() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = box_mesh(40.0, 30.0, 20.0);
    let compiled = one_part(dir.path(), &mesh, "rotate 90 0 0").unwrap();
    let orientation = &compiled.orientations[0];
    assert_eq!(orientation.choice, OrientationChoice::Declared);
    // Rx(90°) turns +y up: the face y = 0 is on the bed.
    assert!(
        (orientation.down + Vector3::y()).norm() < 1e-12,
        "{}",
        orientation.down
    );
    assert_close(
        orientation.facet_area.unwrap(),
        800.0,
        "area of the y = 0 face",
    );
    assert_close(orientation.height, 30.0, "height");
    let to_print = Rotation3::from_axis_angle(&Vector3::x_axis(), 90f64.to_radians());
    assert!((orientation.to_print.matrix() - to_print.matrix()).norm() < 1e-12);
    // The mass model is the box sliced on its side, not upright.
    let print = &compiled.project.print;
    let sideways = print_volumes(&mesh, &slicing(print, orientation.to_print));
    let upright = print_volumes(&mesh, &slicing(print, Rotation3::identity()));
    assert_eq!(compiled.prints[0], sideways);
    assert!((sideways.solid.volume - upright.solid.volume).abs() > 100.0);
    // A tilted rotation stands the box on an edge: no facet is flat on the bed.
    let tilted = one_part(dir.path(), &mesh, "rotate 30 0 0").unwrap();
    assert_eq!(tilted.orientations[0].facet_area, None);
}

#[test]
fn a_box_is_laid_on_its_largest_face_its_longest_edge_along_x() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = box_mesh(20.0, 30.0, 40.0);
    let compiled = one_part(dir.path(), &mesh, "").unwrap();
    let orientation = &compiled.orientations[0];
    let (area, reason) = chosen(&orientation.choice);
    assert_close(area, 1200.0, "the 30 × 40 face");
    assert!(reason.starts_with("the largest flat facet"), "{reason}");
    assert!(
        orientation.down.x.abs() > 1.0 - 1e-12,
        "{}",
        orientation.down
    );
    assert_close(orientation.height, 20.0, "height");
    // The 40 edge (rest z) runs along the bed's x.
    let z = orientation.to_print * Vector3::z();
    assert!(z.x.abs() > 1.0 - 1e-12, "{z}");
}

#[test]
fn the_t_shape_lies_on_its_flat_side() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("examples/t_shape.kdl");
    let compiled = compile(&undeclared_t_shape(&path), &path).unwrap();
    let mesh = &compiled.meshes[0];
    let hull = convex_hull(&mesh.positions).unwrap();
    let largest = hull.facets.iter().map(|f| f.area).fold(0.0, f64::max);
    let orientation = &compiled.orientations[0];
    let (area, _) = chosen(&orientation.choice);
    assert_close(area, largest, "the largest facet");
    // The T is extruded along y: its flat sides face ±y, and it lies as low as its thickness.
    assert!(
        orientation.down.y.abs() > 1.0 - 1e-12,
        "{}",
        orientation.down
    );
    let (low, high) = mesh
        .positions
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.y), hi.max(p.y))
        });
    assert_close(orientation.height, high - low, "height");
}

#[test]
fn a_squat_cylinder_stands_on_its_end_and_a_long_one_lies_on_its_side() {
    let dir = tempfile::tempdir().unwrap();
    // r 10, h 50: the end (≈ 314 mm²) beats a side strip (2·10·sin(π/64)·50 ≈ 49 mm²).
    let squat = prism(64, 10.0, 50.0);
    let compiled = one_part(dir.path(), &squat, "").unwrap();
    let orientation = &compiled.orientations[0];
    let (area, _) = chosen(&orientation.choice);
    assert_close(
        area,
        32.0 * 100.0 * (2.0 * std::f64::consts::PI / 64.0).sin(),
        "end",
    );
    // The project's down (−z) decides between the two equal ends.
    assert!(
        (orientation.down + Vector3::z()).norm() < 1e-12,
        "{}",
        orientation.down
    );
    assert_close(orientation.height, 50.0, "height");
    // r 5, h 200: a side strip (2·5·sin(π/64)·200 ≈ 98 mm²) beats the end (≈ 78 mm²).
    let long = prism(64, 5.0, 200.0);
    let compiled = one_part(dir.path(), &long, "").unwrap();
    let orientation = &compiled.orientations[0];
    let (area, _) = chosen(&orientation.choice);
    assert_close(
        area,
        2.0 * 5.0 * (std::f64::consts::PI / 64.0).sin() * 200.0,
        "side",
    );
    assert!(orientation.down.z.abs() < 1e-9, "{}", orientation.down);
    assert!(
        orientation.height < 10.0 && orientation.height > 9.9,
        "{}",
        orientation.height
    );
}

#[test]
fn each_component_of_the_articulated_example_gets_its_own_orientation_and_place() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("examples/articulated.kdl");
    let compiled = compile(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    let plan = &compiled.print_plan;
    assert_eq!(plan.components.len(), 2);
    assert_eq!(plan.layer_height, compiled.project.print.layer_height);
    assert_eq!(
        plan.first_layer_height,
        compiled.project.print.first_layer_height
    );
    let mut boxes = Vec::new();
    for (i, (mesh, orientation)) in compiled
        .meshes
        .iter()
        .zip(&compiled.orientations)
        .enumerate()
    {
        // Its own hull's largest facet, not the pair's.
        let hull = convex_hull(&mesh.positions).unwrap();
        let largest = hull.facets.iter().map(|f| f.area).fold(0.0, f64::max);
        assert_close(chosen(&orientation.choice).0, largest, "own largest facet");
        let component = &plan.components[i];
        assert_eq!(component.component, i);
        let own = compiled
            .design
            .capsules
            .iter()
            .filter(|capsule| capsule.component == i)
            .count();
        assert_eq!(component.capsules.len(), own);
        let placed: Vec<Point3<f64>> = mesh
            .positions
            .iter()
            .map(|p| component.to_bed * p)
            .collect();
        let low = placed.iter().fold(placed[0], |a, p| a.inf(p));
        let high = placed.iter().fold(placed[0], |a, p| a.sup(p));
        assert!(low.z.abs() < 1e-9, "on the bed: {}", low.z);
        boxes.push((low, high));
    }
    // Side by side along x, 10 mm apart, the layout centred on (125, 105).
    let (a, b) = (boxes[0], boxes[1]);
    assert_close(b.0.x - a.1.x, 10.0, "gap");
    assert_close((a.0.x + b.1.x) / 2.0, 125.0, "centre x");
    assert_close((a.0.y + a.1.y) / 2.0, 105.0, "centre y");
    assert_close((b.0.y + b.1.y) / 2.0, 105.0, "centre y");
}

#[test]
fn a_project_in_inches_is_laid_out_in_inches() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = box_mesh(2.0, 1.0, 1.0);
    write_obj(&mesh, &dir.path().join("part.obj"));
    let source = "units in\ncomponent \"a\" mesh=\"part.obj\"\ncomponent \"b\" mesh=\"part.obj\"\npose \"rest\" { stand }\n";
    let compiled = compile(source, &dir.path().join("part.kdl")).unwrap();
    let plan = &compiled.print_plan.components;
    let x = |i: usize, p: Point3<f64>| (plan[i].to_bed * p).x;
    // Each 2 in long along x, 10 mm apart, centred on 125 mm.
    assert_close(
        x(1, Point3::origin()).min(x(1, Point3::new(2.0, 0.0, 0.0)))
            - x(0, Point3::origin()).max(x(0, Point3::new(2.0, 0.0, 0.0))),
        10.0 / 25.4,
        "gap",
    );
    let left = x(0, Point3::origin()).min(x(0, Point3::new(2.0, 0.0, 0.0)));
    assert_close(left, 125.0 / 25.4 - (4.0 + 10.0 / 25.4) / 2.0, "left edge");
}

#[test]
fn the_orientation_and_the_report_are_the_same_twice() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for example in ["spot", "articulated"] {
        let path = root.join(format!("examples/{example}.kdl"));
        let source = std::fs::read_to_string(&path).unwrap();
        let first = compile(&source, &path).unwrap();
        let second = compile(&source, &path).unwrap();
        assert_eq!(first.print_plan, second.print_plan);
        assert_eq!(
            Report::new(&first, &path).to_json(),
            Report::new(&second, &path).to_json()
        );
    }
}

#[test]
fn the_reported_rotate_written_into_a_print_block_prints_the_part_the_same_way() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("examples/t_shape.kdl");
    let source = undeclared_t_shape(&path);
    let chosen = compile(&source, &path).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&Report::new(&chosen, &path).to_json()).unwrap();
    let print = &json["components"][0]["print"];
    assert_eq!(print["choice"], "chosen");
    let rotate: Vec<f64> = print["rotate"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.as_f64().unwrap())
        .collect();
    let line = "component \"T\" mesh=\"meshes/t_shape.obj\"";
    assert!(source.contains(line));
    let declared = source.replace(
        line,
        &format!(
            "{line} {{\n    print {{ rotate {} {} {} }}\n}}",
            rotate[0], rotate[1], rotate[2]
        ),
    );
    let declared = compile(&declared, &path).unwrap();
    let (a, b) = (&chosen.orientations[0], &declared.orientations[0]);
    assert_eq!(b.choice, OrientationChoice::Declared);
    assert!((a.to_print.matrix() - b.to_print.matrix()).norm() < 1e-12);
    assert!((a.down - b.down).norm() < 1e-12);
    assert_close(
        b.facet_area.unwrap(),
        a.facet_area.unwrap(),
        "facet on the bed",
    );
    let (x, y) = (&chosen.prints[0], &declared.prints[0]);
    assert_close(y.solid.volume, x.solid.volume, "solid volume");
    assert!((y.solid.centroid - x.solid.centroid).norm() < 1e-6);
}

/// The T example's project text without its `print` block, so that ballast chooses how it lies.
fn undeclared_t_shape(path: &Path) -> String {
    let source = std::fs::read_to_string(path).unwrap();
    let block = "component \"T\" mesh=\"meshes/t_shape.obj\" {\n    print { down 1 0 0 }\n}";
    assert!(source.contains(block), "{source}");
    source.replace(block, "component \"T\" mesh=\"meshes/t_shape.obj\"")
}

#[test]
fn the_plan_prints_each_part_along_the_very_direction_the_optimizer_checks() {
    // The insertion windows and pauses of the report come from the plan's setup, the
    // optimizer's insertability checks from the orientations': one direction, to the bit, so
    // a design the optimizer finds insertable has its pause in the plan.
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    for name in ["t_shape", "articulated", "hammer", "spot", "fish"] {
        let path = examples.join(format!("{name}.kdl"));
        let source = std::fs::read_to_string(&path).unwrap();
        let compiled = compile(&source, &path).unwrap_or_else(|_| panic!("{name} compiles"));
        let planned = PrintSetup::from_plan(&compiled.print_plan);
        let optimized = print_setup(&compiled.project, &compiled.orientations);
        assert_eq!(planned, optimized, "{name}");
    }
}
