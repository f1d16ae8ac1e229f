//! Loading OBJ, glTF and GLB files: part selection, transforms, welding and error paths.

mod geometry_support;

use std::borrow::Cow;
use std::path::Path;

use ballast::geometry::{
    check_mesh, load_mesh, load_mesh_with, mass_properties, LoadError, MeshSelector, ReadPolicy,
    TriMesh,
};
use geometry_support::{fixture, shared_mesh};
use nalgebra::Point3;

fn node(name: &str) -> MeshSelector {
    MeshSelector::GltfNode(name.to_string())
}

fn load(path: &Path, selector: &MeshSelector) -> TriMesh {
    load_mesh(path, selector).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn sorted_positions(mesh: &TriMesh) -> Vec<[f64; 3]> {
    let mut p: Vec<[f64; 3]> = mesh.positions.iter().map(|p| [p.x, p.y, p.z]).collect();
    p.sort_by(|a, b| a.partial_cmp(b).unwrap());
    p
}

fn assert_points_close(actual: &[[f64; 3]], expected: &[[f64; 3]]) {
    assert_eq!(actual.len(), expected.len(), "{actual:?}");
    for (a, e) in actual.iter().zip(expected) {
        let d = (0..3).map(|i| (a[i] - e[i]).abs()).fold(0.0, f64::max);
        assert!(d < 1e-6, "{actual:?} vs {expected:?}");
    }
}

/// The fixture's tetrahedron in world frame: rotated 90° about z by `base`, lifted 2 by `arm`,
/// moved 10 along x by `rig`.
const ARM_WORLD: [[f64; 3]; 4] = [
    [9.0, 0.0, 2.0],
    [10.0, 0.0, 2.0],
    [10.0, 0.0, 3.0],
    [10.0, 1.0, 2.0],
];

#[test]
fn gltf_node_selection_applies_the_world_transform() {
    let arm = load(&fixture("two_parts.gltf"), &node("arm"));
    // 12 split vertices welded to 4.
    assert_eq!(arm.positions.len(), 4);
    assert_eq!(arm.triangles.len(), 4);
    assert_points_close(&sorted_positions(&arm), &ARM_WORLD);
    let m = mass_properties(&arm);
    assert!((m.volume - 1.0 / 6.0).abs() < 1e-6, "{}", m.volume);
    assert!(
        (m.centroid - Point3::new(9.75, 0.25, 2.25)).norm() < 1e-6,
        "{}",
        m.centroid
    );

    let base = load(&fixture("two_parts.gltf"), &node("base"));
    assert_eq!(base.positions.len(), 8, "24 split cube vertices weld to 8");
    let check = check_mesh(&base);
    assert!(check.is_closed() && check.is_oriented(), "{check:?}");
    let m = mass_properties(&base);
    assert!((m.volume - 1.0).abs() < 1e-6);
    // The unit cube rotated 90° about z spans x ∈ [−1, 0], then moved by 10.
    assert!(
        (m.centroid - Point3::new(9.5, 0.5, 0.5)).norm() < 1e-6,
        "{}",
        m.centroid
    );
}

#[test]
fn gltf_node_without_mesh_gathers_its_descendants() {
    let rig = load(&fixture("two_parts.gltf"), &node("rig"));
    let whole = load(&fixture("two_parts.gltf"), &MeshSelector::Whole);
    assert_eq!(rig, whole);
    assert_eq!(whole.positions.len(), 12);
    assert_eq!(whole.triangles.len(), 16);
    assert!((mass_properties(&whole).volume - 7.0 / 6.0).abs() < 1e-6);
    // Both parts keep their world frames.
    let arm = load(&fixture("two_parts.gltf"), &node("arm"));
    assert!(sorted_positions(&arm)
        .iter()
        .all(|p| sorted_positions(&whole).contains(p)));
}

#[test]
fn gltf_mesh_name_gives_the_untransformed_mesh() {
    let tetra = load(&fixture("two_parts.gltf"), &node("tetra_mesh"));
    assert_points_close(
        &sorted_positions(&tetra),
        &[
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
        ],
    );
}

#[test]
fn gltf_external_buffer_matches_embedded() {
    for part in ["arm", "base", "rig"] {
        assert_eq!(
            load(&fixture("two_parts_external.gltf"), &node(part)),
            load(&fixture("two_parts.gltf"), &node(part)),
        );
    }
}

#[test]
fn gltf_unknown_part_lists_nodes_and_meshes() {
    match load_mesh(&fixture("two_parts.gltf"), &node("leg")) {
        Err(LoadError::UnknownPart { name, available }) => {
            assert_eq!(name, "leg");
            assert_eq!(available, ["arm", "base", "cube_mesh", "rig", "tetra_mesh"]);
        }
        other => panic!("expected UnknownPart, got {other:?}"),
    }
}

/// Writes `text` as `name` in a fresh temporary folder (kept alive by the returned guard).
fn write_temp(name: &str, bytes: &[u8]) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    (dir, path)
}

