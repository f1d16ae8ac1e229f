//! `verify --gcode` against G-code the installed PrusaSlicer writes: a 40 × 30 × 20 mm box with
//! a level capsule void, sliced from a 3MF with a pause at the planned layer, checked through a
//! plan made by hand (the part placed elsewhere on the bed than the slicer puts it). Then wrong
//! plans (the pause one layer off, another message, a void where there is plastic) must be
//! caught. Skipped, with a message, when `prusa-slicer` is not on the PATH.

mod geometry_support;
mod print_support;

use std::path::Path;

use ballast::compile::{compile, Compilation};
use ballast::fabrication::{ComponentPlan, OrientationChoice, Pause, PrintPlan};
use ballast::geometry::TriMesh;
use ballast::sliced::{verify_gcode, SlicedCheck, SlicedOptions};
use geometry_support::{box_mesh, obj_text};
use nalgebra::{Isometry3, Point3, Vector3};
use print_support::*;

/// The capsule: level, along x, in the middle of the box.
const FROM: [f64; 3] = [10.0, 15.0, 10.0];
const TO: [f64; 3] = [30.0, 15.0, 10.0];
const RADIUS: f64 = 4.0;

/// Where the hand-made plan puts the box's corner on the bed; PrusaSlicer centres it on
/// (100, 100) instead.
const CORNER: [f64; 2] = [50.0, 60.0];

/// PrusaSlicer's first layer (0.35 mm) and layers (0.3 mm): the ball (radius 3.8 mm, resting
/// on the void's floor at z = 6) reaches z = 13.6, the void closes at z = 14; the layer topped at
/// 0.35 + 45 × 0.3 = 13.85 is the one to pause after: 46 layers done, resuming at 14.15.
const LAYERS_DONE: usize = 46;
const HEIGHT: f64 = 13.85;
const RESUME: f64 = 14.15;
const MESSAGE: &str = "Insert one 7.6 mm steel ball into capsule `keel`";

fn skip() -> bool {
    if slicer_available() {
        return false;
    }
    eprintln!("skipped: prusa-slicer is not on the PATH (apt-get install prusa-slicer)");
    true
}

fn write_obj(mesh: &TriMesh, path: &Path) {
    std::fs::write(path, obj_text(mesh)).unwrap();
}

/// The project: the box with the capsule, standing upright.
fn project(dir: &Path) -> Compilation {
    write_obj(&box_mesh(40.0, 30.0, 20.0), &dir.join("box.obj"));
    let source = format!(
        "units mm\nup z\nmaterial \"PLA\" density=1.24\ninfill 0.15\n\
         component \"box\" mesh=\"box.obj\"\n\
         capsule \"keel\" component=\"box\" radius={RADIUS} {{\n    from {} {} {}\n    to {} {} {}\n}}\n\
         pose \"upright\" {{\n    stand margin=2\n}}\n\
         pose \"on its end\" {{\n    rotate 0 90 0\n    stand margin=2\n}}\n",
        FROM[0], FROM[1], FROM[2], TO[0], TO[1], TO[2]
    );
    let path = dir.join("box.kdl");
    std::fs::write(&path, &source).unwrap();
    compile(&source, &path).expect("the project compiles")
}

/// The plan: the box upright with its corner at `CORNER`, one pause after `layers_done` layers
/// (heights on PrusaSlicer's layer grid) showing `message`.
fn plan(layers_done: usize, message: &str) -> PrintPlan {
    let height = 0.35 + 0.3 * (layers_done - 1) as f64;
    PrintPlan {
        first_layer_height: 0.35,
        layer_height: 0.3,
        pause_clearance: 0.2,
        components: vec![ComponentPlan {
            component: 0,
            to_bed: Isometry3::translation(CORNER[0], CORNER[1], 0.0),
            down: -Vector3::z(),
            up: Vector3::z(),
            orientation: OrientationChoice::Declared,
            capsules: Vec::new(),
            pauses: vec![Pause {
                layers_done,
                height,
                resume_height: height + 0.3,
                capsules: vec![0],
                message: message.to_string(),
            }],
        }],
    }
}

