//! A mutation fuzzer for the mesh loaders (OBJ, STL, 3MF, PLY, glTF, GLB) and the mesh checks,
//! on stable Rust.
//!
//! Starts from seed files (the regression cases of tests/mesh_inputs.rs, the test meshes) and
//! mutates them: bytes flipped, inserted, deleted and duplicated, numbers swapped for extreme
//! ones, pieces of other seeds spliced in. Each input is written to a file and loaded with small
//! limits, and every mesh that loads is checked. A panic fails the test and leaves the input in
//! `target/fuzz-meshes/`.
//!
//! The budget is `BALLAST_FUZZ_SECONDS` seconds (default 3; CI runs longer) and the sequence is
//! fixed by `BALLAST_FUZZ_SEED` (default 1), so a failure can be replayed (see
//! `tests/fuzz_support`).

mod fuzz_support;

use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::time::Duration;

use fuzz_support::{budget, campaign, Rng};

use ballast::geometry::{check_mesh, load_mesh_with, MeshLimits, MeshSelector, ReadPolicy};

/// A mesh file to load: its extension and its bytes.
type Input = (&'static str, Vec<u8>);

/// Text that tends to reach edge cases when dropped into OBJ or glTF JSON.
const TOKENS: &[&str] = &[
    "0",
    "-1",
    "1",
    "2",
    "3",
    "4294967295",
    "4294967296",
    "-2147483648",
    "16777216",
    "9999999999999999999999",
    "1e400",
    "-1e400",
    "nan",
    "inf",
    "1e-320",
    "0.5",
    "\u{feff}",
    "\n",
    " ",
    "/",
    "//",
    "f ",
    "v ",
    "o ",
    "g ",
    "f 1 2\n",
    "f -1 -2 -3\n",
    "v 1e38 1e38 1e38\n",
    "\"",
    "[",
    "]",
    "{",
    "}",
    ",",
    ":",
    "null",
    "true",
    "\"uri\": \"../x.bin\"",
    "\"uri\": \"/dev/zero\"",
    "\"byteStride\": 1",
    "\"byteOffset\": 4294967295",
    "\"count\": 16777216",
    "\"mode\": 5",
    "\"componentType\": 5123",
    "\"type\": \"MAT4\"",
    "\"sparse\": {\"count\": 1}",
    "\"children\": [0]",
    "\"matrix\": [0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]",
    "data:application/octet-stream;base64,",
    "AAAA",
    "solid ",
    "endsolid\n",
    "facet normal 0 0 1\nouter loop\n",
    "vertex 1e38 0 0\n",
    "endloop\nendfacet\n",
    "<item objectid=\"1\"/>",
    "<component objectid=\"1\"/>",
    " transform=\"0 0 0 0 0 0 0 0 0 1e308 1e308 1e308\"",
    " p:path=\"/3D/3dmodel.model\"",
    "<vertex x=\"1\" y=\"nan\" z=\"0\"/>",
    "<triangle v1=\"0\" v2=\"1\" v3=\"4294967296\"/>",
    "element vertex 4294967295\n",
    "property list uchar int vertex_indices\n",
    "format binary_little_endian 1.0\n",
    "end_header\n",
];

const TETRAHEDRON_OBJ: &str =
    "o t\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvn 0 0 1\nf 1/1/1 3/1/1 2/1/1\nf 1 2 4\nf 1 4 3\nf 2 3 4 1\n";

/// The tetrahedron's positions and indices, as one little-endian buffer.
fn tetrahedron_bin() -> Vec<u8> {
    let mut bytes = Vec::new();
    for p in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]] {
        for c in p {
            bytes.extend(c.to_le_bytes());
        }
    }
    for i in [0u16, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3] {
        bytes.extend(i.to_le_bytes());
    }
    bytes
}

fn tetrahedron_json(buffer: &str) -> String {
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
        "nodes": [{{"name": "rig", "children": [1], "translation": [1, 2, 3]}},
                  {{"name": "t", "mesh": 0, "scale": [1, 1, -1]}}],
        "buffers": [{{{buffer}"byteLength": 72}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 48, "target": 34962}},
                        {{"buffer": 0, "byteOffset": 48, "byteLength": 24}}],
        "accessors": [
            {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
              "min": [0, 0, 0], "max": [1, 1, 1]}},
            {{"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"}}],
        "meshes": [{{"name": "m", "primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}}]}}"#
    )
}

/// A GLB file: the JSON chunk (padded with spaces) and the binary chunk.
fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut json = json.as_bytes().to_vec();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let mut bin = bin.to_vec();
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin);
    out
}

/// The tetrahedron as an ASCII PLY file, with a property the reader skips.
const TETRAHEDRON_PLY: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n\
    property float y\nproperty float z\nproperty uchar red\nelement face 4\n\
    property list uchar int vertex_indices\nend_header\n0 0 0 1\n1 0 0 1\n0 1 0 1\n0 0 1 1\n\
    3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