fn fixture_text() -> String {
    std::fs::read_to_string(fixture("two_parts.gltf")).unwrap()
}

#[test]
fn gltf_duplicate_node_names_are_ambiguous() {
    let text = fixture_text().replace("\"name\": \"arm\"", "\"name\": \"base\"");
    let (_dir, path) = write_temp("dup.gltf", text.as_bytes());
    match load_mesh(&path, &node("base")) {
        Err(LoadError::AmbiguousPart { name, count }) => {
            assert_eq!((name.as_str(), count), ("base", 2));
        }
        other => panic!("expected AmbiguousPart, got {other:?}"),
    }
}

#[test]
fn gltf_non_triangle_primitive_is_rejected() {
    let text = fixture_text().replacen("\"mode\": 4", "\"mode\": 5", 1);
    let (_dir, path) = write_temp("strip.gltf", text.as_bytes());
    match load_mesh(&path, &node("base")) {
        Err(LoadError::UnsupportedPrimitive { mode }) => assert_eq!(mode, "TRIANGLE_STRIP"),
        other => panic!("expected UnsupportedPrimitive, got {other:?}"),
    }
    // The other part is still loadable.
    assert_eq!(load(&path, &node("tetra_mesh")).triangles.len(), 4);
}

#[test]
fn gltf_accessor_past_its_buffer_is_an_error() {
    let text = fixture_text().replace("\"count\": 36", "\"count\": 3600");
    let (_dir, path) = write_temp("long.gltf", text.as_bytes());
    assert!(matches!(
        load_mesh(&path, &node("base")),
        Err(LoadError::Gltf { .. })
    ));
}

#[test]
fn gltf_bad_buffer_uris_are_errors() {
    let external = std::fs::read_to_string(fixture("two_parts_external.gltf")).unwrap();
    for uri in ["%FF%FE.bin", "missing.bin", "https://example.com/x.bin"] {
        let text = external.replace("two_parts.bin", uri);
        let (_dir, path) = write_temp("bad_uri.gltf", text.as_bytes());
        assert!(
            matches!(
                load_mesh(&path, &MeshSelector::Whole),
                Err(LoadError::Gltf { .. })
            ),
            "{uri}"
        );
    }
}

/// The fixture as GLB: the external variant's JSON without the buffer URI, plus the .bin.
fn fixture_glb(edit_bin: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixture("two_parts_external.gltf")).unwrap())
            .unwrap();
    json["buffers"][0].as_object_mut().unwrap().remove("uri");
    let mut bin = std::fs::read(fixture("two_parts.bin")).unwrap();
    edit_bin(&mut bin);
    let json = serde_json::to_vec(&json).unwrap();
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: 0, // computed by to_vec
        },
        json: Cow::Owned(json),
        bin: Some(Cow::Owned(bin)),
    };
    glb.to_vec().unwrap()
}

#[test]
fn glb_loads_like_gltf() {
    let (_dir, path) = write_temp("two_parts.GLB", &fixture_glb(|_| {}));
    for part in ["arm", "base", "rig"] {
        assert_eq!(
            load(&path, &node(part)),
            load(&fixture("two_parts.gltf"), &node(part))
        );
    }
}

