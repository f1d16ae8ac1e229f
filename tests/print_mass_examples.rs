//! The FDM mass model against the G-code PrusaSlicer writes for every example, component by
//! component and without the balls: the plastic the model puts in each part (mass and centre of
//! mass, rest frame) beside the plastic the slicer deposits, for the bare part (no capsules) and
//! for the part with the design's voids. The bare part measures the body model
//! (`geometry::print_volumes`) alone; the difference between the two measures the capsule term
//! (`balance::capsule_shell`). Prints the table that `docs/physics.md` ("Agreement on the
//! examples") quotes. Skipped when `prusa-slicer` is not installed (`.ci/run` installs it).

mod print_support;

use std::path::Path;

use ballast::balance::{capsule_shell, component_voids, slicing};
use ballast::compile::{bed_parts, bed_plate_pauses, compile, print_settings, Compilation};
use ballast::design::Design;
use ballast::emit::print_files::write_prusa_3mf;
use ballast::geometry::print_volumes_with_voids;
use ballast::sliced::{verify_gcode, SlicedOptions};
use nalgebra::{Point3, Vector3};
use print_support::{examples, slice_with, slicer_available};

/// The plastic the optimizer's closed form puts in component `index` with the capsules of
/// `design`: grams. Recomputed here from its pieces (the component's solid and sparse volumes,
/// each capsule's closed-form term), not read from an evaluation.
fn closed_form(c: &Compilation, design: &Design, index: usize) -> f64 {
    let project = &c.project;
    let density = project.material.density * project.units.cubic_in_cm3();
    let infill = design.infill;
    let print = &c.prints[index];
    let shell = capsule_shell(&project.print);
    let mut mass = density * (print.solid.volume + infill * print.sparse.volume);
    for capsule in design.capsules.iter().filter(|k| k.component == index) {
        let length = capsule.axis_length();
        let volume = |r: f64| std::f64::consts::PI * r * r * (length + 4.0 / 3.0 * r);
        let change =
            density * ((1.0 - infill) * volume(capsule.radius + shell) - volume(capsule.radius));
        mass += change;
    }
    mass
}

/// The plastic the mass model puts in component `index` with the voids of `design` cut from its
/// mesh before slicing (`geometry::print_volumes_with_voids`), without the calibration's
/// correction: grams, and the centre, rest frame. Recomputed here, not read from an evaluation.
fn modelled(c: &Compilation, design: &Design, index: usize) -> (f64, Point3<f64>) {
    let project = &c.project;
    let density = project.material.density * project.units.cubic_in_cm3();
    let voids = component_voids(design, index);
    let slicing = slicing(&project.print, c.orientations[index].to_print);
    let print = print_volumes_with_voids(&c.meshes[index], &slicing, &voids);
    let (solid, sparse) = (print.solid.volume, design.infill * print.sparse.volume);
    let moment = print.solid.centroid.coords * solid + print.sparse.centroid.coords * sparse;
    (
        density * (solid + sparse),
        Point3::from(moment / (solid + sparse)),
    )
}

/// One component, modelled and sliced.
struct Row {
    label: String,
    /// Grams: the mass model's plastic (the voids cut before slicing), the closed form's, the
    /// G-code's.
    modelled: f64,
    closed_form: f64,
    sliced: f64,
    mass_error: f64,
    centres_apart_mm: f64,
}

