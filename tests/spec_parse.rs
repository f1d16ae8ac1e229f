//! The front end on valid project files: the typed project, defaults, units, transforms, paths.

use std::path::{Path, PathBuf};

use ballast::geometry::MeshSelector;
use ballast::spec::model::{
    Axis, Ball, Capsule, Component, FrameSource, Goal, Infill, MassModel, Material, MeshFrame,
    Optimize, Output, Pose, Print, Project, Spanned, Units,
};
use ballast::spec::parse_project;
use ballast::spec::stock::stock_diameters_mm;
use ballast::spec::transform::{compose, Step};
use nalgebra::{Isometry3, Point3, Vector3};

/// Parses `source` as the project file `/projects/teddy.kdl` and expects no problem at all.
fn parse(source: &str) -> Project {
    let parsed = parse_project(source, Path::new("/projects/teddy.kdl"));
    assert!(parsed.problems.is_empty(), "{:#?}", parsed.problems);
    parsed.project.expect("a project when there is no problem")
}

fn read(name: &str) -> String {
    std::fs::read_to_string(format!("tests/data/spec/ok/{name}")).unwrap()
}

/// A span for expected values; spans take no part in equality.
fn any_span() -> miette::SourceSpan {
    (0, 0).into()
}

fn name(text: &str) -> Spanned<String> {
    Spanned::new(text.to_owned(), any_span())
}

fn goal(goal: Goal) -> Spanned<Goal> {
    Spanned::new(goal, any_span())
}

fn point(x: f64, y: f64, z: f64) -> Point3<f64> {
    Point3::new(x, y, z)
}

fn vector(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x, y, z)
}

/// A component of a millimetre, z-up project: its mesh read in the project's units unless it is
/// glTF (metres, +Y up).
fn component(called: &str, mesh: &str, selector: MeshSelector) -> Component {
    let frame = if mesh.ends_with(".glb") {
        MeshFrame::gltf()
    } else {
        MeshFrame::project(Units::Millimetre, Axis::Z)
    };
    Component {
        name: name(called),
        mesh: Spanned::new(PathBuf::from(mesh), any_span()),
        selector,
        frame,
        print: None,
        span: any_span(),
    }
}

fn pose(called: &str, transform: Isometry3<f64>, components: usize, goals: Vec<Goal>) -> Pose {
    Pose {
        name: name(called),
        transform,
        down: None,
        component_transforms: vec![Isometry3::identity(); components],
        goals: goals.into_iter().map(goal).collect(),
        span: any_span(),
    }
}

