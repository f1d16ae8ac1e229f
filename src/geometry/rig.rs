//! A glTF or GLB file read as a rig: its nodes with their rest (world) transforms, the mesh nodes
//! of its scenes, and its animations, sampled into node world transforms at a time.
//!
//! Rigid parts hang under joint nodes, the glTF way: each mesh node moves with its parents'
//! transforms. An animation's channels replace the translation, rotation or scale of the nodes
//! they target, as the glTF specification says: before a channel's first key it holds that key's
//! value, after its last key the last value; `STEP`, `LINEAR` (rotations by spherical
//! interpolation) and `CUBICSPLINE` samplers are read. Skins and morph targets are recorded so
//! that the caller can refuse them; they deform a mesh and so are no rigid part.

use std::path::Path;

use gltf::accessor::{DataType, Dimensions};
use gltf::animation::{Interpolation, Property};
use gltf::scene::Transform;
use gltf::Accessor;
use nalgebra::{Matrix4, Quaternion, Translation3, UnitQuaternion, Vector3};

use super::load::{check_vertices, LoadError};
use super::load_files::{FileReader, MeshLimits, ReadPolicy};
use super::load_gltf::{elements, err, local_matrix, node_rotation, open_document, Hierarchy};

/// A glTF file read as a rig.
#[derive(Debug, Clone)]
pub struct Rig {
    /// Every node of the file, in index order.
    pub nodes: Vec<RigNode>,
    /// The mesh nodes of the default scene (or of the first scene; or, without scenes, of every
    /// root), depth first: the parts of a rig that lists none.
    pub scene_meshes: Vec<usize>,
    /// Every scene, in file order.
    pub scenes: Vec<RigScene>,
    /// Every animation, in file order.
    pub animations: Vec<RigAnimation>,
    /// Each node's local transform as written.
    locals: Vec<Local>,
    roots: Vec<usize>,
    children: Vec<Vec<usize>>,
}

/// One node of a rig.
#[derive(Debug, Clone)]
pub struct RigNode {
    /// The node's name, if it has one.
    pub name: Option<String>,
    /// Whether the node instances a mesh.
    pub has_mesh: bool,
    /// Whether the node's mesh is skinned (the node has a `skin`): it deforms with its joints.
    pub skinned: bool,
    /// The node's world transform as written: the product of its parents' local transforms and
    /// its own, in the file's units and axes.
    pub rest: Matrix4<f64>,
}

/// One scene of a rig: a set of root nodes. A node's world transform is the same in every scene
/// that holds it (glTF gives a node one parent at most), so a scene poses the rig's parts
/// through other nodes of the same names.
#[derive(Debug, Clone)]
pub struct RigScene {
    /// The scene's name, if it has one.
    pub name: Option<String>,
    /// The mesh nodes under its roots, depth first.
    pub meshes: Vec<usize>,
}

/// One animation of a rig.
#[derive(Debug, Clone)]
pub struct RigAnimation {
    /// The animation's name, if it has one.
    pub name: Option<String>,
    /// The time of its first key, seconds.
    pub start: f64,
    /// The time of its last key, seconds.
    pub end: f64,
    /// The most keys any of its channels has.
    pub most_keys: usize,
    channels: Vec<Channel>,
}

impl RigAnimation {
    /// The nodes whose morph target weights the animation changes (they deform their mesh).
    pub fn morphed_nodes(&self) -> impl Iterator<Item = usize> + '_ {
        self.channels
            .iter()
            .filter(|channel| channel.property == Property::MorphTargetWeights)
            .map(|channel| channel.node)
    }
}

/// A node's local transform: translation, rotation and scale, or a matrix (which no animation
/// may target).
#[derive(Debug, Clone, Copy)]
enum Local {
    Decomposed {
        translation: Vector3<f64>,
        rotation: UnitQuaternion<f64>,
        scale: Vector3<f64>,
    },
    Matrix(Matrix4<f64>),
}

#[derive(Debug, Clone)]
struct Channel {
    node: usize,
    property: Property,
    interpolation: Interpolation,
    times: Vec<f64>,
    /// Per key one value (three per key for `CUBICSPLINE`: in-tangent, value, out-tangent);
    /// translations and scales use the first three entries, rotations are `x, y, z, w`.
    values: Vec<[f64; 4]>,
}

