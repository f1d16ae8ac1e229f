//! The `rig` node: components from the mesh nodes of a glTF file, and the component transforms
//! of a pose from one of its animations (`pose "wave" animation="Wave" time=1`) or scenes
//! (`pose "wave" scene="Wave"`).
//!
//! Each part is its mesh node's mesh, in the node's rest world transform (as a component with
//! `node=` reads it). In a pose from an animation, a part moves by its node's world transform at
//! the pose's time times the inverse of its rest transform, turned and scaled from the file's
//! frame into the rest frame; that must be a rigid motion, or the pose is refused. In a pose from
//! a scene, a part moves the same way to the world transform of the scene's mesh node that is its
//! own node, or else is named as its node or as a copy of it (`Arm.L.001`).

use std::path::{Path, PathBuf};

use miette::SourceSpan;
use nalgebra::{Isometry3, Matrix3, Matrix4, Rotation3, Translation3, UnitQuaternion};

use super::codes;
use super::model::{Axis, Component, MeshFrame, Spanned, Units};
use super::tree::{Node, Scalar};
use super::value::listing;
use super::vocabulary;
use crate::diagnostic::Problem;
use crate::geometry::{read_rig, LoadError, MeshSelector, ReadPolicy, Rig, RigAnimation};

/// How far a part's motion may be from rigid (in its linear part, per entry) and still count as
/// rigid: glTF stores transforms in 32-bit floats.
const RIGID_TOLERANCE: f64 = 1e-4;

/// A rig that was read, and which of its nodes became which components.
#[derive(Debug)]
pub(super) struct RigSource {
    rig: Rig,
    /// The file, as the `rig` node writes it.
    path: Spanned<PathBuf>,
    /// Per part: its node in the rig and its index among the project's components.
    parts: Vec<(usize, usize)>,
    frame: MeshFrame,
}

/// Reads the rig a `rig` node names and returns its parts as components, to be numbered from
/// `first_index`; `None` (after reporting why) when the file cannot be used. `frame` is how the
/// file's coordinates become rest-frame coordinates.
pub(super) fn read(
    node: &Node,
    folder: &Path,
    frame: MeshFrame,
    policy: &ReadPolicy,
    first_index: usize,
    problems: &mut Vec<Problem>,
) -> Option<(RigSource, Vec<Component>)> {
    let written = node.text_arg()?;
    let path = Spanned::new(folder.join(&written.value), written.span);
    let rig = match read_rig(&path.value, policy) {
        Ok(rig) => rig,
        Err(error) => {
            problems.push(unreadable(&written, &error));
            return None;
        }
    };
    let chosen = match node.child("nodes") {
        Some(list) => listed_nodes(&rig, list, problems),
        None => scene_nodes(&rig, &written, problems),
    };
    let mut components: Vec<Component> = Vec::new();
    let mut parts = Vec::new();
    for (index, name) in chosen {
        if let Some(first) = components.iter().find(|c| c.name.value == name.value) {
            problems.push(
                Problem::error(
                    codes::DUPLICATE_NAME,
                    format!("the rig lists node `{}` twice", name.value),
                )
                .with_label(name.span, "listed again here")
                .with_label(first.name.span, "first listed here")
                .with_help("list each node once"),
            );
            continue;
        }
        if rig.nodes[index].skinned {
            problems.push(
                Problem::error(
                    codes::RIG_SKINNED,
                    format!(
                        "node `{}` of the rig is a skinned mesh, which bends with its joints",
                        name.value
                    ),
                )
                .with_label(name.span, "skinned")
                .with_help(
                    "a rig's parts must be rigid: in the editor, separate the mesh into one \
                     object per part and parent each to its bone (Blender: Ctrl+P, Bone) instead \
                     of an armature modifier",
                ),
            );
            continue;
        }
        parts.push((index, first_index + components.len()));
        components.push(Component {
            name: name.clone(),
            mesh: path.clone(),
            selector: MeshSelector::GltfNode(name.value),
            frame: frame.clone(),
            print: None,
            span: node.span,
        });
    }
    let source = RigSource {
        rig,
        path,
        parts,
        frame,
    };
    Some((source, components))
}

