//! The glTF writer: what goes in comes back out of a standard glTF reader.

use std::collections::BTreeMap;

use ballast::emit::{write_glb, GltfError, SceneCapsule, SceneComponent, SceneModel, ScenePose};
use nalgebra::{Isometry3, Matrix4, Point3, Translation3, UnitQuaternion, Vector3, Vector4};
use serde_json::json;

fn cube(name: &str, size: f64) -> SceneComponent {
    let positions = (0..8)
        .map(|i| {
            Point3::new(
                f64::from(i & 1) * size,
                f64::from((i >> 1) & 1) * size,
                f64::from((i >> 2) & 1) * size,
            )
        })
        .collect();
    let triangles = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    SceneComponent {
        name: name.to_owned(),
        positions,
        triangles,
    }
}

fn tetrahedron(name: &str) -> SceneComponent {
    SceneComponent {
        name: name.to_owned(),
        positions: vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(30.0, 0.0, 0.0),
            Point3::new(0.0, 30.0, 0.0),
            Point3::new(0.0, 0.0, 30.0),
        ],
        triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    }
}

fn iso(t: [f64; 3], axis: Vector3<f64>, angle: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(t[0], t[1], t[2]),
        UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle),
    )
}

/// Two components, two capsules, two poses; Z is up, lengths in millimetres.
fn model() -> SceneModel {
    SceneModel {
        unit_in_metres: 0.001,
        up: Vector3::z(),
        components: vec![cube("body", 100.0), tetrahedron("keel")],
        capsules: vec![
            SceneCapsule {
                name: "left".to_owned(),
                component: 0,
                from: Point3::new(10.0, 50.0, 20.0),
                to: Point3::new(40.0, 50.0, 20.0),
                radius: 6.0,
                ball_radius: 5.0,
            },
            SceneCapsule {
                name: "fore".to_owned(),
                component: 1,
                from: Point3::new(5.0, 5.0, 5.0),
                to: Point3::new(5.0, 5.0, 15.0),
                radius: 3.5,
                ball_radius: 3.0,
            },
        ],
        poses: vec![
            ScenePose {
                name: "standing".to_owned(),
                component_transforms: vec![
                    Isometry3::identity(),
                    iso([20.0, 30.0, -30.0], Vector3::new(1.0, 2.0, 3.0), 0.7),
                ],
                ball_centres: vec![Point3::new(12.0, 50.0, 20.0), Point3::new(5.0, 5.0, 14.0)],
                centre_of_mass: Point3::new(48.0, 52.0, 31.0),
                support_polygon: vec![
                    Point3::new(0.0, 0.0, -15.0),
                    Point3::new(100.0, 0.0, -15.0),
                    Point3::new(100.0, 100.0, -15.0),
                    Point3::new(0.0, 100.0, -15.0),
                ],
                ground: Some(-15.0),
                suspension_point: None,
                buoyancy_centre: Some(Point3::new(50.0, 50.0, 20.0)),
                extras: json!({"margin_mm": 12.5, "stable": true, "goals": [1, 2.5]}),
            },
            ScenePose {
                name: "hanging".to_owned(),
                component_transforms: vec![
                    iso([1.0, -2.0, 3.0], Vector3::new(0.0, 1.0, 0.0), 2.5),
                    iso([-40.0, 10.0, 0.5], Vector3::new(-1.0, 0.2, 0.0), -1.1),
                ],
                ball_centres: vec![Point3::new(38.0, 50.0, 20.0), Point3::new(5.0, 5.0, 6.0)],
                centre_of_mass: Point3::new(-7.0, 3.0, -50.0),
                support_polygon: vec![Point3::new(0.0, 0.0, 0.0), Point3::new(10.0, 0.0, 0.0)],
                ground: None,
                suspension_point: Some(Point3::new(0.0, 0.0, 120.0)),
                buoyancy_centre: None,
                extras: json!({"tilt_deg": -3.25}),
            },
        ],
    }
}