/// Slices `c`'s parts with the capsules of `design` and compares every component.
fn compare(c: &Compilation, design: &Design, folder: &Path, label: &str) -> Vec<Row> {
    let parts = bed_parts(&c.project, &c.meshes, design, &c.print_plan);
    let settings = print_settings(&c.project, design);
    let project = folder.join(format!("{label}.3mf"));
    let pauses = bed_plate_pauses(&c.project, &c.print_plan);
    std::fs::write(
        &project,
        write_prusa_3mf(&parts, &pauses, &settings).unwrap(),
    )
    .unwrap();
    let gcode = slice_with(&project, &["--dont-arrange"]);
    let mut checked = c.clone();
    checked.design = design.clone();
    let check = verify_gcode(&checked, &c.print_plan, &gcode, &SlicedOptions::default())
        .unwrap_or_else(|error| panic!("{label}: {error}"));
    let mm = 1.0 / c.project.units.from_millimetres(1.0);
    let mut rows = Vec::new();
    for (index, sliced) in check.components.iter().enumerate() {
        let (mass, centre) = modelled(c, design, index);
        let apart: Vector3<f64> =
            c.orientations[index].to_print * (centre - Point3::from(sliced.centroid)) * mm;
        let row = Row {
            label: format!("{label}: {}", sliced.component),
            modelled: mass,
            closed_form: closed_form(c, design, index),
            sliced: sliced.mass,
            mass_error: (mass - sliced.mass) / sliced.mass,
            centres_apart_mm: apart.norm(),
        };
        println!(
            "| {label} | {} | {:.2} g | {:.2} g | {:+.2} % | {:.2} mm ({:+.2}, {:+.2}, {:+.2}) |",
            sliced.component,
            mass,
            sliced.mass,
            100.0 * row.mass_error,
            row.centres_apart_mm,
            apart.x,
            apart.y,
            apart.z
        );
        rows.push(row);
    }
    rows
}

#[test]
fn the_mass_model_against_the_sliced_examples() {
    if !slicer_available() {
        eprintln!("skipped: prusa-slicer is not on the PATH (apt-get install prusa-slicer)");
        return;
    }
    let folder = tempfile::tempdir().unwrap();
    println!(
        "| example | component | model | G-code | mass | centres apart (print frame x, y, z) |"
    );
    let (mut bare, mut cut) = (Vec::new(), Vec::new());
    for path in examples() {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let source = std::fs::read_to_string(&path).unwrap();
        let c = compile(&source, &path)
            .unwrap_or_else(|problems| panic!("{name} does not compile: {problems:?}"));
        let without = Design {
            capsules: Vec::new(),
            ..c.design.clone()
        };
        bare.extend(compare(
            &c,
            &without,
            folder.path(),
            &format!("{name}, bare"),
        ));
        cut.extend(compare(&c, &c.design, folder.path(), &name));
    }
    assert!(bare.len() >= 7 && cut.len() == bare.len());
    // Today's agreement (docs/physics.md): every part within 3 % of the G-code's plastic, bare
    // or with its voids (the sheared cylinder with its void the worst, -2.75 %), and its centre
    // within 0.5 mm (the hammer's, standing on its head, the worst: 0.41 mm bare).
    let mut failures = Vec::new();
    for row in bare.iter().chain(&cut) {
        if row.mass_error.abs() >= 0.03 {
            failures.push(format!(
                "{}: mass {:+.2} %",
                row.label,
                100.0 * row.mass_error
            ));
        }
        if row.centres_apart_mm >= 0.5 {
            failures.push(format!(
                "{}: centres {:.2} mm apart",
                row.label, row.centres_apart_mm
            ));
        }
    }
    // What the voids change: the closed-form capsule term against the raster with the voids
    // cut before slicing, each beside the G-code's change (docs/physics.md, "The capsule term
    // against re-slicing"); the re-sliced change within 0.6 g of the G-code's (the cylinder's
    // 22 mm void the worst, 0.49 g), where the closed form misses the hammer's by 2.0 g.
    println!("| example: component | closed form | re-sliced | G-code |");
    for (without, with) in bare.iter().zip(&cut) {
        let sliced = with.sliced - without.sliced;
        let resliced = with.modelled - without.modelled;
        println!(
            "| {} | {:+.2} g | {:+.2} g | {:+.2} g |",
            with.label,
            with.closed_form - without.closed_form,
            resliced,
            sliced
        );
        if (resliced - sliced).abs() > 0.6 {
            failures.push(format!(
                "{}: the voids change the re-sliced plastic by {resliced:+.2} g, the G-code's by {sliced:+.2} g",
                with.label
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