/// Reads the glTF or GLB file at `path` as a rig, reading only what `policy` allows. Never
/// panics, whatever the file holds.
pub fn read_rig(path: &Path, policy: &ReadPolicy) -> Result<Rig, LoadError> {
    let mut reader = FileReader::new(policy);
    let bytes = reader.read(path)?;
    let base = path.parent().unwrap_or_else(|| Path::new("."));
    let (document, buffers) = open_document(&bytes, base, &mut reader)?;
    let limits = *reader.limits();
    let hierarchy = Hierarchy::new(&document)?;
    let scene_meshes = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => mesh_nodes(&hierarchy, scene.nodes().map(|node| node.index())),
        None => mesh_nodes(&hierarchy, hierarchy.roots.iter().copied()),
    };
    let scenes = document
        .scenes()
        .map(|scene| RigScene {
            name: scene.name().map(str::to_owned),
            meshes: mesh_nodes(&hierarchy, scene.nodes().map(|node| node.index())),
        })
        .collect();
    let mut nodes = Vec::new();
    let mut locals = Vec::new();
    for node in document.nodes() {
        locals.push(local(node.transform())?);
        nodes.push(RigNode {
            // Names become component names, printed in tables: no escape sequences.
            name: node
                .name()
                .map(|name| crate::diagnostic::printable(name).into_owned()),
            has_mesh: node.mesh().is_some(),
            skinned: node.skin().is_some(),
            rest: hierarchy.world[node.index()],
        });
    }
    let mut animations = Vec::new();
    for animation in document.animations() {
        let mut channels = Vec::new();
        for channel in animation.channels() {
            let node = channel.target().node().index();
            let property = channel.target().property();
            if property != Property::MorphTargetWeights
                && matches!(locals.get(node), Some(Local::Matrix(_)))
            {
                return Err(err(format!(
                    "animation {} moves node {node}, whose transform is a matrix",
                    animation.index()
                )));
            }
            let sampler = channel.sampler();
            let interpolation = sampler.interpolation();
            let times: Vec<f64> = floats(&sampler.input(), &buffers, &limits, Dimensions::Scalar)?
                .into_iter()
                .map(|key| key[0])
                .collect();
            let wanted = match property {
                Property::Rotation => Dimensions::Vec4,
                Property::MorphTargetWeights => Dimensions::Scalar,
                _ => Dimensions::Vec3,
            };
            let values = floats(&sampler.output(), &buffers, &limits, wanted)?;
            check_channel(&times, &values, interpolation, property, animation.index())?;
            channels.push(Channel {
                node,
                property,
                interpolation,
                times,
                values,
            });
        }
        let key_times = || channels.iter().flat_map(|channel| channel.times.iter());
        animations.push(RigAnimation {
            name: animation.name().map(str::to_owned),
            start: key_times().copied().fold(f64::INFINITY, f64::min),
            end: key_times().copied().fold(f64::NEG_INFINITY, f64::max),
            most_keys: channels
                .iter()
                .map(|channel| channel.times.len())
                .max()
                .unwrap_or(0),
            channels,
        });
    }
    Ok(Rig {
        nodes,
        scene_meshes,
        scenes,
        animations,
        locals,
        roots: hierarchy.roots,
        children: hierarchy.children,
    })
}

/// The mesh nodes under `roots` (the roots included), depth first, each once.
fn mesh_nodes(hierarchy: &Hierarchy, roots: impl Iterator<Item = usize>) -> Vec<usize> {
    let mut seen = vec![false; hierarchy.world.len()];
    let mut meshes = Vec::new();
    let mut stack: Vec<usize> = roots.collect();
    stack.reverse();
    while let Some(node) = stack.pop() {
        if std::mem::replace(&mut seen[node], true) {
            continue;
        }
        if hierarchy.mesh[node].is_some() {
            meshes.push(node);
        }
        stack.extend(hierarchy.children[node].iter().rev());
    }
    meshes
}

impl Rig {
    /// The world transform of every node with `animation` (an index into
    /// [`Rig::animations`]) at `time` seconds; nodes it does not move keep their own transforms.
    pub fn posed(&self, animation: usize, time: f64) -> Vec<Matrix4<f64>> {
        let mut locals = self.locals.clone();
        if let Some(animation) = self.animations.get(animation) {
            for channel in &animation.channels {
                let Some(Local::Decomposed {
                    translation,
                    rotation,
                    scale,
                }) = locals.get_mut(channel.node)
                else {
                    continue;
                };
                let value = sample(channel, time);
                let vector = Vector3::new(value[0], value[1], value[2]);
                match channel.property {
                    Property::Translation => *translation = vector,
                    Property::Scale => *scale = vector,
                    Property::Rotation => {
                        let q = Quaternion::new(value[3], value[0], value[1], value[2]);
                        if q.norm() > 0.0 {
                            *rotation = UnitQuaternion::from_quaternion(q);
                        }
                    }
                    Property::MorphTargetWeights => {}
                }
            }
        }
        let mut world = vec![Matrix4::identity(); locals.len()];
        let mut stack: Vec<(usize, Matrix4<f64>)> = self
            .roots
            .iter()
            .map(|&root| (root, Matrix4::identity()))
            .collect();
        while let Some((node, parent)) = stack.pop() {
            let own = parent * matrix(&locals[node]);
            world[node] = own;
            stack.extend(self.children[node].iter().map(|&child| (child, own)));
        }
        world
    }
}