/// Every node's world matrix, by name, for the scene at `scene`.
fn world_matrices(doc: &gltf::Document, scene: usize) -> BTreeMap<String, Matrix4<f32>> {
    fn walk(node: gltf::Node, parent: Matrix4<f32>, out: &mut BTreeMap<String, Matrix4<f32>>) {
        let world = parent * Matrix4::from(node.transform().matrix());
        let name = node.name().expect("every node is named").to_owned();
        for child in node.children() {
            walk(child, world, out);
        }
        assert!(out.insert(name, world).is_none(), "node names are unique");
    }
    let mut out = BTreeMap::new();
    for node in doc.scenes().nth(scene).unwrap().nodes() {
        walk(node, Matrix4::identity(), &mut out);
    }
    out
}

fn node<'a>(doc: &'a gltf::Document, name: &str) -> gltf::Node<'a> {
    doc.nodes()
        .find(|n| n.name() == Some(name))
        .unwrap_or_else(|| panic!("no node `{name}`"))
}

fn origin_of(m: &Matrix4<f32>) -> Vector3<f32> {
    (m * Vector4::new(0.0, 0.0, 0.0, 1.0)).xyz()
}

fn extras(value: &gltf::json::Extras) -> serde_json::Value {
    serde_json::from_str(value.as_ref().expect("extras present").get()).unwrap()
}

/// A project point (millimetres, Z up) in glTF's frame (metres, Y up), before the pose's offset.
fn to_gltf(p: &Point3<f64>) -> Vector3<f32> {
    Vector3::new(p.x, p.z, -p.y).cast::<f32>() * 0.001
}

/// The world positions of the vertices of `name`'s mesh in the scene whose worlds are given.
fn world_vertices(
    gltf: &gltf::Gltf,
    worlds: &BTreeMap<String, Matrix4<f32>>,
    name: &str,
) -> Vec<Vector3<f32>> {
    let m = worlds[name];
    read_positions(gltf, &node(&gltf.document, name).mesh().unwrap())
        .iter()
        .map(|p| (m * p.push(1.0)).xyz())
        .collect()
}