#[test]
fn glb_index_out_of_range_is_an_error() {
    // Index buffer starts right after the 24 cube positions (288 bytes); point it at vertex 999.
    let bytes = fixture_glb(|bin| bin[288..290].copy_from_slice(&999u16.to_le_bytes()));
    let (_dir, path) = write_temp("bad_index.glb", &bytes);
    assert!(matches!(
        load_mesh(&path, &node("base")),
        Err(LoadError::Gltf { .. })
    ));
}

#[test]
fn glb_garbage_is_an_error_not_a_panic() {
    let good = fixture_glb(|_| {});
    let mut cases: Vec<Vec<u8>> = vec![
        Vec::new(),
        b"glTF".to_vec(),
        [b"glTF".as_slice(), &2u32.to_le_bytes(), &0u32.to_le_bytes()].concat(),
        [
            b"glTF".as_slice(),
            &2u32.to_le_bytes(),
            &u32::MAX.to_le_bytes(),
        ]
        .concat(),
        good[..good.len() / 2].to_vec(),
        good[..40].to_vec(),
    ];
    // Pseudo-random bytes, with and without the GLB magic.
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    for len in [1, 7, 12, 20, 64, 1000] {
        let noise: Vec<u8> = (0..len)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                state as u8
            })
            .collect();
        cases.push([b"glTF".as_slice(), &2u32.to_le_bytes(), &noise].concat());
        cases.push(noise);
    }
    // Every single-byte corruption of the header and JSON chunk start.
    for i in 0..64 {
        let mut bytes = good.clone();
        bytes[i] ^= 0xa5;
        cases.push(bytes);
    }
    for bytes in cases {
        let (_dir, path) = write_temp("garbage.glb", &bytes);
        let _ = load_mesh(&path, &MeshSelector::Whole);
        let (_dir, path) = write_temp("garbage.obj", &bytes);
        let _ = load_mesh(&path, &MeshSelector::Whole);
    }
    let (_dir, path) = write_temp("noise.glb", &[0x13, 0x37, 0x00, 0xff, 0x42]);
    assert!(matches!(
        load_mesh(&path, &MeshSelector::Whole),
        Err(LoadError::Gltf { .. })
    ));
}

#[test]
fn missing_file_is_not_found() {
    let path = fixture("no_such_mesh.obj");
    match load_mesh(&path, &MeshSelector::Whole) {
        Err(LoadError::NotFound { path: p }) => assert_eq!(p, path),
        other => panic!("expected NotFound, got {other:?}"),
    }
}

#[test]
fn directory_is_not_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("folder.obj");
    std::fs::create_dir(&path).unwrap();
    assert!(matches!(
        load_mesh(&path, &MeshSelector::Whole),
        Err(LoadError::NotAFile { .. })
    ));
}

#[test]
fn unknown_extension_is_rejected() {
    for (name, ext) in [("part.dxf", "dxf"), ("part", ""), ("part.obj.bak", "bak")] {
        match load_mesh(Path::new(name), &MeshSelector::Whole) {
            Err(LoadError::UnknownFormat { extension }) => assert_eq!(extension, ext),
            other => panic!("{name}: expected UnknownFormat, got {other:?}"),
        }
    }
}