fn local(transform: Transform) -> Result<Local, LoadError> {
    match transform {
        Transform::Matrix { .. } => Ok(Local::Matrix(local_matrix(transform)?)),
        Transform::Decomposed {
            translation: t,
            rotation: q,
            scale: s,
        } => Ok(Local::Decomposed {
            translation: Vector3::new(t[0], t[1], t[2]).cast(),
            rotation: node_rotation(q)?,
            scale: Vector3::new(s[0], s[1], s[2]).cast(),
        }),
    }
}

fn matrix(local: &Local) -> Matrix4<f64> {
    match *local {
        Local::Matrix(matrix) => matrix,
        Local::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            Translation3::from(translation).to_homogeneous()
                * rotation.to_homogeneous()
                * Matrix4::new_nonuniform_scaling(&scale)
        }
    }
}

/// The float elements of an animation accessor, each padded to four entries.
fn floats(
    accessor: &Accessor,
    buffers: &[Vec<u8>],
    limits: &MeshLimits,
    dimensions: Dimensions,
) -> Result<Vec<[f64; 4]>, LoadError> {
    let width = match dimensions {
        Dimensions::Scalar => 1,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        _ => unreachable!("animations read scalars, VEC3 and VEC4"),
    };
    if accessor.data_type() != DataType::F32
        || accessor.dimensions() != dimensions
        || accessor.normalized()
    {
        return Err(err(format!(
            "animation accessor {} is not {dimensions:?} of FLOAT (quantized animations are not \
             read)",
            accessor.index()
        )));
    }
    check_vertices(accessor.count(), limits)?;
    let values = elements(accessor, buffers, 4 * width)?
        .into_iter()
        .map(|bytes| {
            let mut value = [0.0; 4];
            for (k, entry) in value.iter_mut().enumerate().take(width) {
                let b = &bytes[4 * k..4 * k + 4];
                *entry = f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]));
            }
            value
        })
        .collect::<Vec<_>>();
    if let Some(bad) = values.iter().position(|v| !v.iter().all(|x| x.is_finite())) {
        return Err(err(format!(
            "element {bad} of animation accessor {} is not finite",
            accessor.index()
        )));
    }
    Ok(values)
}

/// Rejects a channel without keys, with key times out of order, or whose output does not hold
/// one value per key (three for `CUBICSPLINE`; for weights, any whole number per key).
fn check_channel(
    times: &[f64],
    values: &[[f64; 4]],
    interpolation: Interpolation,
    property: Property,
    animation: usize,
) -> Result<(), LoadError> {
    if times.is_empty() {
        return Err(err(format!(
            "a channel of animation {animation} has no keys"
        )));
    }
    if times.windows(2).any(|pair| pair[1] <= pair[0]) {
        return Err(err(format!(
            "the key times of a channel of animation {animation} do not increase"
        )));
    }
    let per_key = if interpolation == Interpolation::CubicSpline {
        3
    } else {
        1
    };
    let fits = if property == Property::MorphTargetWeights {
        values.len() % (per_key * times.len()) == 0
    } else {
        values.len() == per_key * times.len()
    };
    if !fits {
        return Err(err(format!(
            "a channel of animation {animation} has {} keys but {} output values",
            times.len(),
            values.len()
        )));
    }
    Ok(())
}