#[test]
fn round_trip_through_a_gltf_reader() {
    let model = model();
    let bytes = write_glb(&model).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).expect("the output parses as glTF");
    let doc = &gltf.document;

    assert!(doc
        .as_json()
        .asset
        .generator
        .as_deref()
        .unwrap()
        .starts_with("ballast "));

    // One scene per pose holds its group alone; the last, the default, holds every pose group.
    let scene_names: Vec<_> = doc.scenes().map(|s| s.name().unwrap().to_owned()).collect();
    assert_eq!(scene_names, ["standing", "hanging", "all poses"]);
    assert_eq!(doc.default_scene().unwrap().index(), 2);
    let roots = |scene: usize| -> Vec<String> {
        doc.scenes()
            .nth(scene)
            .unwrap()
            .nodes()
            .map(|n| n.name().unwrap().to_owned())
            .collect()
    };
    assert_eq!(roots(0), ["standing"]);
    assert_eq!(roots(1), ["hanging"]);
    assert_eq!(roots(2), ["standing", "hanging"]);

    let worlds = world_matrices(doc, 2);
    // Units are in the vertices and translations: no node scales by the unit.
    for n in doc.nodes() {
        let (_, _, s) = n.transform().decomposed();
        let marker = [
            "ball",
            "centre of mass",
            "gravity",
            "string",
            "buoyancy centre",
        ]
        .iter()
        .any(|m| n.name().unwrap().ends_with(m));
        assert!(marker || s == [1.0; 3], "{:?} scales by {s:?}", n.name());
    }

    let mut spans = Vec::new();
    for pose in &model.poses {
        let p = &pose.name;
        let mut expected = vec![
            p.clone(),
            format!("{p}/body"),
            format!("{p}/body/left"),
            format!("{p}/body/left/ball"),
            format!("{p}/keel"),
            format!("{p}/keel/fore"),
            format!("{p}/keel/fore/ball"),
            format!("{p}/centre of mass"),
            format!("{p}/gravity"),
        ];
        if pose.ground.is_some() {
            expected.push(format!("{p}/support polygon"));
        }
        expected.push(if pose.suspension_point.is_some() {
            format!("{p}/string")
        } else {
            format!("{p}/buoyancy centre")
        });
        let mut names: Vec<String> = worlds
            .keys()
            .filter(|n| *n == p || n.starts_with(&format!("{p}/")))
            .cloned()
            .collect();
        names.sort();
        expected.sort();
        assert_eq!(names, expected);

        // The group: a translation only; a standing pose has its ground at height 0, a hanging
        // one keeps its height.
        let group = node(doc, p);
        let (offset, r, s) = group.transform().decomposed();
        assert_eq!((r, s), ([0.0, 0.0, 0.0, 1.0], [1.0; 3]));
        let offset = Vector3::from(offset);
        let lift = pose.ground.map_or(0.0, |g| -g as f32 * 0.001);
        assert!((offset.y - lift).abs() < 1e-7, "{offset:?}");
        assert_eq!(extras(group.extras()), pose.extras);
        let place = |q: &Point3<f64>| to_gltf(q) + offset;

        // Component vertices land where the pose puts them.
        let mut xs = Vec::new();
        for (component, name) in ["body", "keel"].iter().enumerate() {
            let t = &pose.component_transforms[component];
            let found = world_vertices(&gltf, &worlds, &format!("{p}/{name}"));
            for (v, local) in found.iter().zip(&model.components[component].positions) {
                let want = place(&(t * local));
                assert!((v - want).norm() < 1e-6, "{v:?} vs {want:?}");
                xs.push(v.x);
            }
        }
        spans.push(
            xs.iter()
                .fold((f32::MAX, f32::MIN), |(lo, hi), &x| (lo.min(x), hi.max(x))),
        );

        // Balls sit at their centres, sized by the ball radius in metres.
        for (capsule, path) in ["body/left", "keel/fore"].iter().enumerate() {
            let m = worlds[&format!("{p}/{path}/ball")];
            let t = &pose.component_transforms[model.capsules[capsule].component];
            let want = place(&(t * pose.ball_centres[capsule]));
            assert!((origin_of(&m) - want).norm() < 1e-6);
            let radius = (m * Vector4::new(1.0, 0.0, 0.0, 0.0)).xyz().norm();
            let expected = model.capsules[capsule].ball_radius as f32 * 0.001;
            assert!((radius - expected).abs() < 1e-7, "{radius} vs {expected}");
        }

        let com = place(&pose.centre_of_mass);
        let found = origin_of(&worlds[&format!("{p}/centre of mass")]);
        assert!((found - com).norm() < 1e-6, "{found:?} vs {com:?}");
        assert_eq!(
            extras(node(doc, &format!("{p}/centre of mass")).extras()),
            pose.extras
        );

        // Gravity: a thin solid from the centre of mass straight down -Y.
        let arrow = world_vertices(&gltf, &worlds, &format!("{p}/gravity"));
        let tip = arrow
            .iter()
            .fold(arrow[0], |a, v| if v.y < a.y { *v } else { a });
        let top = arrow.iter().map(|v| v.y).fold(f32::MIN, f32::max);
        assert!((top - com.y).abs() < 1e-6 && tip.y < com.y);
        assert!((tip.xz() - com.xz()).norm() < 1e-6, "{tip:?} vs {com:?}");
        let width = arrow
            .iter()
            .map(|v| (v.xz() - com.xz()).norm())
            .fold(0.0, f32::max);
        assert!(width < 0.1 * (com.y - tip.y), "a thin arrow: {width}");

        // The support polygon: thin tubes through its corners, on the ground at height 0.
        if pose.ground.is_some() {
            let tubes = world_vertices(&gltf, &worlds, &format!("{p}/support polygon"));
            for v in &tubes {
                assert!(v.y.abs() < 1e-3, "{v:?} off the ground");
            }
            for corner in &pose.support_polygon {
                let c = place(corner);
                assert!(tubes.iter().any(|v| (v - c).norm() < 1e-6));
            }
        }
    }
    // Side by side: the poses' components do not overlap along X.
    assert!(spans[0].1 < spans[1].0, "{spans:?}");

    // Every primitive is triangles: nothing is drawn as lines.
    for mesh in doc.meshes() {
        for prim in mesh.primitives() {
            assert_eq!(
                prim.mode(),
                gltf::mesh::Mode::Triangles,
                "{:?}",
                mesh.name()
            );
        }
    }

    // One mesh per component, shared by both poses, holding the input vertices in metres.
    let body_a = node(doc, "standing/body").mesh().unwrap();
    let body_b = node(doc, "hanging/body").mesh().unwrap();
    assert_eq!(body_a.index(), body_b.index());
    let expected: Vec<Vector3<f32>> = model.components[0]
        .positions
        .iter()
        .map(|p| p.coords.cast::<f32>() * 0.001)
        .collect();
    assert_eq!(read_positions(&gltf, &body_a), expected);

    // The body and the capsules are translucent, so what is inside shows; balls share a sphere.
    for name in ["standing/body", "standing/body/left"] {
        let material = node(doc, name)
            .mesh()
            .unwrap()
            .primitives()
            .next()
            .unwrap()
            .material();
        assert_eq!(material.alpha_mode(), gltf::material::AlphaMode::Blend);
        assert!(material.pbr_metallic_roughness().base_color_factor()[3] < 1.0);
    }
    let ball_meshes: Vec<_> = doc
        .nodes()
        .filter(|n| n.name().unwrap().ends_with("/ball"))
        .map(|n| n.mesh().unwrap().index())
        .collect();
    assert_eq!(ball_meshes.len(), 4);
    assert!(ball_meshes.iter().all(|&m| m == ball_meshes[0]));
}