#[test]
fn full_project() {
    let mm = Units::Millimetre;
    let mut waving = pose(
        "waving",
        Isometry3::identity(),
        3,
        vec![Goal::Imbalance {
            margin: 2.0,
            contact_tolerance: None,
        }],
    );
    waving.component_transforms[1] = compose([
        Step::Pivot(point(10.0, 0.0, 40.0)),
        Step::Rotate(vector(0.0, 0.0, 45.0)),
    ]);
    let expected = Project {
        units: mm,
        up: Axis::Z,
        material: Material {
            name: "PETG".to_owned(),
            density: 1.27,
        },
        ball: Ball {
            density: 7.8,
            clearance: 0.25,
            pause_clearance: 0.2,
            min_angle: 4.0,
            diameters: vec![4.0, 5.0, 0.25 * Units::Inch.in_metres() / mm.in_metres()],
        },
        infill: Infill {
            value: 0.4,
            range: Some((0.2, 0.6)),
        },
        wall: 1.5,
        print: Print::defaults(Units::Millimetre),
        components: vec![
            component(
                "body",
                "/projects/meshes/teddy-body.obj",
                MeshSelector::ObjObject("body".to_owned()),
            ),
            component(
                "arm",
                "/projects/meshes/teddy.glb",
                MeshSelector::GltfNode("arm_L".to_owned()),
            ),
            component("head", "/meshes/head.obj", MeshSelector::Whole),
        ],
        poses: vec![
            pose(
                "sitting",
                Isometry3::identity(),
                3,
                vec![Goal::Stand {
                    margin: 5.0,
                    contact_tolerance: Some(0.1),
                }],
            ),
            pose(
                "headstand",
                compose([
                    Step::Rotate(vector(180.0, 0.0, 0.0)),
                    Step::Translate(vector(0.0, 0.0, 80.0)),
                ]),
                3,
                vec![Goal::Stand {
                    margin: 0.0,
                    contact_tolerance: None,
                }],
            ),
            waving,
            pose(
                "hanging",
                Isometry3::identity(),
                3,
                vec![Goal::Suspend {
                    point: point(0.0, 0.0, 42.0),
                    component: 2,
                    tolerance: 1.0,
                    unique: false,
                }],
            ),
            pose(
                "swimming",
                Isometry3::identity(),
                3,
                vec![Goal::Immerse {
                    fluid_density: 1.0,
                    min_distance: 2.0,
                    tolerance: 3.0,
                    mass_tolerance: Some(5.0),
                    unique: false,
                }],
            ),
        ],
        capsules: vec![Capsule {
            name: name("c0"),
            component: Spanned::new(0, any_span()),
            from: point(0.0, 0.0, 10.0),
            to: point(0.0, 0.0, 30.0),
            radius: 4.0,
            pinned: true,
            span: any_span(),
        }],
        optimize: Some(Optimize {
            capsules: Some(2),
            grid_cell: Some(0.5),
            grid_cell_span: None,
            tolerance_degrees: 0.5,
            seed: 7,
            span: any_span(),
        }),
        output: Output {
            gltf: PathBuf::from("/projects/out/teddy.glb"),
            report: PathBuf::from("/projects/out/teddy.json"),
            solution: PathBuf::from("/projects/teddy.solution.kdl"),
            stl: PathBuf::from("/projects/out/parts"),
            prusa: PathBuf::from("/projects/out/teddy.3mf"),
            sheet: PathBuf::from("/projects/out/teddy.md"),
        },
    };
    assert_eq!(parse(&read("full.kdl")), expected);
}

#[test]
fn defaults() {
    let project = parse(&read("minimal.kdl"));
    let mm = Units::Millimetre;
    let expected = Project {
        units: mm,
        up: Axis::Z,
        material: Material {
            name: "PLA".to_owned(),
            density: 1.24,
        },
        ball: Ball {
            density: 7.85,
            clearance: mm.from_millimetres(0.2),
            pause_clearance: mm.from_millimetres(0.2),
            min_angle: 3.0,
            diameters: stock_diameters_mm(),
        },
        infill: Infill {
            value: 1.0,
            range: None,
        },
        wall: mm.from_millimetres(1.0),
        print: Print::defaults(mm),
        components: vec![component("body", "/projects/body.obj", MeshSelector::Whole)],
        poses: vec![pose(
            "rest",
            Isometry3::identity(),
            1,
            vec![Goal::Stand {
                margin: 0.0,
                contact_tolerance: None,
            }],
        )],
        capsules: Vec::new(),
        optimize: None,
        output: Output {
            gltf: PathBuf::from("/projects/build/teddy.glb"),
            report: PathBuf::from("/projects/build/teddy.report.json"),
            solution: PathBuf::from("/projects/teddy.solution.kdl"),
            stl: PathBuf::from("/projects/build/teddy-stl"),
            prusa: PathBuf::from("/projects/build/teddy.3mf"),
            sheet: PathBuf::from("/projects/build/teddy.insertion.md"),
        },
    };
    assert_eq!(project, expected);
}

