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
                    Point3::new(0.0, 0.0, 0.0),
                    Point3::new(100.0, 0.0, 0.0),
                    Point3::new(100.0, 100.0, 0.0),
                    Point3::new(0.0, 100.0, 0.0),
                ],
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

fn close(a: &[f32], b: &[f32], tol: f32) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

fn extras(value: &gltf::json::Extras) -> serde_json::Value {
    serde_json::from_str(value.as_ref().expect("extras present").get()).unwrap()
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

    let scene_names: Vec<_> = doc.scenes().map(|s| s.name().unwrap().to_owned()).collect();
    assert_eq!(scene_names, ["standing", "hanging"]);

    for (scene, pose) in model.poses.iter().enumerate() {
        let p = &pose.name;
        let worlds = world_matrices(doc, scene);
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
            format!("{p}/support polygon"),
        ];
        expected.push(if pose.suspension_point.is_some() {
            format!("{p}/string")
        } else {
            format!("{p}/buoyancy centre")
        });
        expected.sort();
        assert_eq!(worlds.keys().cloned().collect::<Vec<_>>(), expected);

        // The root turns project up (Z) onto glTF +Y and scales millimetres to metres.
        let root = node(doc, p);
        let (t, r, s) = root.transform().decomposed();
        assert_eq!(t, [0.0; 3]);
        assert!(close(&s, &[0.001; 3], 1e-9));
        let up_to_y =
            UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(r[3], r[0], r[1], r[2]));
        assert!((up_to_y * Vector3::<f32>::z() - Vector3::y()).norm() < 1e-6);
        assert_eq!(extras(root.extras()), pose.extras);

        // Component nodes carry the pose's isometry exactly (to single precision).
        for (component, name) in ["body", "keel"].iter().enumerate() {
            let iso = &pose.component_transforms[component];
            let (t, r, s) = node(doc, &format!("{p}/{name}")).transform().decomposed();
            let v = iso.translation.vector.cast::<f32>();
            assert!(close(&t, &[v.x, v.y, v.z], 1e-4), "{t:?} vs {v:?}");
            let q = iso.rotation.coords.cast::<f32>();
            let same = close(&r, &[q.x, q.y, q.z, q.w], 1e-6);
            let opposite = close(&r, &[-q.x, -q.y, -q.z, -q.w], 1e-6);
            assert!(same || opposite, "{r:?} vs {q:?}");
            assert_eq!(s, [1.0; 3]);
        }

        // Balls sit at the given centres, sized by the ball radius, under their component.
        for (capsule, path) in ["body/left", "keel/fore"].iter().enumerate() {
            let ball = node(doc, &format!("{p}/{path}/ball"));
            let (t, _, s) = ball.transform().decomposed();
            let c = pose.ball_centres[capsule].cast::<f32>();
            assert!(close(&t, &[c.x, c.y, c.z], 1e-4));
            assert!(close(
                &s,
                &[model.capsules[capsule].ball_radius as f32; 3],
                1e-6
            ));
        }

        // The centre of mass in glTF world: (x, y, z) mm, Z up, becomes (x, z, -y) / 1000 m.
        let com = pose.centre_of_mass.cast::<f32>();
        let expected = Vector3::new(com.x, com.z, -com.y) * 0.001;
        let found = origin_of(&worlds[&format!("{p}/centre of mass")]);
        assert!(
            (found - expected).norm() < 1e-6,
            "{found:?} vs {expected:?}"
        );
        assert_eq!(
            extras(node(doc, &format!("{p}/centre of mass")).extras()),
            pose.extras
        );

        // Gravity starts at the centre of mass and points down glTF -Y.
        let gravity = node(doc, &format!("{p}/gravity"));
        let to_world = worlds[&format!("{p}/gravity")];
        let positions = read_positions(&gltf, &gravity.mesh().unwrap());
        let start = (to_world * positions[0].push(1.0)).xyz();
        let tip = (to_world * positions[1].push(1.0)).xyz();
        assert!((start - expected).norm() < 1e-6);
        let down = (tip - start).normalize();
        assert!((down + Vector3::y()).norm() < 1e-5, "{down:?}");
    }

    // The support polygon: a loop through four points, then a single segment.
    let standing = node(doc, "standing/support polygon").mesh().unwrap();
    let prim = standing.primitives().next().unwrap();
    assert_eq!(prim.mode(), gltf::mesh::Mode::LineLoop);
    assert_eq!(read_positions(&gltf, &standing).len(), 4);
    let hanging = node(doc, "hanging/support polygon").mesh().unwrap();
    assert_eq!(
        hanging.primitives().next().unwrap().mode(),
        gltf::mesh::Mode::Lines
    );

    // One mesh per component, shared by both poses, holding the input vertices.
    let body_a = node(doc, "standing/body").mesh().unwrap();
    let body_b = node(doc, "hanging/body").mesh().unwrap();
    assert_eq!(body_a.index(), body_b.index());
    let expected: Vec<Vector3<f32>> = model.components[0]
        .positions
        .iter()
        .map(|p| p.coords.cast())
        .collect();
    assert_eq!(read_positions(&gltf, &body_a), expected);
    let prim = body_a.primitives().next().unwrap();
    let material = prim.material();
    assert_eq!(material.alpha_mode(), gltf::material::AlphaMode::Opaque);
    assert!(!material.double_sided());

    // Capsules are translucent; balls share one sphere mesh.
    let capsule = node(doc, "standing/body/left").mesh().unwrap();
    let capsule_material = capsule.primitives().next().unwrap().material();
    assert_eq!(
        capsule_material.alpha_mode(),
        gltf::material::AlphaMode::Blend
    );
    assert!(
        capsule_material
            .pbr_metallic_roughness()
            .base_color_factor()[3]
            < 1.0
    );
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
        // The string runs from the suspension point along project up.
        let string = node(&gltf.document, "hanging/string");
        let positions = read_positions(&gltf, &string.mesh().unwrap());
        let m = worlds["hanging/string"];
        let dir = (m * positions[1].push(1.0) - m * positions[0].push(1.0))
            .xyz()
            .normalize();
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
