//! Loading a mesh file: dispatch on the extension, then the clean-up common to all formats.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use nalgebra::Point3;

use super::load_files::{FileReader, MeshLimits, ReadPolicy};
use super::load_gltf::OpenedGltf;
use super::load_obj;
use super::mesh::TriMesh;
use super::repair::{repair, Repairs};
use super::{load_3mf, load_ply, load_stl};

/// Which part of a mesh file to load.
///
/// A name selector is matched against the names the file's format has: OBJ object and group
/// names (`o`/`g` lines), ASCII STL solid names, the names of the objects a 3MF file's build
/// places, glTF node names and then glTF mesh names. The variant records which
/// format the name was written for; either variant works on either format.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum MeshSelector {
    /// Everything: all objects of an OBJ file, all solids of an STL file, every build item of a
    /// 3MF file, or every mesh instance of the glTF default scene.
    Whole,
    /// The OBJ object (or group), STL solid or 3MF build item's object with this name; several
    /// with the name are merged.
    ObjObject(String),
    /// The glTF node with this name (in its world frame), or else the glTF mesh with this name.
    GltfNode(String),
}

impl MeshSelector {
    /// The part name, or `None` for [`MeshSelector::Whole`].
    pub(crate) fn part_name(&self) -> Option<&str> {
        match self {
            MeshSelector::Whole => None,
            MeshSelector::ObjObject(name) | MeshSelector::GltfNode(name) => Some(name),
        }
    }
}

/// Why a mesh file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file does not exist.
    #[error("file not found: {path}")]
    NotFound {
        /// The path as given.
        path: PathBuf,
    },
    /// The file exists but could not be read (a directory, no permission, ...).
    #[error("cannot read {path}: {source}")]
    Io {
        /// The path as given.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The extension is not one of `.obj`, `.stl`, `.3mf`, `.ply`, `.gltf`, `.glb` (compared
    /// case-insensitively).
    #[error(
        "unsupported mesh format `{extension}` (expected .obj, .stl, .3mf, .ply, .gltf or .glb)"
    )]
    UnknownFormat {
        /// The file's extension without the dot (empty when there is none).
        extension: String,
    },
    /// The OBJ text could not be parsed.
    #[error("malformed OBJ file: {message}")]
    Obj {
        /// What is wrong.
        message: String,
    },
    /// The STL file is neither a binary STL nor well-formed ASCII STL.
    #[error("malformed STL file: {message}")]
    Stl {
        /// What is wrong.
        message: String,
    },
    /// The PLY header or body could not be read.
    #[error("malformed PLY file: {message}")]
    Ply {
        /// What is wrong.
        message: String,
    },
    /// The 3MF archive, or a model part in it, could not be read.
    #[error("malformed 3MF file: {message}")]
    ThreeMf {
        /// What is wrong.
        message: String,
    },
    /// The glTF/GLB file could not be parsed, or refers to data that is missing or out of range.
    #[error("malformed glTF file: {message}")]
    Gltf {
        /// What is wrong.
        message: String,
    },
    /// The selector names a part the file does not have.
    #[error("no part named `{name}` in the file{}", available_note(available))]
    UnknownPart {
        /// The name asked for.
        name: String,
        /// Every object, node and mesh name in the file, sorted and without duplicates.
        available: Vec<String>,
    },
    /// The selector names a glTF node (or mesh) that several nodes (or meshes) share.
    #[error("{count} parts are named `{name}`")]
    AmbiguousPart {
        /// The name asked for.
        name: String,
        /// How many nodes (or meshes) carry it.
        count: usize,
    },
    /// The selected glTF node (or a node under it) has a skinned mesh, which bends with its
    /// joints and so is no rigid part.
    #[error("node `{node}` is a skinned mesh")]
    Skinned {
        /// The skinned node's name (or `#index` when it has none).
        node: String,
    },
    /// A selected glTF primitive is not made of triangles.
    #[error("glTF primitive mode {mode} is not supported; only TRIANGLES is")]
    UnsupportedPrimitive {
        /// The glTF mode name, e.g. `LINES` or `TRIANGLE_STRIP`.
        mode: String,
    },
    /// The selected part has no triangles.
    #[error("the mesh has no triangles")]
    Empty,
    /// A vertex coordinate is infinite or NaN (or too large for a 64-bit float).
    #[error("vertex {index} has a non-finite coordinate")]
    NonFinite {
        /// Index of the vertex in load order, before duplicate positions are merged.
        index: usize,
    },
    /// A file of the mesh (the mesh itself or a glTF buffer) is outside the folder the
    /// [`ReadPolicy`] allows, once symbolic links are followed.
    #[error("{path} is outside the folder {folder}")]
    OutsideFolder {
        /// The path as given (or as a buffer URI resolves).
        path: PathBuf,
        /// The allowed folder, canonical.
        folder: PathBuf,
    },
    /// A file of the mesh is not a regular file: a folder, a device, a pipe, or a file of
    /// `/proc`, `/sys` or `/dev`. Such files are never read.
    #[error("{path} is not a regular file")]
    NotAFile {
        /// The path as given (or as a buffer URI resolves).
        path: PathBuf,
    },
    /// Reading this file would take the mesh past [`MeshLimits::max_bytes`].
    #[error("{path} would take the mesh past the limit of {limit} bytes")]
    TooLarge {
        /// The file that does not fit.
        path: PathBuf,
        /// The limit, in bytes.
        limit: u64,
    },
    /// The mesh has more triangles (or vertices) than [`MeshLimits::max_triangles`] allows.
    #[error("the mesh has more than {limit} {what}")]
    TooMany {
        /// `triangles` or `vertices`.
        what: &'static str,
        /// The limit that was passed.
        limit: usize,
    },
}