#[test]
fn goal_defaults() {
    let project = parse(
        r#"
        component "body" mesh="body.obj"
        component "head" mesh="head.obj"
        pose "all" {
            imbalance
            suspend 1 2 3
            immerse fluid-density=1.03
        }
        "#,
    );
    let goals: Vec<Goal> = project.poses[0]
        .goals
        .iter()
        .map(|goal| goal.value.clone())
        .collect();
    assert_eq!(
        goals,
        vec![
            Goal::Imbalance {
                margin: 0.0,
                contact_tolerance: None,
            },
            Goal::Suspend {
                point: point(1.0, 2.0, 3.0),
                component: 0,
                tolerance: 2.0,
                unique: false,
            },
            Goal::Immerse {
                fluid_density: 1.03,
                min_distance: 0.0,
                tolerance: 2.0,
                mass_tolerance: None,
                unique: false,
            },
        ]
    );
}

#[test]
fn material_without_a_name() {
    let project = parse(&read("articulated.kdl"));
    assert_eq!(
        project.material,
        Material {
            name: "material".to_owned(),
            density: 1.1,
        }
    );
    assert_eq!(project.up, Axis::Y);
}

#[test]
fn infill_range_without_a_value_takes_its_top() {
    let source = |infill: &str| format!("{infill}\ncomponent \"a\" mesh=\"a.obj\"\npose \"p\"");
    assert_eq!(
        parse(&source("infill min=0.2 max=0.7")).infill,
        Infill {
            value: 0.7,
            range: Some((0.2, 0.7)),
        }
    );
    assert_eq!(
        parse(&source("infill 0.3")).infill,
        Infill {
            value: 0.3,
            range: None,
        }
    );
}

#[test]
fn print_settings_default_to_prusaslicer_and_follow_the_units() {
    let source =
        |print: &str| format!("units cm\n{print}\ncomponent \"a\" mesh=\"a.obj\"\npose \"p\"");
    let cm = Units::Centimetre;
    assert_eq!(parse(&source("")).print, Print::defaults(cm));
    let defaults = Print::defaults(cm);
    assert_eq!(defaults.model, MassModel::Fdm);
    assert!((defaults.layer_height - 0.03).abs() < 1e-12);
    assert!((defaults.solid_infill_below_area - 0.7).abs() < 1e-12);
    let print = parse(&source(
        "print model=\"uniform\" perimeters=2 extrusion-width=(mm)0.5 layer-height=(mm)0.2 \
         first-layer-height=0.025 top-solid-layers=5 bottom-solid-layers=4 \
         solid-infill-below-area=0.5",
    ))
    .print;
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert_eq!(print.model, MassModel::Uniform);
    assert_eq!(
        (
            print.perimeters,
            print.top_solid_layers,
            print.bottom_solid_layers
        ),
        (2, 5, 4)
    );
    assert!(close(print.extrusion_width, 0.05) && close(print.layer_height, 0.02));
    assert!(close(print.first_layer_height, 0.025));
    assert!(close(print.solid_infill_below_area, 0.5));
    assert_eq!(print.surface_margin, defaults.surface_margin);
}

#[test]
fn a_print_node_with_an_unknown_model_is_an_error() {
    let parsed = parse_project(
        "print model=\"resin\"\ncomponent \"a\" mesh=\"a.obj\"\npose \"p\"",
        Path::new("/projects/teddy.kdl"),
    );
    assert!(parsed.project.is_none());
    assert_eq!(parsed.problems.len(), 1, "{:#?}", parsed.problems);
    let text = format!("{:?}", parsed.problems[0]);
    assert!(text.contains("resin"), "{text}");
}

