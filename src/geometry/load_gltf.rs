//! glTF 2.0 loading (`.gltf` with embedded or external buffers, and binary `.glb`).
//!
//! The `gltf` crate parses and validates the document; buffer data is read here with every
//! offset, length and index checked, so that a malformed file gives an error and never a panic.

use std::collections::BTreeSet;
use std::path::Path;

use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;
use gltf::scene::Transform;
use gltf::{Accessor, Document, Semantic};
use nalgebra::{Matrix4, Point3, Quaternion, Translation3, UnitQuaternion};

use super::gltf_buffers::resolve_buffers;
use super::load::{check_triangles, check_vertices, index_u32, LoadError, MeshSelector, RawMesh};
use super::load_files::{FileReader, MeshLimits};

pub(super) fn err(message: impl Into<String>) -> LoadError {
    LoadError::Gltf {
        message: message.into(),
    }
}

/// A glTF or GLB file parsed once (its document, buffers and node hierarchy), for taking any
/// number of its parts without parsing it again: a rig of thousands of parts is parsed once,
/// not once a part.
pub(crate) struct OpenedGltf {
    document: Document,
    buffers: Vec<Vec<u8>>,
    hierarchy: Hierarchy,
    limits: MeshLimits,
}

impl OpenedGltf {
    /// The file of `bytes`, its buffers read through `reader` (relative URIs against `base`,
    /// within the reader's policy and budget).
    pub(crate) fn open(
        bytes: &[u8],
        base: &Path,
        reader: &mut FileReader,
    ) -> Result<OpenedGltf, LoadError> {
        let (document, buffers) = open_document(bytes, base, reader)?;
        let hierarchy = Hierarchy::new(&document)?;
        Ok(OpenedGltf {
            document,
            buffers,
            hierarchy,
            limits: *reader.limits(),
        })
    }

    /// The part `selector` picks. Every primitive instance counts against the triangle limit
    /// (at least one each), and its vertex and index counts are checked against the limits
    /// before its data is decoded.
    ///
    /// - `Whole`: every mesh instance of the default scene (or the first scene; or, without
    ///   scenes, of every root node), each in its node's world frame.
    /// - A name: the node with that name, in its world frame (its own mesh, or when it has
    ///   none, the meshes of all its descendants, each in its world frame); failing that, the
    ///   mesh with that name, untransformed.
    pub(crate) fn part(&self, selector: &MeshSelector) -> Result<RawMesh, LoadError> {
        let (document, hierarchy) = (&self.document, &self.hierarchy);
        let instances = match selector.part_name() {
            None => match document
                .default_scene()
                .or_else(|| document.scenes().next())
            {
                Some(scene) => {
                    hierarchy.mesh_instances(&scene.nodes().map(|n| n.index()).collect::<Vec<_>>())
                }
                None => hierarchy.mesh_instances(&hierarchy.roots),
            },
            Some(name) => select_named(document, hierarchy, name)?,
        };
        let mut raw = RawMesh {
            positions: Vec::new(),
            triangles: Vec::new(),
        };
        let mut work = 0usize;
        for (mesh_index, transform) in instances {
            let Some(mesh) = document.meshes().nth(mesh_index) else {
                return Err(err(format!("mesh {mesh_index} does not exist")));
            };
            for primitive in mesh.primitives() {
                work += 1;
                check_triangles(work, &self.limits)?;
                append_primitive(
                    &primitive,
                    &transform,
                    &self.buffers,
                    &self.limits,
                    &mut raw,
                )?;
                work = work.max(raw.triangles.len());
            }
        }
        Ok(raw)
    }
}

/// The validated document of a glTF or GLB file and its buffers, read through `reader`
/// (relative buffer URIs against `base`).
pub(super) fn open_document(
    bytes: &[u8],
    base: &Path,
    reader: &mut FileReader,
) -> Result<(Document, Vec<Vec<u8>>), LoadError> {
    check_glb_header(bytes)?;
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| err(e.to_string()))?;
    check_position_indices(document.as_json())?;
    check_animation_targets(document.as_json())?;
    let document = Document::from_json(document.into_json()).map_err(|e| err(e.to_string()))?;
    let buffers = resolve_buffers(&document, base, blob, reader)?;
    Ok((document, buffers))
}