/// The box with its void as PrusaSlicer slices it, with a pause before the layer topped at
/// `RESUME`, at infill 15%, with the extra arguments `args`.
fn sliced(dir: &Path, args: &[&str]) -> String {
    let body = box_mesh(40.0, 30.0, 20.0);
    let void = capsule_mesh(FROM.into(), TO.into(), RADIUS, 64);
    let path = dir.join("box.3mf");
    write_3mf(
        &[("box", &with_voids(&body, &[void]))],
        &[(RESUME, MESSAGE)],
        &path,
    );
    let mut all = vec!["--fill-density", "15%"];
    all.extend(args);
    slice_with(&path, &all)
}

fn check(compilation: &Compilation, plan: &PrintPlan, gcode: &str) -> SlicedCheck {
    verify_gcode(compilation, plan, gcode, &SlicedOptions::default()).expect("the file reads")
}

/// Mass (g) and centre (rest frame) of the plastic the design's mass model computes: the pose's
/// mass and centre less its ball, upright (world is the rest frame).
fn modelled_plastic(compilation: &Compilation) -> (f64, Point3<f64>) {
    let pose = &compilation.poses[0];
    let mut mass = pose.mass;
    let mut moment = Vector3::from(pose.centre_of_mass) * pose.mass;
    for ball in &pose.balls {
        mass -= ball.mass;
        moment -= Vector3::from(ball.centre_world) * ball.mass;
    }
    (mass, Point3::from(moment / mass))
}

#[test]
fn the_sliced_box_is_as_planned() {
    if skip() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let compilation = project(dir.path());
    let gcode = sliced(dir.path(), &["--skirts", "0"]);
    let check = check(&compilation, &plan(LAYERS_DONE, MESSAGE), &gcode);
    println!("{:#?}", check.components);
    assert_eq!(check.failures(), Vec::<String>::new());
    assert!(check.passes());

    // The pause, found after the planned layer with its message.
    assert_eq!(check.pauses.len(), 1);
    let found = check.pauses[0].found.as_ref().expect("the pause is found");
    assert_eq!(found.layers_done, LAYERS_DONE);
    assert!((found.height.unwrap() - HEIGHT).abs() < 1e-6);
    assert!((found.resume_height.unwrap() - RESUME).abs() < 1e-6);
    assert_eq!(found.message.as_deref(), Some(MESSAGE));

    // The void is empty: the closest extrusion's centre line runs on the void's surface, just
    // outside it (PrusaSlicer keeps the bead's edge, not its centre, out of a negative volume).
    let void = &check.voids[0];
    assert_eq!(void.intrusions, 0);
    let closest = void.closest.unwrap();
    println!(
        "closest extrusion {closest:.3} mm from the axis, limit {:.3}",
        void.limit
    );
    assert!((RADIUS..RADIUS + 0.45).contains(&closest), "{closest}");

    // PrusaSlicer centred the box on (100, 100): its corner moved from (50, 60) to (80, 85).
    let part = &check.components[0];
    assert!((part.shift[0] - 30.0).abs() < 0.1, "{:?}", part.shift);
    assert!((part.shift[1] - 25.0).abs() < 0.1, "{:?}", part.shift);
    assert_eq!(part.mismatch, None);

    // The sliced plastic against the mass model (which tests/print_slicer.rs holds to 5% and
    // 0.2 mm for this box).
    let (mass, centre) = modelled_plastic(&compilation);
    let centroid = Point3::from(part.centroid);
    println!(
        "model {mass:.2} g at {centre:.2?}, G-code {:.2} g at {centroid:.2?}",
        part.mass
    );
    assert!(((part.mass - mass) / mass).abs() < 0.05);
    assert!(
        (centroid - centre).norm() < 0.3,
        "{}",
        (centroid - centre).norm()
    );

    // Every goal, with the sliced mass, near what the design computed.
    for pose in &check.poses {
        assert!(((pose.sliced_mass - pose.computed_mass) / pose.computed_mass).abs() < 0.05);
        for goal in &pose.goals {
            println!(
                "{} {}: computed {:.2}, sliced {:.2}",
                pose.pose, goal.kind, goal.computed, goal.sliced
            );
            assert!(goal.met && goal.computed_met);
            assert!((goal.computed - goal.sliced).abs() < 1.0);
        }
    }
}