#[test]
fn lengths_convert_to_the_project_units() {
    let project = parse(&read("centimetres.kdl"));
    let cm = Units::Centimetre;
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert_eq!(project.units, cm);
    assert!(close(project.wall, 0.2));
    assert!(close(project.ball.clearance, 0.05));
    let diameters = &project.ball.diameters;
    assert!(close(diameters[0], 0.6) && close(diameters[1], 0.8) && close(diameters[2], 0.635));
    let capsule = &project.capsules[0];
    assert!(close(capsule.radius, 0.635));
    assert!(close(capsule.from.z, 1.0) && close(capsule.to.z, 3.0));
    let upright = &project.poses[0];
    let moved = upright.transform * Point3::origin();
    assert!(close(moved.x, 1.0) && close(moved.z, 50.0));
    match upright.goals[0].value {
        Goal::Stand {
            contact_tolerance, ..
        } => assert!(close(contact_tolerance.unwrap(), 0.1)),
        ref other => panic!("expected stand, found {other:?}"),
    }
    match project.poses[1].goals[0].value {
        Goal::Immerse { min_distance, .. } => assert!(close(min_distance, 0.5)),
        ref other => panic!("expected immerse, found {other:?}"),
    }
}

#[test]
fn defaults_follow_the_project_units() {
    let project = parse("units \"in\"\ncomponent \"a\" mesh=\"a.obj\"\npose \"p\" { stand }");
    let inch = Units::Inch;
    assert_eq!(project.wall, inch.from_millimetres(1.0));
    assert_eq!(project.ball.clearance, inch.from_millimetres(0.2));
    assert_eq!(
        project.poses[0].goals[0].value,
        Goal::Stand {
            margin: 0.0,
            contact_tolerance: None,
        }
    );
}

/// Parses a one-pose project whose pose holds `steps` and returns the pose.
fn pose_with(steps: &str) -> Pose {
    let source = format!(
        "component \"body\" mesh=\"b.obj\"\ncomponent \"arm\" mesh=\"a.obj\"\npose \"p\" {{\n{steps}\n}}"
    );
    parse(&source).poses.remove(0)
}

fn assert_maps(transform: &Isometry3<f64>, from: Point3<f64>, to: Point3<f64>) {
    let mapped = transform * from;
    assert!(
        (mapped - to).norm() < 1e-9,
        "{from} mapped to {mapped}, expected {to}"
    );
}

#[test]
fn rotation_turns_about_the_pivot() {
    let pose = pose_with("pivot 1 0 0\nrotate 0 0 90");
    assert_maps(&pose.transform, point(2.0, 0.0, 0.0), point(1.0, 1.0, 0.0));
}

#[test]
fn steps_apply_in_file_order() {
    let rotate_then_move = pose_with("rotate 0 0 90\ntranslate 1 0 0");
    let move_then_rotate = pose_with("translate 1 0 0\nrotate 0 0 90");
    let origin = Point3::origin();
    assert_maps(&rotate_then_move.transform, origin, point(1.0, 0.0, 0.0));
    assert_maps(&move_then_rotate.transform, origin, point(0.0, 1.0, 0.0));
}

#[test]
fn the_pivot_is_a_fixed_point_not_moved_by_earlier_steps() {
    let pose = pose_with("translate 5 0 0\npivot 1 0 0\nrotate 0 0 180");
    // (0,0,0) -> (5,0,0), then a half turn about (1,0,0) -> (-3,0,0).
    assert_maps(&pose.transform, Point3::origin(), point(-3.0, 0.0, 0.0));
}

#[test]
fn euler_angles_are_extrinsic_x_then_y_then_z() {
    let pose = pose_with("rotate 90 0 90");
    assert_maps(&pose.transform, point(0.0, 1.0, 0.0), point(0.0, 0.0, 1.0));
    assert_maps(&pose.transform, point(1.0, 0.0, 0.0), point(0.0, 1.0, 0.0));
}