/// gltf-json's validation indexes the accessors with each primitive's `POSITION` index before
/// checking it (and panics when it is out of range): check those indices first.
fn check_position_indices(root: &gltf::json::Root) -> Result<(), LoadError> {
    let positions = gltf::json::validation::Checked::Valid(gltf::json::mesh::Semantic::Positions);
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(index) = primitive.attributes.get(&positions) {
                if index.value() >= root.accessors.len() {
                    return Err(err(format!(
                        "the POSITION of primitive {p} of mesh {m} is accessor {}, which does not exist",
                        index.value()
                    )));
                }
            }
        }
    }
    Ok(())
}

/// gltf-json's validation leaves an animation channel's target unchecked, and the document's
/// accessors panic on a target node that does not exist or a path it does not know: check them
/// first (every channel, whether a pose uses its animation or not).
fn check_animation_targets(root: &gltf::json::Root) -> Result<(), LoadError> {
    for (a, animation) in root.animations.iter().enumerate() {
        for (c, channel) in animation.channels.iter().enumerate() {
            let target = &channel.target;
            if target.node.value() >= root.nodes.len() {
                return Err(err(format!(
                    "channel {c} of animation {a} moves node {}, which does not exist",
                    target.node.value()
                )));
            }
            if !matches!(target.path, gltf::json::validation::Checked::Valid(_)) {
                return Err(err(format!(
                    "channel {c} of animation {a} changes a property glTF does not have (not translation, rotation, scale or weights)"
                )));
            }
        }
    }
    Ok(())
}

/// `gltf::binary::Glb::from_slice` subtracts the header size from the declared length without
/// checking it; reject such headers first.
fn check_glb_header(bytes: &[u8]) -> Result<(), LoadError> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let declared = bytes
        .get(8..12)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .ok_or_else(|| err("truncated GLB header"))?;
    if declared < 20 {
        return Err(err(format!(
            "GLB header declares an impossible length {declared}"
        )));
    }
    Ok(())
}

/// The node forest with every node's world transform. A node with two parents, and a cycle,
/// are errors.
pub(super) struct Hierarchy {
    /// The nodes without a parent, in index order.
    pub(super) roots: Vec<usize>,
    /// Each node's children, as the file lists them.
    pub(super) children: Vec<Vec<usize>>,
    /// Each node's mesh.
    pub(super) mesh: Vec<Option<usize>>,
    /// The product of the local transforms from the root down to the node.
    pub(super) world: Vec<Matrix4<f64>>,
}

impl Hierarchy {
    /// The hierarchy of `document`'s nodes.
    pub(super) fn new(document: &Document) -> Result<Self, LoadError> {
        let n = document.nodes().len();
        let mut has_parent = vec![false; n];
        let mut children = vec![Vec::new(); n];
        let mut local = Vec::with_capacity(n);
        let mut mesh = Vec::with_capacity(n);
        for node in document.nodes() {
            for child in node.children() {
                let seen = has_parent
                    .get_mut(child.index())
                    .ok_or_else(|| err(format!("node {} does not exist", child.index())))?;
                if std::mem::replace(seen, true) {
                    return Err(err(format!(
                        "node {} has more than one parent",
                        child.index()
                    )));
                }
                children[node.index()].push(child.index());
            }
            local.push(local_matrix(node.transform())?);
            mesh.push(node.mesh().map(|m| m.index()));
        }
        let roots: Vec<usize> = (0..n).filter(|&i| !has_parent[i]).collect();
        // Top-down from the roots; with one parent each, a node not reached is on a cycle.
        let mut world: Vec<Option<Matrix4<f64>>> = vec![None; n];
        let mut stack: Vec<(usize, Matrix4<f64>)> =
            roots.iter().map(|&r| (r, Matrix4::identity())).collect();
        while let Some((node, parent_world)) = stack.pop() {
            let w = parent_world * local[node];
            world[node] = Some(w);
            stack.extend(children[node].iter().map(|&c| (c, w)));
        }
        let world = world
            .into_iter()
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| err("the node hierarchy has a cycle"))?;
        Ok(Hierarchy {
            roots,
            children,
            mesh,
            world,
        })
    }

    /// Every (mesh, world transform) under the given nodes, the nodes included, depth first.
    pub(super) fn mesh_instances(&self, from: &[usize]) -> Vec<(usize, Matrix4<f64>)> {
        let mut out = Vec::new();
        let mut visited = vec![false; self.world.len()];
        let mut stack: Vec<usize> = from.iter().rev().copied().collect();
        while let Some(node) = stack.pop() {
            if std::mem::replace(&mut visited[node], true) {
                continue;
            }
            if let Some(mesh) = self.mesh[node] {
                out.push((mesh, self.world[node]));
            }
            stack.extend(self.children[node].iter().rev());
        }
        out
    }
}