#[test]
fn a_plan_a_layer_off_or_with_another_message_fails() {
    if skip() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let compilation = project(dir.path());
    let gcode = sliced(dir.path(), &["--skirts", "0"]);

    let late = check(&compilation, &plan(LAYERS_DONE + 1, MESSAGE), &gcode);
    let failures = late.failures();
    println!("{failures:#?}");
    assert!(!late.passes());
    assert_eq!(failures.len(), 2, "{failures:#?}");
    assert!(
        failures[0].contains("no pause after layer 47"),
        "{failures:#?}"
    );
    assert!(failures[0].contains("nearest pause in the file is after layer 46"));
    assert!(failures[1].contains("the plan does not"), "{failures:#?}");

    let early = check(&compilation, &plan(LAYERS_DONE - 1, MESSAGE), &gcode);
    assert_eq!(early.failures().len(), 2, "{:#?}", early.failures());

    let other = "Insert one 8 mm steel ball into capsule `keel`";
    let wrong = check(&compilation, &plan(LAYERS_DONE, other), &gcode);
    let failures = wrong.failures();
    assert_eq!(failures.len(), 1, "{failures:#?}");
    assert!(failures[0].contains("it shows"), "{failures:#?}");
}

#[test]
fn a_void_where_the_file_prints_plastic_fails() {
    if skip() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut compilation = project(dir.path());
    let gcode = sliced(dir.path(), &["--skirts", "0"]);
    // The design's capsule 8 mm over to -y, where the file prints plastic (sparse infill and
    // the void's own shell).
    let capsule = &mut compilation.design.capsules[0];
    capsule.from.y -= 8.0;
    capsule.to.y -= 8.0;
    let moved = check(&compilation, &plan(LAYERS_DONE, MESSAGE), &gcode);
    let void = &moved.voids[0];
    println!("{:?}", moved.failures());
    assert!(void.intrusions > 0);
    assert!(void.closest.unwrap() < void.limit);
    assert!(!moved.passes());
    assert!(moved
        .failures()
        .iter()
        .any(|f| f.starts_with("capsule `keel`") && f.contains("inside the void")));
}

#[test]
fn labelled_objects_and_a_skirt_outside_them() {
    if skip() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let compilation = project(dir.path());
    let gcode = sliced(dir.path(), &["--skirts", "1", "--gcode-label-objects"]);
    let check = check(&compilation, &plan(LAYERS_DONE, MESSAGE), &gcode);
    assert_eq!(check.failures(), Vec::<String>::new());
    let part = &check.components[0];
    assert_eq!(part.object.as_deref(), Some("box id:0 copy 0"));
    // The skirt, outside the label, moves nothing.
    assert!((part.shift[0] - 30.0).abs() < 0.1, "{:?}", part.shift);
    assert!((part.shift[1] - 25.0).abs() < 0.1, "{:?}", part.shift);
}

#[test]
fn a_skirt_around_an_unlabelled_object_is_named_as_the_cause() {
    if skip() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let compilation = project(dir.path());
    let gcode = sliced(
        dir.path(),
        &[
            "--skirts",
            "1",
            "--skirt-distance",
            "3",
            "--no-gcode-label-objects",
        ],
    );
    let check = check(&compilation, &plan(LAYERS_DONE, MESSAGE), &gcode);
    let part = &check.components[0];
    assert_eq!(part.object, None);
    let mismatch = part
        .mismatch
        .as_deref()
        .expect("the skirt widens the object");
    assert!(mismatch.contains("labels no object"), "{mismatch}");
    assert!(mismatch.contains("skirt"), "{mismatch}");
}