/// The nodes a `nodes` list names, each with the span of its name; reports names the rig does
/// not have, names two nodes share, and nodes without a mesh.
fn listed_nodes(
    rig: &Rig,
    list: &Node,
    problems: &mut Vec<Problem>,
) -> Vec<(usize, Spanned<String>)> {
    let mut chosen = Vec::new();
    for value in list.args.iter().flatten() {
        let Scalar::Text(name) = &value.scalar else {
            continue;
        };
        let name = Spanned::new(name.clone(), value.span);
        let found: Vec<usize> = (0..rig.nodes.len())
            .filter(|&index| rig.nodes[index].name.as_deref() == Some(name.value.as_str()))
            .collect();
        match found.as_slice() {
            [index] if rig.nodes[*index].has_mesh => chosen.push((*index, name)),
            [_] => problems.push(
                Problem::error(
                    codes::RIG_NO_MESH,
                    format!("node `{}` of the rig has no mesh of its own", name.value),
                )
                .with_label(name.span, "no mesh")
                .with_help(format!(
                    "list the mesh nodes that hang under it: the rig's mesh nodes are {}",
                    mesh_names(rig)
                )),
            ),
            [] => problems.push(unknown_node(rig, &name)),
            many => problems.push(
                Problem::error(
                    codes::RIG_AMBIGUOUS_NODE,
                    format!(
                        "{} nodes of the rig are called `{}`",
                        many.len(),
                        name.value
                    ),
                )
                .with_label(name.span, "more than one node")
                .with_help("give each node its own name in the editor"),
            ),
        }
    }
    chosen
}

/// The mesh nodes of the rig's scene, each spanned by the rig's path; reports unnamed ones
/// (a component needs a name) and a scene without meshes.
fn scene_nodes(
    rig: &Rig,
    written: &Spanned<String>,
    problems: &mut Vec<Problem>,
) -> Vec<(usize, Spanned<String>)> {
    if rig.scene_meshes.is_empty() {
        problems.push(
            Problem::error(
                codes::RIG_NO_MESH,
                format!("the scene of `{}` has no mesh nodes", written.value),
            )
            .with_label(written.span, "no parts")
            .with_help("a rig's parts are the mesh nodes of its default scene"),
        );
    }
    let mut chosen = Vec::new();
    for &index in &rig.scene_meshes {
        match &rig.nodes[index].name {
            Some(name) => chosen.push((index, Spanned::new(name.clone(), written.span))),
            None => problems.push(
                Problem::error(
                    codes::RIG_UNNAMED_NODE,
                    format!("mesh node {index} of `{}` has no name", written.value),
                )
                .with_label(written.span, "in this rig")
                .with_help("every part becomes a component named after its node: name the node in the editor, or list the parts with `nodes`"),
            ),
        }
    }
    let names: Vec<&str> = chosen.iter().map(|(_, name)| name.value.as_str()).collect();
    for (position, name) in names.iter().enumerate() {
        if names[..position].contains(name) {
            problems.push(
                Problem::error(
                    codes::RIG_AMBIGUOUS_NODE,
                    format!(
                        "several mesh nodes of `{}` are called `{name}`",
                        written.value
                    ),
                )
                .with_label(written.span, "in this rig")
                .with_help("give each node its own name in the editor"),
            );
        }
    }
    chosen
}

/// Whether `name` is the node `part` or a copy of it as Blender names copies: `part`, a dot and
/// digits (`Arm.L.001`).
fn is_copy_of(name: &str, part: &str) -> bool {
    name == part
        || name.strip_prefix(part).is_some_and(|rest| {
            rest.strip_prefix('.').is_some_and(|digits| {
                !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
            })
        })
}

fn mesh_names(rig: &Rig) -> String {
    let names: Vec<&str> = rig
        .nodes
        .iter()
        .filter(|node| node.has_mesh)
        .filter_map(|node| node.name.as_deref())
        .collect();
    if names.is_empty() {
        return "none".to_owned();
    }
    listing(&names, |name| format!("`{name}`"), "and")
}