fn select_named(
    document: &Document,
    hierarchy: &Hierarchy,
    name: &str,
) -> Result<Vec<(usize, Matrix4<f64>)>, LoadError> {
    let nodes: Vec<usize> = document
        .nodes()
        .filter(|n| n.name() == Some(name))
        .map(|n| n.index())
        .collect();
    match nodes.as_slice() {
        [node] => {
            let under = match hierarchy.mesh[*node] {
                Some(_) => vec![*node],
                None => hierarchy.children[*node].clone(),
            };
            if let Some(skinned) = skinned_under(document, hierarchy, &under) {
                return Err(LoadError::Skinned { node: skinned });
            }
            return match hierarchy.mesh[*node] {
                Some(mesh) => Ok(vec![(mesh, hierarchy.world[*node])]),
                None => Ok(hierarchy.mesh_instances(&under)),
            };
        }
        [] => {}
        many => {
            return Err(LoadError::AmbiguousPart {
                name: name.to_string(),
                count: many.len(),
            })
        }
    }
    let meshes: Vec<usize> = document
        .meshes()
        .filter(|m| m.name() == Some(name))
        .map(|m| m.index())
        .collect();
    match meshes.as_slice() {
        [mesh] => Ok(vec![(*mesh, Matrix4::identity())]),
        [] => {
            let available: BTreeSet<String> = document
                .nodes()
                .filter_map(|n| n.name())
                .chain(document.meshes().filter_map(|m| m.name()))
                .map(str::to_string)
                .collect();
            Err(LoadError::UnknownPart {
                name: name.to_string(),
                available: available.into_iter().collect(),
            })
        }
        many => Err(LoadError::AmbiguousPart {
            name: name.to_string(),
            count: many.len(),
        }),
    }
}

/// The name (or `#index`) of the first mesh node with a skin among `from` and their
/// descendants, depth first.
fn skinned_under(document: &Document, hierarchy: &Hierarchy, from: &[usize]) -> Option<String> {
    let mut stack: Vec<usize> = from.iter().rev().copied().collect();
    let mut visited = vec![false; hierarchy.world.len()];
    while let Some(index) = stack.pop() {
        if std::mem::replace(&mut visited[index], true) {
            continue;
        }
        let node = document.nodes().nth(index)?;
        if node.mesh().is_some() && node.skin().is_some() {
            return Some(node.name().map_or(format!("#{index}"), str::to_owned));
        }
        stack.extend(hierarchy.children[index].iter().rev());
    }
    None
}