/// The goals of the t_shape example that the sliced mass misses: none. With its calibration file
/// the T stands on its sides 2.57° and 2.51° computed, 2.52° and 2.57° sliced, over its 2° limit
/// (`SHORT_WITH_THE_SLICED_MASS` in `tests/fabrication_examples.rs`). The test fails when the list
/// is no longer exactly what the file misses.
const T_SHAPE_SHORT_WITH_THE_SLICED_MASS: &[&str] = &[];

/// The t_shape example with its design, sliced from the PrusaSlicer project `ballast build`
/// writes (the part where its print plan lays it, its voids, its pauses) with the command line
/// the docs give, checked through that plan: every part where planned, every planned pause after
/// its layer with its message and none other, the voids empty, each goal within 1 (degree or
/// millimetre) of its computed value, and met with the sliced mass but for the goals listed above.
#[test]
fn the_t_shape_sliced_as_planned_is_as_planned() {
    if skip() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (compilation, gcode) = example_sliced("t_shape", dir.path());
    let check = check(&compilation, &compilation.print_plan, &gcode);
    for void in &check.voids {
        println!(
            "capsule `{}`: closest extrusion {:.3} from the axis, limit {:.3}",
            void.capsule,
            void.closest.unwrap(),
            void.limit
        );
    }
    assert!(!check.pauses.is_empty());
    let mut missed = Vec::new();
    for pose in &check.poses {
        for goal in &pose.goals {
            println!(
                "{} {}: computed {:.2}, sliced {:.2}",
                pose.pose, goal.kind, goal.computed, goal.sliced
            );
            assert!((goal.computed - goal.sliced).abs() < 1.0);
            if !goal.met {
                missed.push(format!("{} {}", pose.pose, goal.kind));
            }
        }
    }
    let as_planned: Vec<String> = check
        .components
        .iter()
        .filter_map(|c| c.mismatch.clone())
        .chain(check.pauses.iter().filter_map(|p| p.problem.clone()))
        .chain(check.voids.iter().filter_map(|v| v.problem()))
        .collect();
    assert_eq!(as_planned, Vec::<String>::new());
    assert_eq!(missed, T_SHAPE_SHORT_WITH_THE_SLICED_MASS);
}