fn available_note(available: &[String]) -> String {
    if available.is_empty() {
        " (it has no named parts)".to_string()
    } else {
        format!(" (available: {})", available.join(", "))
    }
}

/// Loads a triangle mesh from an `.obj`, `.stl`, `.3mf`, `.ply`, `.gltf` or `.glb` file (extension
/// compared case-insensitively), reading files only inside the mesh's own folder (see
/// [`load_mesh_with`], whose mesh this is).
pub fn load_mesh(path: &Path, selector: &MeshSelector) -> Result<TriMesh, LoadError> {
    let folder = match path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder,
        _ => Path::new("."),
    };
    load_mesh_with(path, selector, &ReadPolicy::within(folder)).map(|loaded| loaded.mesh)
}

/// A loaded mesh and what the loader left out of it.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedMesh {
    /// The mesh.
    pub mesh: TriMesh,
    /// The 1-based line numbers of the OBJ faces with fewer than three vertices, which are
    /// not part of the mesh (empty for other formats).
    pub short_faces: Vec<usize>,
    /// What was repaired to make the mesh the solid a slicer prints ([`Repairs`]).
    pub repairs: Repairs,
}

/// Loads a triangle mesh from an `.obj`, `.stl`, `.3mf`, `.ply`, `.gltf` or `.glb` file (extension
/// compared case-insensitively), reading only the files `policy` allows and within its limits.
///
/// The result is one [`TriMesh`] in the file's frame and units; for glTF, node transforms
/// (world transforms, the product of the parents' local transforms) are applied; for 3MF, the
/// build and component transforms, and coordinates are scaled from the file's `unit` into
/// millimetres. Vertices with
/// bit-identical positions are merged (first occurrence kept, order preserved) so files that split
/// vertices by normal or texture coordinate give a connected surface; `-0.0` and `0.0` count as
/// equal. Then the mesh is repaired as a slicer repairs it ([`Repairs`]): triangles with two
/// corners at one position (as STL files and exporters that weld nothing leave) and repeated
/// triangles are left out, flipped patches turned, holes capped, an inside-out mesh turned.
/// Other zero-area triangles (three distinct corners on a line) are kept: they enclose nothing,
/// and leaving them out would open the surface. What is still wrong is for
/// [`check_mesh`](super::check_mesh) to report.
///
/// Never panics, whatever the file holds, and never reads a file that is not regular, is
/// outside `policy.within`, or does not fit in `policy.limits.max_bytes`.
pub fn load_mesh_with(
    path: &Path,
    selector: &MeshSelector,
    policy: &ReadPolicy,
) -> Result<LoadedMesh, LoadError> {
    MeshFile::open(path, policy)?.load(selector)
}