/// The tetrahedron as a big-endian binary PLY file.
fn tetrahedron_binary_ply() -> Vec<u8> {
    let mut bytes = b"ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\n\
        property double y\nproperty double z\nelement face 4\n\
        property list uchar ushort vertex_indices\nend_header\n"
        .to_vec();
    for p in [[0f64, 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]] {
        for c in p {
            bytes.extend(c.to_be_bytes());
        }
    }
    for face in [[0u16, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
        bytes.push(3);
        for i in face {
            bytes.extend(i.to_be_bytes());
        }
    }
    bytes
}

/// The tetrahedron as an ASCII STL file.
fn tetrahedron_stl() -> String {
    let corners = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
    let mut text = String::from("solid t\n");
    for triangle in [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
        text += "facet normal 0 0 0\nouter loop\n";
        for corner in triangle {
            let [x, y, z]: [f64; 3] = corners[corner];
            text += &format!("vertex {x} {y} {z}\n");
        }
        text += "endloop\nendfacet\n";
    }
    text + "endsolid t\n"
}

/// The tetrahedron as a binary STL file.
fn tetrahedron_binary_stl() -> Vec<u8> {
    let mut bytes = vec![0u8; 80];
    bytes.extend(4u32.to_le_bytes());
    let corners = [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
    for triangle in [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
        bytes.extend([0u8; 12]);
        for corner in triangle {
            for c in corners[corner] {
                bytes.extend(c.to_le_bytes());
            }
        }
        bytes.extend([0u8; 2]);
    }
    bytes
}

/// The tetrahedron as a 3MF archive, its parts stored uncompressed (so that mutations reach the
/// ZIP structure and the XML), placed by a build item through a component.
fn tetrahedron_3mf() -> Vec<u8> {
    use std::io::Write;
    let model = r#"<?xml version="1.0" encoding="UTF-8"?>
<model unit="millimeter" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">
<resources><object id="1" type="model" name="m"><mesh><vertices>
<vertex x="0" y="0" z="0"/><vertex x="1" y="0" z="0"/><vertex x="0" y="1" z="0"/><vertex x="0" y="0" z="1"/>
</vertices><triangles><triangle v1="0" v2="2" v3="1"/><triangle v1="0" v2="1" v3="3"/>
<triangle v1="0" v2="3" v3="2"/><triangle v1="1" v2="2" v3="3"/></triangles></mesh></object>
<object id="2" name="t"><components><component objectid="1" transform="1 0 0 0 1 0 0 0 1 5 0 0"/></components></object>
</resources><build><item objectid="2"/></build></model>"#;
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let stored =
        zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    zip.start_file("3D/3dmodel.model", stored).unwrap();
    zip.write_all(model.as_bytes()).unwrap();
    zip.finish().unwrap().into_inner()
}

/// The seeds: (extension, bytes).
fn seeds() -> Vec<Input> {
    use base64::Engine;
    let data_uri = format!(
        "\"uri\": \"data:application/octet-stream;base64,{}\", ",
        base64::engine::general_purpose::STANDARD.encode(tetrahedron_bin())
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut seeds = vec![
        ("obj", TETRAHEDRON_OBJ.as_bytes().to_vec()),
        ("obj", format!("\u{feff}{TETRAHEDRON_OBJ}f 1 2\nf 3\n").into_bytes()),
        ("gltf", tetrahedron_json(&data_uri).into_bytes()),
        ("gltf", tetrahedron_json("\"uri\": \"t.bin\", ").into_bytes()),
        ("glb", glb(&tetrahedron_json(""), &tetrahedron_bin())),
        ("stl", tetrahedron_stl().into_bytes()),
        ("stl", tetrahedron_binary_stl()),
        ("3mf", tetrahedron_3mf()),
        ("ply", TETRAHEDRON_PLY.as_bytes().to_vec()),
        ("ply", tetrahedron_binary_ply()),
        (
            "gltf",
            br#"{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#
                .to_vec(),
        ),
        (
            "gltf",
            br#"{"asset": {"version": "2.0"},
            "buffers": [{"uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAAAAAA==", "byteLength": 16}],
            "bufferViews": [{"buffer": 0, "byteLength": 4}, {"buffer": 0, "byteOffset": 4, "byteLength": 12}],
            "accessors": [{"componentType": 5126, "count": 16777216, "type": "VEC3",
                "min": [0, 0, 0], "max": [0, 0, 0],
                "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5125},
                           "values": {"bufferView": 1}}}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "nodes": [{"mesh": 0}, {"mesh": 0}, {"mesh": 0}, {"mesh": 0}]}"#
                .to_vec(),
        ),
    ];
    for relative in [
        "tests/data/meshes/two_parts.gltf",
        "tests/data/compile/err/meshes/overlapping_cubes.obj",
        "tests/data/compile/err/meshes/nested_cubes.obj",
        "tests/data/compile/err/meshes/hollow_cube.obj",
        "examples/meshes/hinged_arm.obj",
    ] {
        let path = root.join(relative);
        let extension = if relative.ends_with(".gltf") {
            "gltf"
        } else {
            "obj"
        };
        seeds.push((extension, std::fs::read(path).unwrap()));
    }
    seeds
}

/// One to four mutations of `input`.
fn mutate(rng: &mut Rng, input: &[u8], seeds: &[Input]) -> Vec<u8> {
    let mut out = input.to_vec();
    for _ in 0..1 + rng.below(4) {
        let at = rng.below(out.len() + 1);
        match rng.below(7) {
            0 if !out.is_empty() => {
                let i = at.min(out.len() - 1);
                out[i] ^= 1 << rng.below(8);
            }
            1 => {
                let token = TOKENS[rng.below(TOKENS.len())];
                out.splice(at..at, token.bytes());
            }
            2 if !out.is_empty() => {
                let end = (at + 1 + rng.below(16)).min(out.len());
                out.drain(at.min(end)..end);
            }
            3 => {
                // Replace the number (or word) at a random place with a token.
                let start = at.min(out.len());
                let end = out[start..]
                    .iter()
                    .position(|b| !b.is_ascii_alphanumeric() && !b"-+.".contains(b))
                    .map_or(out.len(), |n| start + n);
                let token = TOKENS[rng.below(TOKENS.len())];
                out.splice(start..end, token.bytes());
            }
            4 if !out.is_empty() => {
                // Duplicate a piece.
                let start = at.min(out.len() - 1);
                let end = (start + 1 + rng.below(64)).min(out.len());
                let piece = out[start..end].to_vec();
                out.splice(start..start, piece);
            }
            5 => {
                let other = &seeds[rng.below(seeds.len())].1;
                if !other.is_empty() {
                    let start = rng.below(other.len());
                    let end = (start + 1 + rng.below(128)).min(other.len());
                    out.splice(at..at, other[start..end].iter().copied());
                }
            }
            _ => out.push(rng.below(256) as u8),
        }
    }
    out.truncate(1 << 16);
    out
}

#[test]
fn mutated_meshes_never_panic() {
    let mut rng = Rng::from_env();
    let seeds = seeds();
    let folder = tempfile::tempdir().unwrap();
    std::fs::write(folder.path().join("t.bin"), tetrahedron_bin()).unwrap();
    let policy = ReadPolicy {
        within: Some(folder.path().to_path_buf()),
        limits: MeshLimits {
            max_bytes: 1 << 20,
            max_triangles: 20_000,
        },
    };
    let mutate =
        |rng: &mut Rng, base: &Input, seeds: &[Input]| (base.0, mutate(rng, &base.1, seeds));
    let mut selectors = Rng::from_env();
    let done = campaign(
        &seeds,
        budget(3.0),
        &mut rng,
        mutate,
        |(extension, bytes)| {
            let path = folder.path().join(format!("input.{extension}"));
            std::fs::write(&path, bytes).unwrap();
            let selector = match selectors.below(4) {
                0 => MeshSelector::GltfNode("t".into()),
                1 => MeshSelector::ObjObject("m".into()),
                _ => MeshSelector::Whole,
            };
            let outcome = std::panic::catch_unwind(AssertUnwindSafe(|| {
                load_mesh_with(&path, &selector, &policy).map(|loaded| check_mesh(&loaded.mesh))
            }));
            match outcome {
                // A loading input is a good place to mutate from.
                Ok(loaded) => loaded.is_ok(),
                Err(_) => panic!(
                    "the loader panicked: the input is saved as {}",
                    save_crash(extension, bytes).display()
                ),
            }
        },
    );
    let slowest = done.slowest.0;
    eprintln!(
        "fuzz_meshes: {} inputs, {} kept to mutate from, slowest {slowest:?}",
        done.runs, done.kept
    );
    assert!(done.runs > seeds.len());
    assert!(done.kept >= 5, "only {} mutated inputs loaded", done.kept);
    // Bounded work: no input takes long under the limits.
    assert!(slowest < Duration::from_secs(5), "{slowest:?}");
}

fn save_crash(extension: &str, bytes: &[u8]) -> PathBuf {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/fuzz-meshes");
    std::fs::create_dir_all(&folder).unwrap();
    let path = folder.join(format!("crash-{:016x}.{extension}", fnv(bytes)));
    std::fs::write(&path, bytes).unwrap();
    path
}

fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x1000_0000_01b3)
    })
}