fn unknown_node(rig: &Rig, name: &Spanned<String>) -> Problem {
    let known = rig.nodes.iter().filter_map(|node| node.name.as_deref());
    let help = match vocabulary::suggest(&name.value, known) {
        Some(close) => format!("did you mean `{close}`?"),
        None => format!("the rig's mesh nodes are {}", mesh_names(rig)),
    };
    Problem::error(
        codes::RIG_UNKNOWN_NODE,
        format!("the rig has no node called `{}`", name.value),
    )
    .with_label(name.span, "not a node of the rig")
    .with_help(help)
}

fn unreadable(written: &Spanned<String>, error: &LoadError) -> Problem {
    let (message, help) = match error {
        LoadError::NotFound { .. } => (
            format!("rig file `{}` does not exist", written.value),
            "paths are relative to the folder of the project file",
        ),
        LoadError::OutsideFolder { .. } => (
            format!(
                "rig file `{}` is outside the project's folder",
                written.value
            ),
            "move the file into the project's folder, or pass `--read-outside`",
        ),
        other => (
            format!("cannot read rig `{}`: {other}", written.value),
            "a rig is a glTF (.gltf) or binary glTF (.glb) file",
        ),
    };
    Problem::error(codes::RIG_UNREADABLE, message)
        .with_label(written.span, "this rig")
        .with_help(help)
}

/// The time pose `pose` samples animation `clip` (called `animation`) at: its `time=`, inside
/// the animation's keys; without one, the single key's time (or 0 for an animation without keys);
/// `None` after reporting a time outside the keys, or a missing one where there are several keys.
fn pose_time(
    pose: &Node,
    animation: &Spanned<String>,
    clip: &RigAnimation,
    problems: &mut Vec<Problem>,
) -> Option<f64> {
    match pose.prop("time").zip(pose.number("time")) {
        Some((value, time)) => {
            // Keys are 32-bit seconds, often at frame / fps (Blender's first at 1/24 s). Before
            // the first key the channels hold their first values, so any time from 0 is taken up
            // to a millisecond past the last key.
            let slack = TIME_SLACK;
            let has_keys = clip.most_keys > 0;
            if has_keys && time > clip.end + slack {
                problems.push(time_problem(
                    codes::RIG_TIME_OUTSIDE,
                    format!(
                        "time {time} s is outside animation `{}`, which runs from {} s to {} s",
                        animation.value,
                        seconds(clip.start),
                        seconds(clip.end)
                    ),
                    (value.span, "outside the animation"),
                    format!("give a time from 0 to {} (seconds)", seconds(clip.end)),
                ));
                return None;
            }
            Some(time)
        }
        None if clip.most_keys > 1 => {
            problems.push(time_problem(
                codes::RIG_TIME_NEEDED,
                format!(
                    "animation `{}` has keys from {} s to {} s: the pose must say when",
                    animation.value,
                    seconds(clip.start),
                    seconds(clip.end)
                ),
                (animation.span, "more than one key"),
                format!(
                    "add `time=` in seconds, e.g. `time={}`, or give the animation a single \
                     (STEP) key",
                    seconds(clip.end)
                ),
            ));
            None
        }
        None if clip.most_keys == 1 => Some(clip.start),
        None => Some(0.0),
    }
}

/// How far past its animation's last key a pose's `time=` may lie, seconds.
const TIME_SLACK: f64 = 1e-3;

/// A key time for a message: at most four decimals, trailing zeros dropped (within
/// [`TIME_SLACK`] of the time, so it may be pasted as `time=`).
fn seconds(time: f64) -> String {
    let text = format!("{time:.4}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".to_owned()
    } else {
        text.to_owned()
    }
}

/// A problem with a pose's time against its animation's keys: `code`, `message`, one label
/// (span and text) and `help`.
fn time_problem(
    code: &'static str,
    message: String,
    (span, label): (SourceSpan, &str),
    help: String,
) -> Problem {
    Problem::error(code, message)
        .with_label(span, label)
        .with_help(help)
}

