//! Hostile and unlucky mesh inputs: no panic, bounded work, only regular files inside the
//! project's folder (unless `--read-outside`), and each refusal a diagnostic naming its limit.

use std::path::Path;
use std::process::{Command, Output};
use std::time::Instant;

use ballast::geometry::{load_mesh_with, LoadError, MeshLimits, MeshSelector, ReadPolicy};

const TETRAHEDRON: &str =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// A tetrahedron as a glTF document whose one buffer has the URI `uri` (48 bytes of positions,
/// 24 of indices).
fn tetrahedron_gltf(uri: &str) -> String {
    format!(
        r#"{{"asset": {{"version": "2.0"}},
        "buffers": [{{"uri": "{uri}", "byteLength": 72}}],
        "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
                        {{"buffer": 0, "byteOffset": 48, "byteLength": 24}}],
        "accessors": [
            {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
              "min": [0, 0, 0], "max": [1, 1, 1]}},
            {{"bufferView": 1, "componentType": 5125, "count": 6, "type": "SCALAR"}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}],
        "nodes": [{{"mesh": 0}}]}}"#
    )
}

/// The tetrahedron's buffer: positions, then two of its triangles (enough to load).
fn tetrahedron_bin() -> Vec<u8> {
    let mut bytes = Vec::new();
    for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]] {
        for c in p {
            bytes.extend(c.to_le_bytes());
        }
    }
    for i in [0u32, 2, 1, 0, 1, 3] {
        bytes.extend(i.to_le_bytes());
    }
    bytes
}

fn anywhere() -> ReadPolicy {
    ReadPolicy {
        within: None,
        limits: MeshLimits::default(),
    }
}

/// The triangles the tetrahedron files load as: their two, and the four that cap the hole they
/// leave open.
const TETRAHEDRON_TRIANGLES: usize = 6;

fn load(path: &Path, policy: &ReadPolicy) -> Result<usize, LoadError> {
    load_mesh_with(path, &MeshSelector::Whole, policy).map(|loaded| loaded.mesh.triangles.len())
}

#[test]
fn the_85_byte_gltf_is_an_error_not_a_panic() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("p.gltf");
    let text =
        r#"{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#;
    assert_eq!(text.len(), 85);
    std::fs::write(&path, text).unwrap();
    match load(&path, &ReadPolicy::within(folder.path())) {
        Err(LoadError::Gltf { message }) => assert!(message.contains("accessor 0"), "{message}"),
        other => panic!("{other:?}"),
    }
}

/// A zero-filled accessor of `count` positions (no buffer view; one sparse value) drawn by
/// `nodes` nodes.
fn zero_filled_gltf(count: usize, nodes: usize) -> String {
    let node_list: Vec<String> = (0..nodes).map(|_| r#"{"mesh": 0}"#.to_string()).collect();
    format!(
        r#"{{"asset": {{"version": "2.0"}},
        "buffers": [{{"uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAAAAAA==", "byteLength": 16}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 4}}, {{"buffer": 0, "byteOffset": 4, "byteLength": 12}}],
        "accessors": [{{"componentType": 5126, "count": {count}, "type": "VEC3",
            "min": [0, 0, 0], "max": [0, 0, 0],
            "sparse": {{"count": 1, "indices": {{"bufferView": 0, "componentType": 5125}},
                        "values": {{"bufferView": 1}}}}}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
        "nodes": [{}]}}"#,
        node_list.join(", ")
    )
}

#[test]
fn a_huge_zero_filled_sparse_accessor_is_refused_before_it_is_decoded() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("sparse.gltf");
    let text = zero_filled_gltf(1 << 24, 8);
    assert!(text.len() < 1000, "{}", text.len());
    std::fs::write(&path, &text).unwrap();
    let start = Instant::now();
    let result = load(&path, &ReadPolicy::within(folder.path()));
    assert!(
        matches!(
            result,
            Err(LoadError::TooMany {
                what: "vertices",
                ..
            })
        ),
        "{result:?}"
    );
    // Refused from the declared count: no time spent decoding 16M elements.
    assert!(start.elapsed().as_secs_f64() < 1.0, "{:?}", start.elapsed());
}