/// Two components, each a box with a capsule (the second box 30 mm long), written into the 3MF
/// second first and sliced with object labels: each object is found by its name, each with its
/// own shift, and the two components' pauses after the same layer are the file's one pause, whose
/// message holds both.
#[test]
fn two_labelled_parts_are_matched_by_name_and_share_a_pause() {
    if skip() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    write_obj(&box_mesh(40.0, 30.0, 20.0), &dir.path().join("long.obj"));
    write_obj(&box_mesh(30.0, 30.0, 20.0), &dir.path().join("short.obj"));
    let source = "units mm\nup z\nmaterial \"PLA\" density=1.24\ninfill 0.15\n\
        component \"long\" mesh=\"long.obj\"\ncomponent \"short\" mesh=\"short.obj\"\n\
        capsule \"a\" component=\"long\" radius=4 {\n    from 10 15 10\n    to 30 15 10\n}\n\
        capsule \"b\" component=\"short\" radius=4 {\n    from 8 15 10\n    to 22 15 10\n}\n\
        pose \"side by side\" {\n    component \"short\" { translate 50 0 0 }\n    stand margin=2\n}\n";
    let path = dir.path().join("two.kdl");
    std::fs::write(&path, source).unwrap();
    let compilation = compile(source, &path).expect("the project compiles");

    let void = |from: [f64; 3], to: [f64; 3]| capsule_mesh(from.into(), to.into(), RADIUS, 64);
    let long = with_voids(&box_mesh(40.0, 30.0, 20.0), &[void(FROM, TO)]);
    let short = with_voids(
        &box_mesh(30.0, 30.0, 20.0),
        &[void([8.0, 15.0, 10.0], [22.0, 15.0, 10.0])],
    );
    let messages = [
        "Insert one 7.6 mm steel ball into capsule `a`",
        "Insert one 7.6 mm steel ball into capsule `b`",
    ];
    let both = messages.join(" / ");
    let file = dir.path().join("two.3mf");
    write_3mf(
        &[("short", &short), ("long", &long)],
        &[(RESUME, &both)],
        &file,
    );
    let gcode = slice_with(
        &file,
        &[
            "--fill-density",
            "15%",
            "--skirts",
            "0",
            "--gcode-label-objects",
        ],
    );

    let mut plan = plan(LAYERS_DONE, messages[0]);
    let mut second = plan.components[0].clone();
    second.component = 1;
    second.to_bed = Isometry3::translation(120.0, CORNER[1], 0.0);
    second.pauses[0].message = messages[1].to_string();
    plan.components.push(second);
    let check = check(&compilation, &plan, &gcode);
    for part in &check.components {
        println!(
            "{} as {:?}: shift {:?}",
            part.component, part.object, part.shift
        );
    }
    assert_eq!(check.failures(), Vec::<String>::new());
    let labels: Vec<_> = check
        .components
        .iter()
        .map(|c| c.object.as_deref())
        .collect();
    assert_eq!(
        labels,
        [Some("long id:1 copy 0"), Some("short id:0 copy 0")]
    );
    assert_eq!(check.pauses.len(), 1);
    assert_eq!(check.pauses[0].planned.as_ref().unwrap().messages.len(), 2);
    assert!(check.voids.iter().all(|v| v.intrusions == 0));
    // The shifts differ (PrusaSlicer arranged the two parts its own way), and each maps its
    // object onto its own part: the deposits' centroids lie at the boxes' middles.
    assert_ne!(check.components[0].shift, check.components[1].shift);
    for (part, middle) in check.components.iter().zip([20.0, 15.0]) {
        assert!((part.centroid[0] - middle).abs() < 0.3, "{part:?}");
        assert!((part.centroid[1] - 15.0).abs() < 0.3, "{part:?}");
    }
}

/// The example `name` compiled, and its G-code as `ballast build`'s PrusaSlicer project slices
/// (in `folder`).
fn example_sliced(name: &str, folder: &Path) -> (Compilation, String) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join(format!("examples/{name}.kdl"));
    let source = std::fs::read_to_string(&path).unwrap();
    let compilation = compile(&source, &path).expect("the example compiles");
    let gcode = sliced_compilation(&compilation, folder, name);
    (compilation, gcode)
}

/// `gcode` with the X and Y of every move and arc mapped by `map` (positions are absolute, as
/// PrusaSlicer writes them; an arc's `I` and `J` are relative and keep).
fn moved(gcode: &str, map: impl Fn(f64, f64) -> (f64, f64)) -> String {
    let mut out = String::with_capacity(gcode.len());
    let (mut x, mut y) = (0.0, 0.0);
    for line in gcode.lines() {
        let (code, comment) = line.split_at(line.find(';').unwrap_or(line.len()));
        let words: Vec<&str> = code.split_whitespace().collect();
        if !matches!(words.first(), Some(&("G0" | "G1" | "G2" | "G3"))) {
            out.push_str(line);
            out.push('\n');
            continue;
        }
        let has = |axis: char| words.iter().any(|w| w.starts_with(axis));
        if !has('X') && !has('Y') {
            out.push_str(line);
            out.push('\n');
            continue;
        }
        for word in &words[1..] {
            if let Some(v) = word.strip_prefix('X') {
                x = v.parse().unwrap();
            } else if let Some(v) = word.strip_prefix('Y') {
                y = v.parse().unwrap();
            }
        }
        let (mx, my) = map(x, y);
        let mut text = words[0].to_string();
        text.push_str(&format!(" X{mx:.4} Y{my:.4}"));
        for word in &words[1..] {
            if !word.starts_with('X') && !word.starts_with('Y') {
                text.push(' ');
                text.push_str(word);
            }
        }
        out.push_str(&text);
        out.push_str(comment);
        out.push('\n');
    }
    out
}