/// A mesh file read (and a glTF file parsed) once, for loading several parts of it: the parts
/// of a rig, or the objects of one OBJ file that several components name.
pub struct MeshFile {
    contents: Contents,
    /// The limits of the policy the file was opened with, which every part is held to.
    limits: MeshLimits,
}

/// What a [`MeshFile`] keeps between parts.
enum Contents {
    /// An OBJ file's bytes (each part is parsed from them).
    Obj(Vec<u8>),
    /// An STL file's solids.
    Stl(Vec<load_stl::Solid>),
    /// A PLY file's bytes (parsed for each load: a PLY file is one part).
    Ply(Vec<u8>),
    /// A 3MF package's model parts.
    ThreeMf(Box<load_3mf::Package>),
    /// A glTF file's document, buffers and node hierarchy.
    Gltf(Box<OpenedGltf>),
}

impl MeshFile {
    /// Reads the `.obj`, `.stl`, `.3mf`, `.ply`, `.gltf` or `.glb` file at `path` (extension
    /// compared case-insensitively), and parses STL, 3MF and glTF (OBJ and PLY are parsed per
    /// part), reading only what `policy` allows ([`load_mesh_with`]).
    pub fn open(path: &Path, policy: &ReadPolicy) -> Result<MeshFile, LoadError> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().into_owned())
            .unwrap_or_default();
        let format = match extension.to_ascii_lowercase().as_str() {
            "obj" => Format::Obj,
            "stl" => Format::Stl,
            "3mf" => Format::ThreeMf,
            "ply" => Format::Ply,
            "gltf" | "glb" => Format::Gltf,
            _ => return Err(LoadError::UnknownFormat { extension }),
        };
        let mut reader = FileReader::new(policy);
        let bytes = reader.read(path)?;
        let contents = match format {
            Format::Obj => Contents::Obj(bytes),
            Format::Stl => Contents::Stl(load_stl::parse_stl(&bytes, &policy.limits)?),
            Format::Ply => Contents::Ply(bytes),
            Format::ThreeMf => {
                Contents::ThreeMf(Box::new(load_3mf::Package::open(&bytes, &policy.limits)?))
            }
            Format::Gltf => {
                let base = path.parent().unwrap_or_else(|| Path::new("."));
                Contents::Gltf(Box::new(OpenedGltf::open(&bytes, base, &mut reader)?))
            }
        };
        Ok(MeshFile {
            contents,
            limits: policy.limits,
        })
    }

    /// The part `selector` picks (the whole file for [`MeshSelector::Whole`]), as
    /// [`load_mesh_with`] describes, within the limits it was opened with.
    pub fn load(&self, selector: &MeshSelector) -> Result<LoadedMesh, LoadError> {
        let (raw, short_faces) = match &self.contents {
            Contents::Obj(bytes) => load_obj::parse_obj(bytes, selector, &self.limits)?,
            Contents::Stl(solids) => (load_stl::select(solids, selector)?, Vec::new()),
            Contents::ThreeMf(package) => (package.part(selector, &self.limits)?, Vec::new()),
            Contents::Ply(bytes) => {
                if let Some(name) = selector.part_name() {
                    return Err(LoadError::UnknownPart {
                        name: name.to_string(),
                        available: Vec::new(),
                    });
                }
                (load_ply::parse_ply(bytes, &self.limits)?, Vec::new())
            }
            Contents::Gltf(opened) => (opened.part(selector)?, Vec::new()),
        };
        let (mesh, repairs) = repair(finish(raw)?);
        if mesh.triangles.is_empty() {
            return Err(LoadError::Empty);
        }
        Ok(LoadedMesh {
            mesh,
            short_faces,
            repairs,
        })
    }
}

/// Fails with [`LoadError::TooMany`] when `count` triangles pass `limits`.
pub(crate) fn check_triangles(count: usize, limits: &MeshLimits) -> Result<(), LoadError> {
    if count > limits.max_triangles {
        return Err(LoadError::TooMany {
            what: "triangles",
            limit: limits.max_triangles,
        });
    }
    Ok(())
}