#[test]
fn component_blocks_move_one_component() {
    let pose = pose_with("rotate 0 0 90\ncomponent \"arm\" {\n pivot 0 0 1\n rotate 90 0 0\n}");
    assert_eq!(pose.component_transforms[0], Isometry3::identity());
    let arm = pose.component_transforms[1];
    // The arm turns about the line through (0,0,1) along x: (0,0,2) -> (0,-1,1).
    assert_maps(&arm, point(0.0, 0.0, 2.0), point(0.0, -1.0, 1.0));
    // Then the whole pose turns a quarter about z: (0,-1,1) -> (1,0,1).
    assert_maps(
        &(pose.transform * arm),
        point(0.0, 0.0, 2.0),
        point(1.0, 0.0, 1.0),
    );
}

#[test]
fn paths_resolve_against_the_project_folder() {
    let source =
        "component \"a\" mesh=\"../shared/a.obj\"\npose \"p\"\noutput { gltf \"/tmp/a.glb\" }";
    let parsed = parse_project(source, Path::new("designs/toy.kdl"));
    let project = parsed.project.unwrap();
    assert_eq!(
        project.components[0].mesh.value,
        PathBuf::from("designs/../shared/a.obj")
    );
    assert_eq!(project.output.gltf, PathBuf::from("/tmp/a.glb"));
    assert_eq!(
        project.output.report,
        PathBuf::from("designs/build/toy.report.json")
    );
    assert_eq!(project.output.stl, PathBuf::from("designs/build/toy-stl"));
    assert_eq!(project.output.prusa, PathBuf::from("designs/build/toy.3mf"));
    assert_eq!(
        project.output.sheet,
        PathBuf::from("designs/build/toy.insertion.md")
    );
    let bare = parse_project(source, Path::new("toy.kdl")).project.unwrap();
    assert_eq!(
        bare.components[0].mesh.value,
        PathBuf::from("../shared/a.obj")
    );
}

#[test]
fn spans_point_at_the_source() {
    let source = "component \"body\" mesh=\"body.obj\"\npose \"rest\" { stand }\n";
    let project = parse_project(source, Path::new("p.kdl")).project.unwrap();
    let text = |span: miette::SourceSpan| &source[span.offset()..span.offset() + span.len()];
    assert_eq!(text(project.components[0].name.span), "\"body\"");
    assert_eq!(text(project.components[0].mesh.span), "\"body.obj\"");
    assert_eq!(text(project.poses[0].goals[0].span), "stand");
}

#[test]
fn every_ok_file_parses_without_problems() {
    let mut checked = 0;
    for entry in std::fs::read_dir("tests/data/spec/ok").unwrap() {
        let path = entry.unwrap().path();
        let source = std::fs::read_to_string(&path).unwrap();
        let parsed = parse_project(&source, &path);
        assert!(
            parsed.problems.is_empty(),
            "{}: {:#?}",
            path.display(),
            parsed.problems
        );
        assert!(parsed.project.is_some());
        checked += 1;
    }
    assert!(checked >= 4);
}

/// A one-component, one-pose project with `extra` appended.
fn project_with(extra: &str) -> Project {
    parse(&format!(
        "component \"body\" mesh=\"b.obj\"\npose \"p\" {{ stand }}\n{extra}"
    ))
}

#[test]
fn optimize_defaults() {
    let optimize = project_with("optimize").optimize.unwrap();
    assert_eq!(
        optimize,
        Optimize {
            capsules: None,
            grid_cell: None,
            grid_cell_span: None,
            tolerance_degrees: 1.0,
            seed: 0,
            span: any_span(),
        }
    );
    assert_eq!(project_with("").optimize, None);
}

#[test]
fn optimize_properties() {
    let optimize = project_with("optimize capsules=0 seed=18446744073709551615 tolerance=0")
        .optimize
        .unwrap();
    assert_eq!(optimize.capsules, Some(0));
    assert_eq!(optimize.seed, u64::MAX);
    assert_eq!(optimize.tolerance_degrees, 0.0);
    let optimize = project_with("optimize capsules=6 tolerance=2.5")
        .optimize
        .unwrap();
    assert_eq!(optimize.capsules, Some(6));
    assert_eq!(optimize.tolerance_degrees, 2.5);
}