/// The examples the issue names, sliced as planned (`--dont-arrange`): PrusaSlicer moves no part
/// (by 0.001 mm at most, measured from the outer perimeters), and the fit finds none, where the
/// bounding boxes' centres, lopsided by sloped faces, gave (+0.07, +0.00) mm and
/// (+0.10, +0.05) mm.
#[test]
fn the_examples_sliced_as_planned_are_found_where_planned() {
    if skip() {
        return;
    }
    for name in ["t_shape", "sheared_cylinder"] {
        let dir = tempfile::tempdir().unwrap();
        let (compilation, gcode) = example_sliced(name, dir.path());
        let check = check(&compilation, &compilation.print_plan, &gcode);
        for part in &check.components {
            println!("{name} `{}`: {:?}", part.component, part.fit);
            assert_eq!(part.doubt, None, "{name}");
            let [dx, dy] = part.shift;
            assert!(dx.hypot(dy) < 0.01, "{name}: {:?}", part.shift);
            assert!(part.fit.residual < 0.05, "{name}: {:?}", part.fit);
        }
    }
}

/// The T's file with every part moved by (+0.8, −0.5) mm is found moved by that, to 0.01 mm,
/// and maps back to what the file as sliced does: the same deposit and the same closest
/// extrusion to each void.
#[test]
fn a_part_moved_on_the_bed_is_found_where_it_is() {
    if skip() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (compilation, gcode) = example_sliced("t_shape", dir.path());
    let plan = &compilation.print_plan;
    let as_sliced = check(&compilation, plan, &gcode);
    let shifted = check(
        &compilation,
        plan,
        &moved(&gcode, |x, y| (x + 0.8, y - 0.5)),
    );
    for (part, before) in shifted.components.iter().zip(&as_sliced.components) {
        println!("moved `{}`: {:?}", part.component, part.fit);
        assert_eq!(part.doubt, None);
        assert!((part.shift[0] - 0.8).abs() < 0.01, "{:?}", part.shift);
        assert!((part.shift[1] + 0.5).abs() < 0.01, "{:?}", part.shift);
        for axis in 0..3 {
            assert!((part.centroid[axis] - before.centroid[axis]).abs() < 0.01);
        }
    }
    for (void, before) in shifted.voids.iter().zip(&as_sliced.voids) {
        assert!((void.closest.unwrap() - before.closest.unwrap()).abs() < 0.01);
    }
    assert_eq!(shifted.failures(), as_sliced.failures());
}

/// The T's file scaled by 3% about the bed's centre is no placement of the planned part: the
/// fit is not trusted, the check says so, and the plan's place is kept.
#[test]
fn a_part_that_does_not_fit_its_outline_is_reported_not_placed() {
    if skip() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let (compilation, gcode) = example_sliced("t_shape", dir.path());
    let scaled = moved(&gcode, |x, y| {
        (100.0 + (x - 100.0) * 1.03, 100.0 + (y - 100.0) * 1.03)
    });
    let check = check(&compilation, &compilation.print_plan, &scaled);
    for part in &check.components {
        println!("scaled `{}`: {:?}", part.component, part.fit);
        let doubt = part.doubt.as_deref().expect("the fit is not trusted");
        assert!(doubt.contains("place on the bed is not found"), "{doubt}");
        assert_eq!(part.shift, [0.0, 0.0]);
    }
    let failures = check.failures();
    assert!(failures
        .iter()
        .any(|f| f.contains("the plan's place is assumed")));
}