#[test]
fn every_instance_counts_against_the_limits() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("sparse.gltf");
    // 900 vertices (300 triangles) per instance; 8 instances pass 2000 vertices.
    std::fs::write(&path, zero_filled_gltf(900, 8)).unwrap();
    let limits = MeshLimits {
        max_triangles: 700,
        ..MeshLimits::default()
    };
    let policy = ReadPolicy {
        within: Some(folder.path().to_path_buf()),
        limits,
    };
    assert!(matches!(
        load(&path, &policy),
        Err(LoadError::TooMany {
            what: "vertices",
            limit: 2100
        })
    ));
    // Two instances fit the limits; every corner is at the origin, so every triangle
    // collapses to a point and none is left.
    std::fs::write(&path, zero_filled_gltf(900, 2)).unwrap();
    assert!(matches!(load(&path, &policy), Err(LoadError::Empty)));
}

#[test]
fn buffers_outside_the_folder_are_refused_unless_allowed() {
    let outer = tempfile::tempdir().unwrap();
    let project = outer.path().join("project");
    std::fs::create_dir(&project).unwrap();
    std::fs::write(outer.path().join("outside.bin"), tetrahedron_bin()).unwrap();
    std::fs::write(project.join("inside.bin"), tetrahedron_bin()).unwrap();
    let absolute = outer.path().join("outside.bin");
    for uri in ["../outside.bin", absolute.to_str().unwrap()] {
        let path = project.join("m.gltf");
        std::fs::write(&path, tetrahedron_gltf(uri)).unwrap();
        assert!(
            matches!(
                load(&path, &ReadPolicy::within(&project)),
                Err(LoadError::OutsideFolder { .. })
            ),
            "{uri}"
        );
        assert_eq!(
            load(&path, &anywhere()).unwrap(),
            TETRAHEDRON_TRIANGLES,
            "{uri}"
        );
    }
    let path = project.join("m.gltf");
    std::fs::write(&path, tetrahedron_gltf("inside.bin")).unwrap();
    assert_eq!(
        load(&path, &ReadPolicy::within(&project)).unwrap(),
        TETRAHEDRON_TRIANGLES
    );
}

#[cfg(target_os = "linux")]
#[test]
fn device_and_proc_files_are_never_read() {
    let folder = tempfile::tempdir().unwrap();
    for uri in ["/dev/zero", "/proc/self/environ", "/dev/stdin"] {
        let path = folder.path().join("m.gltf");
        std::fs::write(&path, tetrahedron_gltf(uri)).unwrap();
        let start = Instant::now();
        let result = load(&path, &anywhere());
        assert!(
            matches!(result, Err(LoadError::NotAFile { .. })),
            "{uri}: {result:?}"
        );
        assert!(start.elapsed().as_secs_f64() < 1.0);
    }
    // A mesh path that is a device, even with an .obj name.
    let link = folder.path().join("zero.obj");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    assert!(matches!(
        load(&link, &anywhere()),
        Err(LoadError::NotAFile { .. })
    ));
}

#[test]
fn the_byte_limit_is_checked_before_reading_and_covers_the_buffers() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("m.gltf");
    let gltf = tetrahedron_gltf("m.bin");
    std::fs::write(&path, &gltf).unwrap();
    std::fs::write(folder.path().join("m.bin"), tetrahedron_bin()).unwrap();
    let policy = |max_bytes: u64| ReadPolicy {
        within: Some(folder.path().to_path_buf()),
        limits: MeshLimits {
            max_bytes,
            ..MeshLimits::default()
        },
    };
    let both = gltf.len() as u64 + 72;
    assert_eq!(load(&path, &policy(both)).unwrap(), TETRAHEDRON_TRIANGLES);
    assert!(matches!(
        load(&path, &policy(both - 1)),
        Err(LoadError::TooLarge { .. })
    ));
    assert!(matches!(
        load(&path, &policy(10)),
        Err(LoadError::TooLarge { limit: 10, .. })
    ));
}