#[test]
fn obj_extension_is_case_insensitive_and_empty_files_are_empty() {
    let text = "o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let (_dir, path) = write_temp("tri.OBJ", text.as_bytes());
    // The one triangle, and its reverse capping the hole it leaves open.
    assert_eq!(
        load(&path, &MeshSelector::Whole).triangles,
        vec![[0, 1, 2], [2, 1, 0]]
    );
    let (_dir, path) = write_temp("points.obj", b"v 0 0 0\nv 1 0 0\n");
    assert!(matches!(
        load_mesh(&path, &MeshSelector::Whole),
        Err(LoadError::Empty)
    ));
    let (_dir, path) = write_temp("nan.obj", b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    assert!(matches!(
        load_mesh(&path, &MeshSelector::Whole),
        Err(LoadError::NonFinite { index: 1 })
    ));
}

#[test]
fn poppy_unknown_object_lists_the_links() {
    let Some(path) = shared_mesh("poppy_humanoid.obj") else {
        return;
    };
    match load_mesh(&path, &MeshSelector::ObjObject("tail".into())) {
        Err(LoadError::UnknownPart { name, available }) => {
            assert_eq!(name, "tail");
            assert_eq!(available.len(), 26);
            assert!(
                available.windows(2).all(|w| w[0] < w[1]),
                "sorted: {available:?}"
            );
            assert!(available.iter().any(|n| n == "head"));
            assert!(available.iter().any(|n| n == "l_thigh"));
        }
        other => panic!("expected UnknownPart, got {other:?}"),
    }
}

#[test]
fn poppy_whole_merges_all_links() {
    let Some(path) = shared_mesh("poppy_humanoid.obj") else {
        return;
    };
    let loaded = load_mesh_with(
        &path,
        &MeshSelector::Whole,
        &ReadPolicy::within(path.parent().unwrap()),
    )
    .unwrap();
    // 3,951 in the file; 4 repeated (two faces and their reverses) left out, and one hole of
    // 5 edges capped by 5.
    assert_eq!(loaded.repairs.repeated_triangles, 4);
    assert_eq!(
        loaded
            .repairs
            .holes
            .iter()
            .map(|h| h.edges)
            .collect::<Vec<_>>(),
        [5]
    );
    let whole = loaded.mesh;
    assert_eq!(whole.triangles.len(), 3951 - 4 + 5);
    let parts_volume: f64 = ["head", "l_thigh", "abdomen"]
        .iter()
        .map(|n| mass_properties(&load(&path, &MeshSelector::ObjObject(n.to_string()))).volume)
        .sum();
    assert!(parts_volume > 0.0 && parts_volume < mass_properties(&whole).volume);
}

fn fixture_json() -> serde_json::Value {
    serde_json::from_str(&fixture_text()).unwrap()
}

fn load_json(json: &serde_json::Value, selector: &MeshSelector) -> Result<TriMesh, LoadError> {
    let (_dir, path) = write_temp("edited.gltf", &serde_json::to_vec(json).unwrap());
    load_mesh(&path, selector)
}

#[test]
fn gltf_sparse_accessor_is_applied() {
    let mut json = fixture_json();
    // Replace tetra vertex 0 by cube vertex 2, (1, 1, 0): sparse index 0 is the first u16 of
    // the index view (which is 0), the value is 24 bytes into the cube positions.
    json["accessors"][2]["sparse"] = serde_json::json!({
        "count": 1,
        "indices": {"bufferView": 1, "byteOffset": 0, "componentType": 5123},
        "values": {"bufferView": 0, "byteOffset": 24}
    });
    let (_dir, path) = write_temp("edited.gltf", &serde_json::to_vec(&json).unwrap());
    let loaded = load_mesh_with(
        &path,
        &node("tetra_mesh"),
        &ReadPolicy::within(path.parent().unwrap()),
    )
    .unwrap();
    assert!(loaded.mesh.positions.contains(&Point3::new(1.0, 1.0, 0.0)));
    // The file's 5 positions, and a cap's centre for each hole of more than 3 edges.
    let centres = loaded.repairs.holes.iter().filter(|h| h.edges > 3).count();
    assert_eq!(loaded.mesh.positions.len() - centres, 5);
}

#[test]
fn gltf_malformed_documents_are_errors_not_panics() {
    use serde_json::json;
    let edits: Vec<(&str, serde_json::Value)> = vec![
        ("/accessors/0/count", json!(0)),
        ("/accessors/1/count", json!(0)),
        ("/accessors/1/count", json!(35)),
        ("/accessors/0/count", json!(u32::MAX)),
        ("/accessors/0/byteOffset", json!(u32::MAX)),
        ("/accessors/0/type", json!("VEC2")),
        ("/accessors/0/componentType", json!(5121)),
        ("/accessors/1/componentType", json!(5126)),
        ("/accessors/1/type", json!("VEC3")),
        ("/bufferViews/0/byteLength", json!(4)),
        ("/bufferViews/0/byteOffset", json!(u32::MAX)),
        ("/bufferViews/0/byteStride", json!(4)),
        ("/bufferViews/0/byteStride", json!(252)),
        ("/bufferViews/0/buffer", json!(7)),
        ("/buffers/0/byteLength", json!(99999)),
        (
            "/buffers/0/uri",
            json!("data:application/octet-stream;base64,@@@@"),
        ),
        ("/nodes/2/children", json!([0])),
        ("/nodes/0/children", json!([0])),
        ("/nodes/0/children", json!([1, 1])),
        ("/nodes/1/children", json!([9])),
        ("/nodes/1/rotation", json!([0.0, 0.0, 0.0, 0.0])),
        ("/nodes/1/mesh", json!(5)),
        ("/scenes/0/nodes", json!([7])),
        ("/meshes/0/primitives/0/attributes", json!({})),
        (
            "/accessors/0",
            json!({"componentType": 5126, "count": 1_000_000_000, "type": "VEC3"}),
        ),
    ];
    for (pointer, value) in edits {
        let mut json = fixture_json();
        let (parent, key) = pointer.rsplit_once('/').unwrap();
        match json
            .pointer_mut(parent)
            .unwrap_or_else(|| panic!("{pointer}"))
        {
            serde_json::Value::Object(map) => {
                map.insert(key.to_string(), value.clone());
            }
            serde_json::Value::Array(items) => items[key.parse::<usize>().unwrap()] = value.clone(),
            _ => panic!("{pointer}"),
        }
        for selector in [
            MeshSelector::Whole,
            node("base"),
            node("arm"),
            node("cube_mesh"),
        ] {
            if let Ok(mesh) = load_json(&json, &selector) {
                // Whatever loads must be a valid mesh.
                let n = mesh.positions.len() as u32;
                assert!(
                    mesh.triangles.iter().flatten().all(|&i| i < n),
                    "{pointer} = {value}"
                );
            }
        }
    }
    // A cycle in the node tree is reported as such.
    let mut json = fixture_json();
    json["nodes"][2]["children"] = json!([0]);
    match load_json(&json, &node("arm")) {
        Err(LoadError::Gltf { message }) => assert!(
            message.contains("cycle") || message.contains("parent"),
            "{message}"
        ),
        other => panic!("expected a glTF error, got {other:?}"),
    }
}

#[test]
fn gltf_whole_without_a_default_scene() {
    let expected = load(&fixture("two_parts.gltf"), &MeshSelector::Whole);
    // No `scene`: the first scene.
    let mut json = fixture_json();
    json.as_object_mut().unwrap().remove("scene");
    assert_eq!(load_json(&json, &MeshSelector::Whole).unwrap(), expected);
    // No scenes at all: every root node.
    json.as_object_mut().unwrap().remove("scenes");
    assert_eq!(load_json(&json, &MeshSelector::Whole).unwrap(), expected);
    // A scene that only holds the arm: just the arm, still in its world frame.
    let mut json = fixture_json();
    json["scenes"][0]["nodes"] = serde_json::json!([2]);
    assert_eq!(
        load_json(&json, &MeshSelector::Whole).unwrap(),
        load(&fixture("two_parts.gltf"), &node("arm"))
    );
}

#[test]
fn gltf_mirroring_transform_keeps_triangles_outward() {
    let mut json = fixture_json();
    json["nodes"][1]["scale"] = serde_json::json!([-1.0, 2.0, 1.0]);
    let base = load_json(&json, &node("base")).unwrap();
    let check = check_mesh(&base);
    assert!(
        check.is_closed() && check.is_oriented() && !check.is_inverted(),
        "{check:?}"
    );
    assert!((mass_properties(&base).volume - 2.0).abs() < 1e-6);
}