/// The value of `channel` at `time` (a transform channel: weights are not sampled).
fn sample(channel: &Channel, time: f64) -> [f64; 4] {
    let times = &channel.times;
    let cubic = channel.interpolation == Interpolation::CubicSpline;
    let value = |key: usize| {
        if cubic {
            channel.values[3 * key + 1]
        } else {
            channel.values[key]
        }
    };
    let last = times.len() - 1;
    if time <= times[0] {
        return value(0);
    }
    if time >= times[last] {
        return value(last);
    }
    // The key at or before `time`; `time` lies strictly inside [times[0], times[last]).
    let key = times.partition_point(|&t| t <= time) - 1;
    let (t0, t1) = (times[key], times[key + 1]);
    let s = (time - t0) / (t1 - t0);
    let rotation = channel.property == Property::Rotation;
    match channel.interpolation {
        Interpolation::Step => value(key),
        Interpolation::Linear if rotation => slerp(value(key), value(key + 1), s),
        Interpolation::Linear => lerp(value(key), value(key + 1), s),
        Interpolation::CubicSpline => {
            let (s2, s3) = (s * s, s * s * s);
            let span = t1 - t0;
            let out_tangent = channel.values[3 * key + 2];
            let in_tangent = channel.values[3 * (key + 1)];
            let (v0, v1) = (value(key), value(key + 1));
            let mut out = [0.0; 4];
            for k in 0..4 {
                out[k] = (2.0 * s3 - 3.0 * s2 + 1.0) * v0[k]
                    + (s3 - 2.0 * s2 + s) * span * out_tangent[k]
                    + (-2.0 * s3 + 3.0 * s2) * v1[k]
                    + (s3 - s2) * span * in_tangent[k];
            }
            out
        }
    }
}

fn lerp(a: [f64; 4], b: [f64; 4], s: f64) -> [f64; 4] {
    std::array::from_fn(|k| a[k] + (b[k] - a[k]) * s)
}

/// Spherical interpolation of two rotation quaternions `x, y, z, w`, the short way round.
fn slerp(a: [f64; 4], mut b: [f64; 4], s: f64) -> [f64; 4] {
    let mut dot: f64 = (0..4).map(|k| a[k] * b[k]).sum();
    if dot < 0.0 {
        b = b.map(|x| -x);
        dot = -dot;
    }
    if dot > 0.9995 {
        return lerp(a, b, s);
    }
    let angle = dot.min(1.0).acos();
    let (wa, wb) = (
        ((1.0 - s) * angle).sin() / angle.sin(),
        (s * angle).sin() / angle.sin(),
    );
    std::array::from_fn(|k| wa * a[k] + wb * b[k])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(interpolation: Interpolation, property: Property, values: Vec<[f64; 4]>) -> Channel {
        Channel {
            node: 0,
            property,
            interpolation,
            times: vec![1.0, 3.0],
            values,
        }
    }

    #[test]
    fn linear_step_and_clamped_samples() {
        let linear = channel(
            Interpolation::Linear,
            Property::Translation,
            vec![[0.0, 0.0, 0.0, 0.0], [2.0, 4.0, 0.0, 0.0]],
        );
        assert_eq!(sample(&linear, 2.0), [1.0, 2.0, 0.0, 0.0]);
        assert_eq!(sample(&linear, 0.0), [0.0; 4]);
        assert_eq!(sample(&linear, 9.0), [2.0, 4.0, 0.0, 0.0]);
        let step = Channel {
            interpolation: Interpolation::Step,
            ..linear
        };
        assert_eq!(sample(&step, 2.9), [0.0; 4]);
        assert_eq!(sample(&step, 3.0), [2.0, 4.0, 0.0, 0.0]);
    }

    #[test]
    fn linear_rotations_turn_at_a_steady_rate() {
        let half = std::f64::consts::FRAC_1_SQRT_2;
        // The identity, then a quarter turn about z: halfway is an eighth of a turn.
        let rotation = channel(
            Interpolation::Linear,
            Property::Rotation,
            vec![[0.0, 0.0, 0.0, 1.0], [0.0, 0.0, half, half]],
        );
        let q = sample(&rotation, 2.0);
        let eighth = std::f64::consts::FRAC_PI_8;
        assert!((q[2] - eighth.sin()).abs() < 1e-12 && (q[3] - eighth.cos()).abs() < 1e-12);
    }

    #[test]
    fn cubic_splines_pass_through_their_keys_and_follow_the_tangents() {
        // Value 0 then 1 with zero tangents: the smoothstep 3s² − 2s³, 0.5 halfway.
        let zero = [0.0; 4];
        let cubic = channel(
            Interpolation::CubicSpline,
            Property::Translation,
            vec![zero, zero, zero, zero, [1.0, 0.0, 0.0, 0.0], zero],
        );
        assert_eq!(sample(&cubic, 1.0)[0], 0.0);
        assert_eq!(sample(&cubic, 3.0)[0], 1.0);
        assert!((sample(&cubic, 1.5)[0] - (3.0 * 0.0625 - 2.0 * 0.015625)).abs() < 1e-12);
    }
}