impl RigSource {
    /// The component transforms (component index, rest frame to model frame) of the pose
    /// `pose`, whose `animation=` is `animation`; `None` after reporting an unknown animation, a
    /// missing or out-of-range time, or a part the animation does not move rigidly.
    pub(super) fn animated(
        &self,
        pose: &Node,
        animation: &Spanned<String>,
        units: Units,
        up: Axis,
        problems: &mut Vec<Problem>,
    ) -> Option<Vec<(usize, Isometry3<f64>)>> {
        let rig = &self.rig;
        let Some(index) = rig
            .animations
            .iter()
            .position(|a| a.name.as_deref() == Some(animation.value.as_str()))
        else {
            problems.push(self.unknown_animation(animation));
            return None;
        };
        let clip = &rig.animations[index];
        let time = pose_time(pose, animation, clip, problems)?;
        let posed = rig.posed(index, time);
        let morphed: Vec<usize> = clip.morphed_nodes().collect();
        let mut transforms = Vec::new();
        let mut rigid = true;
        for &(node, component) in &self.parts {
            let name = rig.nodes[node].name.as_deref().unwrap_or("");
            let motion = self.motion(node, &posed[node], units, up);
            match motion {
                Some(motion) if !morphed.contains(&node) => transforms.push((component, motion)),
                _ => {
                    let what = if morphed.contains(&node) {
                        "changes the morph target weights of"
                    } else {
                        "scales, shears or mirrors"
                    };
                    problems.push(
                        Problem::error(
                            codes::RIG_NOT_RIGID,
                            format!(
                                "animation `{}` at {time} s {what} part `{name}`: a printed \
                                 part only moves rigidly",
                                animation.value
                            ),
                        )
                        .with_label(animation.span, "this animation")
                        .with_label(self.path.span, "in this rig")
                        .with_help(
                            "key only the rotation and location of the part's bones, and keep \
                             their scale at 1",
                        ),
                    );
                    rigid = false;
                }
            }
        }
        rigid.then_some(transforms)
    }

    /// The component transforms (component index, rest frame to model frame) of the pose
    /// whose `scene=` is `scene`: each part moves to where the scene's node of the same name
    /// (or the part's own node, when the scene holds it) stands. `None` after reporting an
    /// unknown scene, a part the scene lacks, or one it moves other than rigidly.
    pub(super) fn scene_pose(
        &self,
        scene: &Spanned<String>,
        units: Units,
        up: Axis,
        problems: &mut Vec<Problem>,
    ) -> Option<Vec<(usize, Isometry3<f64>)>> {
        let rig = &self.rig;
        let found: Vec<usize> = (0..rig.scenes.len())
            .filter(|&index| rig.scenes[index].name.as_deref() == Some(scene.value.as_str()))
            .collect();
        let meshes = match found.as_slice() {
            [index] => &rig.scenes[*index].meshes,
            [] => {
                problems.push(self.unknown_scene(scene));
                return None;
            }
            many => {
                problems.push(
                    Problem::error(
                        codes::RIG_UNKNOWN_SCENE,
                        format!(
                            "{} scenes of the rig are called `{}`",
                            many.len(),
                            scene.value
                        ),
                    )
                    .with_label(scene.span, "more than one scene")
                    .with_label(self.path.span, "in this rig")
                    .with_help("give each scene its own name in the editor"),
                );
                return None;
            }
        };
        let mut transforms = Vec::new();
        let mut complete = true;
        for &(node, component) in &self.parts {
            let name = rig.nodes[node].name.as_deref().unwrap_or("");
            let twins: Vec<usize> = if meshes.contains(&node) {
                vec![node]
            } else {
                meshes
                    .iter()
                    .copied()
                    .filter(|&other| {
                        rig.nodes[other]
                            .name
                            .as_deref()
                            .is_some_and(|other| is_copy_of(other, name))
                    })
                    .collect()
            };
            let problem = match twins.as_slice() {
                [twin] => match self.motion(node, &rig.nodes[*twin].rest, units, up) {
                    Some(motion) => {
                        transforms.push((component, motion));
                        continue;
                    }
                    None => Problem::error(
                        codes::RIG_NOT_RIGID,
                        format!(
                            "scene `{}` scales, shears or mirrors part `{name}`: a printed part \
                             only moves rigidly",
                            scene.value
                        ),
                    )
                    .with_help("pose the part's bones by rotation and location only, scale 1"),
                },
                [] => Problem::error(
                    codes::RIG_NOT_IN_SCENE,
                    format!(
                        "scene `{}` has no mesh node `{name}` (nor a copy such as `{name}.001`)",
                        scene.value
                    ),
                )
                .with_help(format!(
                    "every part of the rig must be in the pose's scene; the rig's parts come \
                     from its default scene{}",
                    if !meshes.is_empty() {
                        ""
                    } else {
                        ", and this scene has no mesh nodes"
                    }
                )),
                many => Problem::error(
                    codes::RIG_AMBIGUOUS_NODE,
                    format!(
                        "scene `{}` has {} mesh nodes for part `{name}`: {}",
                        scene.value,
                        many.len(),
                        listing(
                            &many
                                .iter()
                                .filter_map(|&n| rig.nodes[n].name.as_deref())
                                .collect::<Vec<_>>(),
                            |name| format!("`{name}`"),
                            "and"
                        )
                    ),
                )
                .with_help("keep one copy of each part in a scene"),
            };
            problems.push(
                problem
                    .with_label(scene.span, "this scene")
                    .with_label(self.path.span, "in this rig"),
            );
            complete = false;
        }
        complete.then_some(transforms)
    }

