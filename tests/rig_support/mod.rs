//! Rigs written as GLB files for the tests: boxes hung under joint nodes, and animations of the
//! joints, in glTF's own terms (metres, +Y up).

use crate::glb_support::glb;

/// One node: a joint, or a joint with a box mesh in its local frame.
pub struct Joint {
    /// The node's name.
    pub name: &'static str,
    /// The index of its parent among the joints, if any.
    pub parent: Option<usize>,
    /// Its local translation.
    pub translation: [f32; 3],
    /// Its local rotation, `x, y, z, w`.
    pub rotation: [f32; 4],
    /// Its local scale.
    pub scale: [f32; 3],
    /// A box `[min, max]` in the node's local frame, when the node has a mesh.
    pub mesh: Option<[[f32; 3]; 2]>,
    /// Whether the node is given a skin (its mesh then bends with joints).
    pub skinned: bool,
}

impl Joint {
    /// A joint at `translation` under `parent`, not turned, with an optional box.
    pub fn new(
        name: &'static str,
        parent: Option<usize>,
        translation: [f32; 3],
        mesh: Option<[[f32; 3]; 2]>,
    ) -> Joint {
        Joint {
            name,
            parent,
            translation,
            rotation: [0.0, 0.0, 0.0, 1.0],
            scale: [1.0; 3],
            mesh,
            skinned: false,
        }
    }
}

/// One channel of an animation: a joint's `translation`, `rotation` or `scale` at key times.
pub struct Channel {
    /// The joint it moves.
    pub joint: usize,
    /// `translation`, `rotation` or `scale`.
    pub path: &'static str,
    /// `LINEAR`, `STEP` or `CUBICSPLINE`.
    pub interpolation: &'static str,
    /// The key times, seconds.
    pub times: Vec<f32>,
    /// The values, flattened (4 per key for rotations, 3 otherwise).
    pub values: Vec<f32>,
}

/// A named animation.
pub struct Animation {
    /// Its name.
    pub name: &'static str,
    /// Its channels.
    pub channels: Vec<Channel>,
}

/// The rotation quaternion `x, y, z, w` of `degrees` about the unit `axis`.
pub fn turn(axis: [f32; 3], degrees: f32) -> [f32; 4] {
    let half = degrees.to_radians() / 2.0;
    let s = half.sin();
    [axis[0] * s, axis[1] * s, axis[2] * s, half.cos()]
}

/// The 8 corners of the box `[min, max]` and its 12 triangles, counter-clockwise from outside.
fn box_mesh([min, max]: [[f32; 3]; 2]) -> (Vec<[f32; 3]>, Vec<[u16; 3]>) {
    let corners = (0..8)
        .map(|i| {
            let pick = |bit: usize, axis: usize| if i & bit == 0 { min[axis] } else { max[axis] };
            [pick(1, 0), pick(2, 1), pick(4, 2)]
        })
        .collect();
    let triangles = vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ];
    (corners, triangles)
}

/// The GLB file of `joints` and `animations`: one scene of the root joints.
pub fn rig_glb(joints: &[Joint], animations: &[Animation]) -> Vec<u8> {
    scenes_glb(joints, animations, &[])
}

/// The GLB file of `joints` and `animations` with the named `scenes`, each its root joints, the
/// first the default; without scenes, one unnamed scene of the root joints.
pub fn scenes_glb(
    joints: &[Joint],
    animations: &[Animation],
    scenes: &[(&str, Vec<usize>)],
) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut push = |bytes: Vec<u8>, accessor: serde_json::Value| -> usize {
        let view = views.len();
        views.push(serde_json::json!({
            "buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()
        }));
        bin.extend_from_slice(&bytes);
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        let mut accessor = accessor;
        accessor["bufferView"] = view.into();
        accessors.push(accessor);
        accessors.len() - 1
    };
    let floats = |values: &[f32]| {
        values
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect::<Vec<_>>()
    };
    let mut meshes = Vec::new();
    let mut nodes = Vec::new();
    for joint in joints {
        let mut node = serde_json::json!({
            "name": joint.name,
            "translation": joint.translation,
            "rotation": joint.rotation,
            "scale": joint.scale,
        });
        if let Some(bounds) = joint.mesh {
            let (corners, triangles) = box_mesh(bounds);
            let flat: Vec<f32> = corners.iter().flatten().copied().collect();
            let positions = push(
                floats(&flat),
                serde_json::json!({
                    "componentType": 5126, "count": 8, "type": "VEC3",
                    "min": bounds[0], "max": bounds[1]
                }),
            );
            let indices = push(
                triangles
                    .iter()
                    .flatten()
                    .flat_map(|i| i.to_le_bytes())
                    .collect(),
                serde_json::json!({"componentType": 5123, "count": 36, "type": "SCALAR"}),
            );
            node["mesh"] = meshes.len().into();
            meshes.push(serde_json::json!({
                "name": joint.name,
                "primitives": [{"attributes": {"POSITION": positions}, "indices": indices}]
            }));
            if joint.skinned {
                node["skin"] = 0.into();
            }
        }
        let children: Vec<usize> = (0..joints.len())
            .filter(|&child| joints[child].parent == Some(nodes.len()))
            .collect();
        if !children.is_empty() {
            node["children"] = children.into();
        }
        nodes.push(node);
    }
    let mut clips = Vec::new();
    for animation in animations {
        let mut samplers = Vec::new();
        let mut channels = Vec::new();
        for channel in &animation.channels {
            let min = channel.times.iter().copied().fold(f32::INFINITY, f32::min);
            let max = channel
                .times
                .iter()
                .copied()
                .fold(f32::NEG_INFINITY, f32::max);
            let input = push(
                floats(&channel.times),
                serde_json::json!({
                    "componentType": 5126, "count": channel.times.len(), "type": "SCALAR",
                    "min": [min], "max": [max]
                }),
            );
            let width = if channel.path == "rotation" { 4 } else { 3 };
            let kind = if width == 4 { "VEC4" } else { "VEC3" };
            let output = push(
                floats(&channel.values),
                serde_json::json!({
                    "componentType": 5126, "count": channel.values.len() / width, "type": kind
                }),
            );
            channels.push(serde_json::json!({
                "sampler": samplers.len(),
                "target": {"node": channel.joint, "path": channel.path}
            }));
            samplers.push(serde_json::json!({
                "input": input, "output": output, "interpolation": channel.interpolation
            }));
        }
        clips.push(serde_json::json!({
            "name": animation.name, "channels": channels, "samplers": samplers
        }));
    }
    let roots: Vec<usize> = (0..joints.len())
        .filter(|&joint| joints[joint].parent.is_none())
        .collect();
    let scenes: Vec<serde_json::Value> = if scenes.is_empty() {
        vec![serde_json::json!({"nodes": roots})]
    } else {
        scenes
            .iter()
            .map(|(name, roots)| serde_json::json!({"name": name, "nodes": roots}))
            .collect()
    };
    let mut json = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": scenes,
        "nodes": nodes,
        "meshes": meshes,
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors,
    });
    if !clips.is_empty() {
        json["animations"] = clips.into();
    }
    if joints.iter().any(|joint| joint.skinned) {
        json["skins"] = serde_json::json!([{"joints": [0]}]);
    }
    glb(&json, bin)
}