/// A node's local transform in f64 (a decomposed transform is composed as T·R·S in f64).
pub(super) fn local_matrix(transform: Transform) -> Result<Matrix4<f64>, LoadError> {
    match transform {
        Transform::Matrix { matrix } => Ok(Matrix4::from_fn(|r, c| f64::from(matrix[c][r]))),
        Transform::Decomposed {
            translation: t,
            rotation: q,
            scale: s,
        } => {
            let r = node_rotation(q)?;
            let t = Translation3::new(t[0], t[1], t[2]).cast::<f64>();
            let s = Matrix4::new_nonuniform_scaling(&nalgebra::Vector3::new(
                f64::from(s[0]),
                f64::from(s[1]),
                f64::from(s[2]),
            ));
            Ok(t.to_homogeneous() * r.to_homogeneous() * s)
        }
    }
}

/// A node's `rotation` (glTF order x, y, z, w) as a unit quaternion in f64; a zero or NaN
/// quaternion is refused.
pub(super) fn node_rotation(q: [f32; 4]) -> Result<UnitQuaternion<f64>, LoadError> {
    let q = Quaternion::new(q[3], q[0], q[1], q[2]).cast::<f64>();
    if q.norm().is_nan() || q.norm() == 0.0 {
        return Err(err("a node has a zero rotation quaternion"));
    }
    Ok(UnitQuaternion::from_quaternion(q))
}

fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "POINTS",
        Mode::Lines => "LINES",
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        Mode::Triangles => "TRIANGLES",
        Mode::TriangleStrip => "TRIANGLE_STRIP",
        Mode::TriangleFan => "TRIANGLE_FAN",
    }
}

/// Appends one TRIANGLES primitive, mapped by `transform`. A transform with a negative
/// determinant mirrors the geometry, so the triangles' order is reversed to keep them
/// counter-clockwise seen from outside (glTF specifies the same rule for rendering).
fn append_primitive(
    primitive: &gltf::Primitive,
    transform: &Matrix4<f64>,
    buffers: &[Vec<u8>],
    limits: &MeshLimits,
    raw: &mut RawMesh,
) -> Result<(), LoadError> {
    if primitive.mode() != Mode::Triangles {
        return Err(LoadError::UnsupportedPrimitive {
            mode: mode_name(primitive.mode()).to_string(),
        });
    }
    let accessor = primitive
        .get(&Semantic::Positions)
        .ok_or_else(|| err("a primitive has no POSITION attribute"))?;
    if accessor.data_type() != DataType::F32
        || accessor.dimensions() != Dimensions::Vec3
        || accessor.normalized()
    {
        return Err(err(format!(
            "POSITION accessor {} is not VEC3 of FLOAT",
            accessor.index()
        )));
    }
    let too_many = || err("too many vertices for 32-bit indices");
    let offset = index_u32(raw.positions.len(), too_many)?;
    check_vertices(raw.positions.len().saturating_add(accessor.count()), limits)?;
    let index_count = primitive
        .indices()
        .map_or(accessor.count(), |acc| acc.count());
    check_triangles(raw.triangles.len().saturating_add(index_count / 3), limits)?;
    let points = elements(&accessor, buffers, 12)?;
    let count = index_u32(points.len(), too_many)?;
    offset.checked_add(count).ok_or_else(too_many)?;

    let indices: Vec<u32> = match primitive.indices() {
        None => (0..count).collect(),
        Some(acc) => {
            let size = match acc.data_type() {
                DataType::U8 => 1,
                DataType::U16 => 2,
                DataType::U32 => 4,
                other => {
                    return Err(err(format!(
                        "index accessor {} has component type {other:?}",
                        acc.index()
                    )))
                }
            };
            if acc.dimensions() != Dimensions::Scalar {
                return Err(err(format!("index accessor {} is not SCALAR", acc.index())));
            }
            elements(&acc, buffers, size)?
                .into_iter()
                .map(|b| match *b {
                    [x] => u32::from(x),
                    [x, y] => u32::from(u16::from_le_bytes([x, y])),
                    [x, y, z, w] => u32::from_le_bytes([x, y, z, w]),
                    _ => unreachable!("element slices have the requested size"),
                })
                .collect()
        }
    };
    if indices.len() % 3 != 0 {
        return Err(err(format!(
            "a TRIANGLES primitive has {} indices, not a multiple of 3",
            indices.len()
        )));
    }
    if let Some(bad) = indices.iter().find(|&&i| i >= count) {
        return Err(err(format!(
            "index {bad} is past the {count} vertices of its primitive"
        )));
    }

    raw.positions.extend(points.iter().map(|b| {
        let f = |k: usize| f64::from(f32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]));
        transform.transform_point(&Point3::new(f(0), f(4), f(8)))
    }));
    let mirrored = transform.fixed_view::<3, 3>(0, 0).determinant() < 0.0;
    raw.triangles.extend(indices.chunks_exact(3).map(|t| {
        let t = [t[0] + offset, t[1] + offset, t[2] + offset];
        if mirrored {
            [t[0], t[2], t[1]]
        } else {
            t
        }
    }));
    Ok(())
}