fn read_positions(gltf: &gltf::Gltf, mesh: &gltf::Mesh) -> Vec<Vector3<f32>> {
    let prim = mesh.primitives().next().unwrap();
    let reader = prim.reader(|buffer| match buffer.source() {
        gltf::buffer::Source::Bin => gltf.blob.as_deref(),
        gltf::buffer::Source::Uri(_) => None,
    });
    reader
        .read_positions()
        .expect("positions are present")
        .map(Vector3::from)
        .collect()
}

#[test]
fn buffer_layout_follows_the_specification() {
    let bytes = write_glb(&model()).unwrap();
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    let root = gltf.document.as_json();
    assert_eq!(root.buffers.len(), 1);
    assert_eq!(
        root.buffers[0].byte_length.0 as usize,
        gltf.blob.as_ref().unwrap().len()
    );
    for view in &root.buffer_views {
        assert_eq!(view.byte_offset.map_or(0, |o| o.0) % 4, 0);
        assert!(view.target.is_some());
    }
    for mesh in gltf.document.meshes() {
        for prim in mesh.primitives() {
            let positions = prim.get(&gltf::Semantic::Positions).unwrap();
            assert_eq!(positions.data_type(), gltf::accessor::DataType::F32);
            assert!(positions.min().is_some() && positions.max().is_some());
            assert_eq!(
                positions.view().unwrap().target(),
                Some(gltf::buffer::Target::ArrayBuffer)
            );
            if let Some(indices) = prim.indices() {
                assert_eq!(indices.data_type(), gltf::accessor::DataType::U32);
                assert_eq!(
                    indices.view().unwrap().target(),
                    Some(gltf::buffer::Target::ElementArrayBuffer)
                );
            }
        }
    }
}

#[test]
fn the_same_model_gives_the_same_bytes() {
    let a = write_glb(&model()).unwrap();
    let b = write_glb(&model()).unwrap();
    assert!(a == b, "two writes of one model differ");
    // And the content does depend on the model.
    let mut other = model();
    other.poses[0].centre_of_mass.x += 1.0;
    assert!(write_glb(&other).unwrap() != a);
}

#[test]
fn any_up_axis_ends_up_as_gltf_y() {
    for up in [
        Vector3::z(),
        Vector3::y(),
        -Vector3::y(),
        Vector3::new(1.0, 1.0, 1.0).normalize(),
        -Vector3::x(),
    ] {
        let mut model = model();
        model.up = up;
        let bytes = write_glb(&model).unwrap();
        let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
        let worlds = world_matrices(&gltf.document, 1);
        // The string runs from the suspension point along project up: its tube's first vertex
        // is the centre of its bottom, its last the centre of its top.
        let tube = world_vertices(&gltf, &worlds, "hanging/string");
        let dir = (tube[tube.len() - 1] - tube[0]).normalize();
        assert!(
            (dir - Vector3::y()).norm() < 1e-5,
            "up {up:?} gives {dir:?}"
        );
    }
}