/// The figure of `examples/figure.kdl`, in metres, +Y up: a torso on two legs, a head and two
/// arms, each part a box under its joint, 114 mm tall.
pub fn figure() -> Vec<Joint> {
    vec![
        // 0
        Joint::new("Hips", None, [0.0, 0.05, 0.0], None),
        // 1
        Joint::new(
            "Torso",
            Some(0),
            [0.0, 0.0, 0.0],
            Some([[-0.02, 0.0, -0.012], [0.02, 0.04, 0.012]]),
        ),
        // 2
        Joint::new("Neck", Some(1), [0.0, 0.04, 0.0], None),
        // 3
        Joint::new(
            "Head",
            Some(2),
            [0.0, 0.0, 0.0],
            Some([[-0.012, 0.0, -0.012], [0.012, 0.024, 0.012]]),
        ),
        // 4
        Joint::new("Shoulder.L", Some(1), [0.02, 0.035, 0.0], None),
        // 5
        Joint::new(
            "Arm.L",
            Some(4),
            [0.0, 0.0, 0.0],
            Some([[0.0, -0.036, -0.005], [0.01, 0.0, 0.005]]),
        ),
        // 6
        Joint::new("Shoulder.R", Some(1), [-0.02, 0.035, 0.0], None),
        // 7
        Joint::new(
            "Arm.R",
            Some(6),
            [0.0, 0.0, 0.0],
            Some([[-0.01, -0.036, -0.005], [0.0, 0.0, 0.005]]),
        ),
        // 8
        Joint::new("Hip.L", Some(0), [0.01, 0.0, 0.0], None),
        // 9
        Joint::new(
            "Leg.L",
            Some(8),
            [0.0, 0.0, 0.0],
            Some([[-0.008, -0.05, -0.01], [0.008, 0.0, 0.01]]),
        ),
        // 10
        Joint::new("Hip.R", Some(0), [-0.01, 0.0, 0.0], None),
        // 11
        Joint::new(
            "Leg.R",
            Some(10),
            [0.0, 0.0, 0.0],
            Some([[-0.008, -0.05, -0.01], [0.008, 0.0, 0.01]]),
        ),
    ]
}

/// The figure's animations: `Wave` raises the right arm out sideways over one second (150°
/// about −Z, linear), `Reach` holds both arms straight forward (one STEP key, 90° about −X),
/// `Kick` swings the left leg forward (one STEP key, 80° about −X).
pub fn figure_animations() -> Vec<Animation> {
    let rest = [0.0, 0.0, 0.0, 1.0];
    let raised = turn([0.0, 0.0, 1.0], -150.0);
    let forward = turn([1.0, 0.0, 0.0], -90.0);
    vec![
        Animation {
            name: "Wave",
            channels: vec![Channel {
                joint: 6,
                path: "rotation",
                interpolation: "LINEAR",
                times: vec![0.0, 1.0],
                values: [rest, raised].concat(),
            }],
        },
        Animation {
            name: "Reach",
            channels: vec![
                Channel {
                    joint: 4,
                    path: "rotation",
                    interpolation: "STEP",
                    times: vec![0.0],
                    values: forward.to_vec(),
                },
                Channel {
                    joint: 6,
                    path: "rotation",
                    interpolation: "STEP",
                    times: vec![0.0],
                    values: forward.to_vec(),
                },
            ],
        },
        Animation {
            name: "Kick",
            channels: vec![Channel {
                joint: 8,
                path: "rotation",
                interpolation: "STEP",
                times: vec![0.0],
                values: turn([1.0, 0.0, 0.0], -80.0).to_vec(),
            }],
        },
    ]
}