#[test]
fn grid_cell_is_a_length() {
    let project =
        parse("units cm\ncomponent \"a\" mesh=\"a.obj\"\npose \"p\"\noptimize grid-cell=(mm)0.5");
    let cell = project.optimize.unwrap().grid_cell.unwrap();
    assert!((cell - 0.05).abs() < 1e-12, "{cell}");
    let plain = project_with("optimize grid-cell=0.25").optimize.unwrap();
    assert_eq!(plain.grid_cell, Some(0.25));
}

#[test]
fn pinned_defaults_to_false() {
    let capsule = |pinned: &str| {
        project_with(&format!(
            "capsule \"c\" component=\"body\" radius=2 {pinned} {{\n from 0 0 0\n to 0 0 5\n}}"
        ))
        .capsules
        .remove(0)
        .pinned
    };
    assert!(!capsule(""));
    assert!(!capsule("pinned=#false"));
    assert!(capsule("pinned=#true"));
}

#[test]
fn pinned_takes_part_in_equality() {
    let text = |pinned: &str| {
        format!("capsule \"c\" component=\"body\" radius=2 {pinned} {{\n from 0 0 0\n to 0 0 5\n}}")
    };
    assert_eq!(
        project_with(&text("")),
        project_with(&text("pinned=#false"))
    );
    assert_ne!(project_with(&text("")), project_with(&text("pinned=#true")));
}

#[test]
fn solution_path_follows_the_output_block() {
    let parsed = parse_project(
        "component \"a\" mesh=\"a.obj\"\npose \"p\"\noutput { solution \"solutions/toy.kdl\" }",
        Path::new("designs/toy.kdl"),
    );
    let output = parsed.project.unwrap().output;
    assert_eq!(output.solution, PathBuf::from("designs/solutions/toy.kdl"));
    assert_eq!(output.gltf, PathBuf::from("designs/build/toy.glb"));
    let bare = parse_project(
        "component \"a\" mesh=\"a.obj\"\npose \"p\"",
        Path::new("toy.kdl"),
    );
    assert_eq!(
        bare.project.unwrap().output.solution,
        PathBuf::from("toy.solution.kdl")
    );
}

#[test]
fn without_a_list_the_balls_are_the_stock_sizes_in_the_project_units() {
    let stock = stock_diameters_mm();
    for (units, per_mm) in [("mm", 1.0), ("cm", 0.1), ("in", 1.0 / 25.4)] {
        let project = parse(&format!(
            "units {units}\ncomponent \"a\" mesh=\"a.obj\"\npose \"p\""
        ));
        let diameters = &project.ball.diameters;
        assert_eq!(diameters.len(), stock.len(), "{units}");
        for (d, mm) in diameters.iter().zip(&stock) {
            assert!(
                (d - mm * per_mm).abs() < 1e-12 * mm,
                "{units}: {d} for {mm} mm"
            );
        }
    }
    // In inches the inch sizes are exact fractions: 1/4", 5/16", 1".
    let inch = parse("units in\ncomponent \"a\" mesh=\"a.obj\"\npose \"p\"");
    for size in [0.25, 0.3125, 1.0] {
        assert!(
            inch.ball.diameters.iter().any(|d| (d - size).abs() < 1e-12),
            "{size} in"
        );
    }
    // A 4 mm ball is the largest stock ball in a 2.3 mm capsule with the default clearance.
    let mm = parse("component \"a\" mesh=\"a.obj\"\npose \"p\"");
    assert_eq!(mm.ball.radius_for(2.3), Some(2.0));
}