#[test]
fn empty_models_still_give_a_readable_file() {
    let empty = SceneModel {
        unit_in_metres: 0.001,
        up: Vector3::z(),
        components: Vec::new(),
        capsules: Vec::new(),
        poses: Vec::new(),
    };
    let bytes = write_glb(&empty).unwrap();
    gltf::Gltf::from_slice(&bytes).unwrap();

    // Components but no poses: one scene shows them as they are.
    let mut rest = model();
    rest.poses.clear();
    let gltf = gltf::Gltf::from_slice(&write_glb(&rest).unwrap()).unwrap();
    assert_eq!(gltf.document.scenes().count(), 1);
    let names: Vec<_> = gltf
        .document
        .nodes()
        .map(|n| n.name().unwrap().to_owned())
        .collect();
    assert!(names.contains(&"components/body/left".to_owned()));
    assert!(!names.iter().any(|n| n.ends_with("/ball")));

    // Poses without capsules or support.
    let mut bare = model();
    bare.capsules.clear();
    for pose in &mut bare.poses {
        pose.ball_centres.clear();
        pose.support_polygon.truncate(1);
        pose.extras = serde_json::Value::Null;
    }
    let gltf = gltf::Gltf::from_slice(&write_glb(&bare).unwrap()).unwrap();
    assert!(gltf
        .document
        .nodes()
        .all(|n| !n.name().unwrap().ends_with("support polygon")));
    assert!(node(&gltf.document, "standing").extras().is_none());
}

#[test]
fn repeated_names_stay_unique() {
    let mut model = model();
    model.components[1].name = "body".to_owned();
    model.poses[1].name = "standing".to_owned();
    let gltf = gltf::Gltf::from_slice(&write_glb(&model).unwrap()).unwrap();
    let mut names: Vec<_> = gltf
        .document
        .nodes()
        .map(|n| n.name().unwrap().to_owned())
        .collect();
    let count = names.len();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), count);
}

#[test]
fn inconsistent_models_are_refused() {
    let mut m = model();
    m.capsules[1].component = 2;
    assert!(matches!(
        write_glb(&m),
        Err(GltfError::ComponentOutOfRange {
            component: 2,
            count: 2,
            ..
        })
    ));

    let mut m = model();
    m.poses[1].ball_centres.pop();
    assert!(matches!(
        write_glb(&m),
        Err(GltfError::BallCount {
            expected: 2,
            found: 1,
            ..
        })
    ));

    let mut m = model();
    m.poses[0].component_transforms.push(Isometry3::identity());
    assert!(matches!(
        write_glb(&m),
        Err(GltfError::TransformCount { .. })
    ));

    let mut m = model();
    m.components[1].triangles.push([0, 1, 4]);
    assert!(matches!(
        write_glb(&m),
        Err(GltfError::TriangleOutOfRange {
            index: 4,
            vertices: 4,
            ..
        })
    ));

    let mut m = model();
    m.poses[0].centre_of_mass.y = f64::NAN;
    assert!(matches!(write_glb(&m), Err(GltfError::NonFinite(_))));

    let mut m = model();
    m.up = Vector3::zeros();
    assert!(matches!(write_glb(&m), Err(GltfError::InvalidUp(_))));

    let mut m = model();
    m.unit_in_metres = 0.0;
    assert!(matches!(write_glb(&m), Err(GltfError::InvalidUnit(_))));
}

/// Writes sample files for the Khronos validator (`.ci/validate-gltf.mjs`).
#[test]
fn writes_samples_for_the_validator() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let mut rest = model();
    rest.poses.clear();
    let empty = SceneModel {
        unit_in_metres: 1.0,
        up: Vector3::y(),
        components: Vec::new(),
        capsules: Vec::new(),
        poses: Vec::new(),
    };
    for (name, model) in [
        ("emit-sample", model()),
        ("emit-rest", rest),
        ("emit-empty", empty),
    ] {
        let bytes = write_glb(&model).unwrap();
        ballast::emit::write_atomic(&dir.join(format!("{name}.glb")), &bytes).unwrap();
    }
}
