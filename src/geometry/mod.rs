//! Geometry: triangle meshes, loading, validation, mass properties and distance queries.
//!
//! - [`TriMesh`]: positions and counter-clockwise (seen from outside) triangles in one frame.
//! - [`load_mesh`]: `.obj`, `.stl`, `.3mf`, `.ply`, `.gltf` and `.glb` files, whole or one
//!   named part; the external buffer files a `.gltf` file reads, without loading them
//!   (`external_buffer_paths`).
//!   [`load_mesh_with`] reads only what a [`ReadPolicy`] allows: regular files, inside a
//!   folder, within [`MeshLimits`].
//! - [`read_rig`]: a glTF file as a rig: its nodes' rest transforms, its scenes' mesh nodes and
//!   its animations, sampled into node world transforms.
//! - [`Repairs`]: what loading repairs, as a slicer does: repeated triangles, flipped patches,
//!   holes, a mesh inside out.
//! - [`check_mesh`]: holes, non-manifold and misoriented edges, degenerate triangles, inversion,
//!   crossing triangles and misnested shells (a winding number other than 0 or 1).
//! - [`convex_hull`]: the exact convex hull of points, its coplanar triangles merged into
//!   convex polygon facets with outward normals; [`HullWalk`], its extent along a direction by
//!   walking its edges.
//! - [`mass_properties`]: volume, centroid and second moment of the enclosed solid.
//! - [`print_volumes`]: the solid and the sparse part of an FDM print of the solid.
//! - [`winding_number`]: inside/outside test that tolerates small holes.
//! - [`distance_to_point`], [`distance_to_segment`] and the primitive distances they use.
//! - [`TriangleTree`]: the same distances, fast, for many queries against one mesh.
//! - [`DistanceGrid`]: signed distance sampled on a grid, with a smooth interpolant.
//! - [`Skeleton`]: a curve skeleton as straight segments, whose midpoints seed capsules.

mod convex_hull;
mod distance;
mod edge_sort;
mod field;
mod gltf_buffers;
mod hull_walk;
mod load;
mod load_3mf;
mod load_files;
mod load_gltf;
mod load_obj;
mod load_ply;
mod load_stl;
mod mass;
mod mesh;
pub(crate) mod polygon;
mod print;
mod print_correction;
mod repair;
mod rig;
mod shells;
mod skeleton;
mod tree;
mod validate;
mod winding;

pub use convex_hull::{convex_hull, convex_hull_among, ConvexHull, HullFacet, COPLANAR};
pub use distance::{
    distance_to_point, distance_to_segment, point_triangle_distance, segment_segment_distance,
    segment_triangle_distance,
};
pub use field::DistanceGrid;
pub(crate) use gltf_buffers::external_buffer_paths;
pub use hull_walk::HullWalk;
pub use load::{load_mesh, load_mesh_with, LoadError, LoadedMesh, MeshFile, MeshSelector};
pub(crate) use load_files::FileReader;
pub use load_files::{MeshLimits, ReadPolicy, DEFAULT_MAX_MESH_BYTES, DEFAULT_MAX_TRIANGLES};
pub use mass::{mass_properties, MassProperties};
#[cfg(test)]
pub(crate) use mesh::box_at;
pub use mesh::TriMesh;
pub use print::{
    overlap, print_volumes, print_volumes_with_voids, Overlap, PrintRaster, PrintVolumes, Region,
    Slicing, Void, MODEL_REVISION,
};
pub use print_correction::PrintCorrection;
pub use repair::{Hole, Repairs};
pub use rig::{read_rig, Rig, RigAnimation, RigNode, RigScene};
pub use shells::ShellFault;
pub use skeleton::{Skeleton, SkeletonSegment};
pub use tree::TriangleTree;
pub use validate::{check_mesh, MeshCheck};
pub use winding::winding_number;