#[test]
fn obj_quirks_a_byte_order_mark_short_faces_and_non_finite_coordinates() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("t.obj");
    std::fs::write(&path, format!("\u{feff}{TETRAHEDRON}")).unwrap();
    assert_eq!(load(&path, &ReadPolicy::within(folder.path())).unwrap(), 4);

    std::fs::write(&path, format!("{TETRAHEDRON}f 1 2\nf 3\n")).unwrap();
    let loaded = load_mesh_with(
        &path,
        &MeshSelector::Whole,
        &ReadPolicy::within(folder.path()),
    )
    .unwrap();
    assert_eq!(loaded.mesh.triangles.len(), 4);
    assert_eq!(loaded.short_faces, vec![9, 10]);

    for bad in ["nan", "inf", "1e400", "-1e999"] {
        std::fs::write(
            &path,
            TETRAHEDRON.replace("v 0 0 1", &format!("v 0 0 {bad}")),
        )
        .unwrap();
        assert!(
            matches!(
                load(&path, &ReadPolicy::within(folder.path())),
                Err(LoadError::NonFinite { index: 3 })
            ),
            "{bad}"
        );
    }
}

/// Standard error with the line wrapping undone (the renderer breaks long help lines).
fn unwrapped(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr)
        .split_whitespace()
        .collect()
}

fn ballast(args: &[&str], folder: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ballast"))
        .args(args)
        .current_dir(folder)
        .env("BALLAST_CACHE_DIR", "off")
        .output()
        .unwrap()
}

#[test]
fn the_command_line_confines_meshes_and_names_the_options_that_lift_the_limits() {
    let outer = tempfile::tempdir().unwrap();
    let project = outer.path().join("project");
    std::fs::create_dir(&project).unwrap();
    std::fs::write(outer.path().join("t.obj"), TETRAHEDRON).unwrap();
    std::fs::write(
        project.join("model.kdl"),
        "component \"T\" mesh=\"../t.obj\"\npose \"up\" { stand }\n",
    )
    .unwrap();
    let refused = ballast(&["check", "model.kdl"], &project);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("ballast::mesh::outside_project"),
        "{stderr}"
    );
    assert!(unwrapped(&refused).contains("--read-outside"), "{stderr}");

    let allowed = ballast(&["check", "--read-outside", "model.kdl"], &project);
    let stderr = String::from_utf8_lossy(&allowed.stderr);
    assert!(!stderr.contains("ballast::mesh"), "{stderr}");
    assert_ne!(allowed.status.code(), Some(2), "{stderr}");

    let small = ballast(
        &[
            "check",
            "--read-outside",
            "--max-triangles",
            "3",
            "model.kdl",
        ],
        &project,
    );
    let stderr = String::from_utf8_lossy(&small.stderr);
    assert!(
        stderr.contains("ballast::mesh::too_many_triangles"),
        "{stderr}"
    );
    assert!(unwrapped(&small).contains("--max-trianglesN"), "{stderr}");

    let tiny = ballast(
        &["check", "--read-outside", "--max-mesh-mb", "0", "model.kdl"],
        &project,
    );
    let stderr = String::from_utf8_lossy(&tiny.stderr);
    assert!(stderr.contains("ballast::mesh::too_large"), "{stderr}");
    assert!(unwrapped(&tiny).contains("--max-mesh-mbN"), "{stderr}");
}

#[test]
fn components_that_share_a_refused_file_get_one_diagnostic_naming_them() {
    let outer = tempfile::tempdir().unwrap();
    let project = outer.path().join("project");
    std::fs::create_dir(&project).unwrap();
    std::fs::write(outer.path().join("t.obj"), TETRAHEDRON).unwrap();
    let mut source = String::new();
    for name in ["a", "b", "c", "d", "e"] {
        source += &format!("component \"{name}\" mesh=\"../t.obj\"\n");
    }
    source += "component \"f\" mesh=\"missing.obj\"\npose \"up\" { stand }\n";
    std::fs::write(project.join("model.kdl"), source).unwrap();
    let refused = ballast(&["check", "model.kdl"], &project);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert_eq!(
        stderr.matches("ballast::mesh::outside_project").count(),
        1,
        "{stderr}"
    );
    assert!(
        unwrapped(&refused).contains("components`a`,`b`,`c`and2more"),
        "{stderr}"
    );
    // Another file's problem is its own diagnostic.
    assert_eq!(
        stderr.matches("ballast::mesh::not_found").count(),
        1,
        "{stderr}"
    );
}