    /// How part `node` moves when its mesh stands at world transform `posed` (in the file's
    /// frame) instead of at its rest transform, as a rest-frame to model-frame isometry; `None`
    /// when that motion is not rigid.
    fn motion(
        &self,
        node: usize,
        posed: &Matrix4<f64>,
        units: Units,
        up: Axis,
    ) -> Option<Isometry3<f64>> {
        let turn = self.frame.rotation(up);
        let factor = self.frame.factor(units);
        let motion = posed * self.rig.nodes[node].rest.try_inverse()?;
        let linear: Matrix3<f64> = motion.fixed_view::<3, 3>(0, 0).into_owned();
        let is_rigid = (linear.transpose() * linear - Matrix3::identity()).amax() < RIGID_TOLERANCE
            && linear.determinant() > 0.0;
        if !is_rigid {
            return None;
        }
        let turned = turn.matrix() * linear * turn.matrix().transpose();
        let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_eps(
            &turned,
            1e-12,
            100,
            Rotation3::identity(),
        ));
        let shift = turn * motion.fixed_view::<3, 1>(0, 3).into_owned() * factor;
        Some(Isometry3::from_parts(Translation3::from(shift), rotation))
    }

    fn unknown_scene(&self, scene: &Spanned<String>) -> Problem {
        let known: Vec<&str> = self
            .rig
            .scenes
            .iter()
            .filter_map(|s| s.name.as_deref())
            .collect();
        let help = match vocabulary::suggest(&scene.value, known.iter().copied()) {
            Some(close) => format!("did you mean `{close}`?"),
            None if known.is_empty() => "the rig has no named scenes".to_owned(),
            None => format!(
                "the rig's scenes are {}",
                listing(&known, |name| format!("`{name}`"), "and")
            ),
        };
        Problem::error(
            codes::RIG_UNKNOWN_SCENE,
            format!("the rig has no scene called `{}`", scene.value),
        )
        .with_label(scene.span, "not a scene of the rig")
        .with_label(self.path.span, "this rig")
        .with_help(help)
    }

    fn unknown_animation(&self, animation: &Spanned<String>) -> Problem {
        let known: Vec<&str> = self
            .rig
            .animations
            .iter()
            .filter_map(|a| a.name.as_deref())
            .collect();
        let help = match vocabulary::suggest(&animation.value, known.iter().copied()) {
            Some(close) => format!("did you mean `{close}`?"),
            None if known.is_empty() => "the rig has no named animations".to_owned(),
            None => format!(
                "the rig's animations are {}",
                listing(&known, |name| format!("`{name}`"), "and")
            ),
        };
        Problem::error(
            codes::RIG_UNKNOWN_ANIMATION,
            format!("the rig has no animation called `{}`", animation.value),
        )
        .with_label(animation.span, "not an animation of the rig")
        .with_label(self.path.span, "this rig")
        .with_help(help)
    }
}