static ZEROS: [u8; 16] = [0; 16];

/// The bytes of each element of `accessor` (each `size` bytes long), with sparse substitutions
/// applied. Every range is checked against the buffers.
pub(super) fn elements<'b>(
    accessor: &Accessor,
    buffers: &'b [Vec<u8>],
    size: usize,
) -> Result<Vec<&'b [u8]>, LoadError> {
    let count = accessor.count();
    let mut out = match accessor.view() {
        Some(view) => {
            let stride = view.stride().unwrap_or(size);
            strided(
                &view,
                accessor.offset(),
                stride,
                count,
                size,
                buffers,
                accessor.index(),
            )?
        }
        // All zeros; the caller has checked `count` against the limits.
        None => vec![&ZEROS[..size]; count],
    };
    if let Some(sparse) = accessor.sparse() {
        let n = sparse.count();
        let idx = sparse.indices();
        let index_size = idx.index_type().size();
        let positions = strided(
            &idx.view(),
            idx.offset(),
            index_size,
            n,
            index_size,
            buffers,
            accessor.index(),
        )?;
        let values = sparse.values();
        let values = strided(
            &values.view(),
            values.offset(),
            size,
            n,
            size,
            buffers,
            accessor.index(),
        )?;
        for (at, value) in positions.into_iter().zip(values) {
            let at = match *at {
                [x] => usize::from(x),
                [x, y] => usize::from(u16::from_le_bytes([x, y])),
                [x, y, z, w] => u32::from_le_bytes([x, y, z, w]) as usize,
                _ => unreachable!("sparse index sizes are 1, 2 or 4"),
            };
            *out.get_mut(at).ok_or_else(|| {
                err(format!(
                    "sparse index {at} is past the {count} elements of accessor {}",
                    accessor.index()
                ))
            })? = value;
        }
    }
    Ok(out)
}

/// `count` slices of `size` bytes, `stride` apart, from `offset` into a buffer view.
fn strided<'b>(
    view: &gltf::buffer::View,
    offset: usize,
    stride: usize,
    count: usize,
    size: usize,
    buffers: &'b [Vec<u8>],
    accessor: usize,
) -> Result<Vec<&'b [u8]>, LoadError> {
    let out_of_range = || err(format!("accessor {accessor} reaches past its buffer"));
    if stride < size {
        return Err(err(format!(
            "accessor {accessor} has a byte stride {stride} smaller than its elements"
        )));
    }
    let buffer = buffers
        .get(view.buffer().index())
        .ok_or_else(|| err(format!("buffer {} is missing", view.buffer().index())))?;
    let view_end = view
        .offset()
        .checked_add(view.length())
        .ok_or_else(out_of_range)?;
    let data = buffer
        .get(view.offset()..view_end)
        .ok_or_else(out_of_range)?;
    if count == 0 {
        return Ok(Vec::new());
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|x| x.checked_add(offset))
        .and_then(|x| x.checked_add(size))
        .ok_or_else(out_of_range)?;
    if end > data.len() {
        return Err(out_of_range());
    }
    Ok((0..count)
        .map(|i| &data[offset + i * stride..offset + i * stride + size])
        .collect())
}