#[test]
fn any_size_allows_every_ball_and_excludes_a_list() {
    let project = parse("ball any-size=#true\ncomponent \"a\" mesh=\"a.obj\"\npose \"p\"");
    assert!(project.ball.diameters.is_empty());
    assert_eq!(project.ball.radius_for(2.3), Some(2.3 - 0.2));
    let listed = parse("ball { diameters 4 6; }\ncomponent \"a\" mesh=\"a.obj\"\npose \"p\"");
    assert_eq!(listed.ball.diameters, vec![4.0, 6.0]);
    let parsed = parse_project(
        "ball any-size=#true { diameters 4 6; }\ncomponent \"a\" mesh=\"a.obj\"\npose \"p\"",
        Path::new("/projects/teddy.kdl"),
    );
    assert!(parsed.project.is_none());
    assert_eq!(parsed.problems.len(), 1, "{:#?}", parsed.problems);
    assert_eq!(
        parsed.problems[0].code,
        ballast::spec::codes::CONFLICTING_PROPERTIES
    );
}

#[test]
fn mesh_units_up_and_scale_default_by_format_and_can_be_written() {
    let project = parse(
        "units cm\nup y\n\
         component \"plain\" mesh=\"a.obj\"\n\
         component \"scan\" mesh=\"b.obj\" mesh-units=m mesh-up=z scale=0.5\n\
         component \"rig\" mesh=\"c.glb\"\n\
         component \"cad\" mesh=\"d.GLTF\" mesh-units=mm mesh-up=z\n\
         pose \"p\"\n",
    );
    let frames: Vec<&MeshFrame> = project.components.iter().map(|c| &c.frame).collect();
    // OBJ: the project's units and up axis, used as written.
    assert_eq!(*frames[0], MeshFrame::project(Units::Centimetre, Axis::Y));
    assert_eq!(frames[0].factor(Units::Centimetre), 1.0);
    assert!(frames[0].is_identity(Units::Centimetre, Axis::Y));
    // Written: metres into centimetres, halved; +z up turned onto +y.
    let scan = frames[1];
    assert_eq!(
        (scan.units, scan.units_from),
        (Units::Metre, FrameSource::Written)
    );
    assert_eq!((scan.up, scan.up_from), (Axis::Z, FrameSource::Written));
    assert_eq!(scan.scale, 0.5);
    assert_eq!(scan.factor(Units::Centimetre), 50.0);
    let turn = scan.rotation(Axis::Y);
    assert_eq!(turn * Vector3::z(), Vector3::y());
    // glTF: metres and +Y up by the specification, whatever the extension's case.
    assert_eq!(*frames[2], MeshFrame::gltf());
    assert_eq!(frames[2].factor(Units::Centimetre), 100.0);
    assert_eq!(
        *frames[2].rotation(Axis::Y).matrix(),
        nalgebra::Matrix3::identity()
    );
    let cad = frames[3];
    assert_eq!(
        (cad.units, cad.units_from),
        (Units::Millimetre, FrameSource::Written)
    );
    assert_eq!((cad.up, cad.up_from), (Axis::Z, FrameSource::Written));
    assert_eq!(cad.factor(Units::Centimetre), 0.1);
}

#[test]
fn the_gltf_turn_into_a_z_up_project_is_blenders() {
    // Blender's glTF importer maps glTF (x, y, z) to (x, -z, y): +Y up becomes +Z up and the
    // glTF front (+Z) faces -Y.
    let turn = MeshFrame::gltf().rotation(Axis::Z);
    assert_eq!(
        turn * Vector3::new(1.0, 2.0, 3.0),
        Vector3::new(1.0, -3.0, 2.0)
    );
    assert!((turn.matrix().determinant() - 1.0).abs() == 0.0);
    // Into an x-up project: +Y onto +X by the quarter turn about -Z.
    assert_eq!(
        MeshFrame::gltf().rotation(Axis::X) * Vector3::new(1.0, 2.0, 3.0),
        Vector3::new(2.0, -1.0, 3.0)
    );
    assert_eq!(MeshFrame::gltf().factor(Units::Millimetre), 1000.0);
    assert_eq!(MeshFrame::gltf().factor(Units::Inch), 1000.0 / 25.4);
}