/// Fails with [`LoadError::TooMany`] when `count` vertices pass `limits`.
pub(crate) fn check_vertices(count: usize, limits: &MeshLimits) -> Result<(), LoadError> {
    if count > limits.max_vertices() {
        return Err(LoadError::TooMany {
            what: "vertices",
            limit: limits.max_vertices(),
        });
    }
    Ok(())
}

enum Format {
    Obj,
    Stl,
    Ply,
    ThreeMf,
    Gltf,
}

/// Positions and triangles as read from a file, before clean-up. Indices are already checked
/// to be in range.
pub(crate) struct RawMesh {
    pub positions: Vec<Point3<f64>>,
    pub triangles: Vec<[u32; 3]>,
}

/// Rejects non-finite coordinates and empty meshes, then merges bit-identical positions.
pub(crate) fn finish(raw: RawMesh) -> Result<TriMesh, LoadError> {
    if let Some(index) = raw
        .positions
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(LoadError::NonFinite { index });
    }
    if raw.triangles.is_empty() {
        return Err(LoadError::Empty);
    }
    debug_assert!(raw
        .triangles
        .iter()
        .flatten()
        .all(|&i| (i as usize) < raw.positions.len()));
    Ok(weld(raw))
}

/// Merges vertices with bit-identical positions (`-0.0` taken as `0.0`). The first occurrence
/// of a position keeps its place; the order of first occurrences is preserved.
fn weld(raw: RawMesh) -> TriMesh {
    let key = |p: &Point3<f64>| p.coords.map(|c| (c + 0.0).to_bits());
    let mut first: HashMap<_, u32> = HashMap::with_capacity(raw.positions.len());
    let mut positions = Vec::with_capacity(raw.positions.len());
    let remap: Vec<u32> = raw
        .positions
        .iter()
        .map(|p| {
            *first.entry(key(p)).or_insert_with(|| {
                positions.push(*p);
                // At most as many welded vertices as loaded ones, which fit in u32 indices.
                (positions.len() - 1) as u32
            })
        })
        .collect();
    let triangles = raw
        .triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .collect();
    TriMesh {
        positions,
        triangles,
    }
}

/// Converts a vertex count to the `u32` index space, or reports it with `err`.
pub(crate) fn index_u32(n: usize, err: impl FnOnce() -> LoadError) -> Result<u32, LoadError> {
    u32::try_from(n).map_err(|_| err())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64, z: f64) -> Point3<f64> {
        Point3::new(x, y, z)
    }

    #[test]
    fn weld_merges_identical_positions_first_wins() {
        let raw = RawMesh {
            positions: vec![
                p(0., 0., 0.),
                p(1., 0., 0.),
                p(0., 1., 0.),
                p(1., 0., 0.),
                p(-0.0, 1., 0.),
            ],
            triangles: vec![[0, 1, 2], [3, 4, 0]],
        };
        let mesh = finish(raw).unwrap();
        assert_eq!(
            mesh.positions,
            vec![p(0., 0., 0.), p(1., 0., 0.), p(0., 1., 0.)]
        );
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [1, 2, 0]]);
    }

    #[test]
    fn weld_keeps_unreferenced_vertices() {
        let raw = RawMesh {
            positions: vec![p(5., 5., 5.), p(0., 0., 0.), p(1., 0., 0.), p(0., 1., 0.)],
            triangles: vec![[1, 2, 3]],
        };
        let mesh = finish(raw).unwrap();
        assert_eq!(mesh.positions.len(), 4);
        assert_eq!(mesh.triangles, vec![[1, 2, 3]]);
    }

    #[test]
    fn rejects_non_finite_and_empty() {
        let raw = RawMesh {
            positions: vec![p(0., 0., 0.), p(f64::NAN, 0., 0.), p(0., 1., 0.)],
            triangles: vec![[0, 1, 2]],
        };
        assert!(matches!(
            finish(raw),
            Err(LoadError::NonFinite { index: 1 })
        ));
        let raw = RawMesh {
            positions: vec![p(0., 0., 0.)],
            triangles: vec![],
        };
        assert!(matches!(finish(raw), Err(LoadError::Empty)));
    }
}
