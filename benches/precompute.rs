//! The optimizer's precompute per mesh size: the signed distance grid at the default spacing and
//! the skeleton thinned on it (and, apart, the time then to read every node: the deferred blocks
//! that the grid's background thread has not computed yet are computed by the read), for the examples' meshes and the real meshes in `../shared/meshes`
//! (each scaled so its longest side is 150 mm, capsules at least 1.2 mm in radius, as a project in
//! millimetres with the default clearance gets). `docs/benchmarks.md` gives the figures.
//!
//! Run with `cargo bench --bench precompute`; a mesh that is missing is skipped with a note. The
//! shared meshes are looked for in `BALLAST_SHARED_MESHES` when set.
//! `BALLAST_BENCH_FILTER=word` keeps only the meshes whose label contains it.
//! `BALLAST_BENCH_EXPORT=folder` also writes each mesh as benched (`LABEL.obj`) and its grid
//! (`LABEL.grid.json`: origin, cell, dims; `LABEL.grid.f64`: the node values, little-endian, x
//! fastest), for `benches/igl_compare.py` to time libigl on the same nodes.

mod support;

use std::path::PathBuf;
use std::time::Instant;

use ballast::geometry::{load_mesh, DistanceGrid, MeshSelector, Skeleton, TriMesh};
use ballast::optimize::default_cell;
use support::manifest;

/// The smallest capsule radius of a project in millimetres with the default ball clearance.
const MIN_RADIUS: f64 = 1.2;

/// The longest side every shared mesh is scaled to, millimetres.
const SIDE: f64 = 150.0;

/// (label, path, and whether it is a shared mesh: under the shared folder and scaled to
/// [`SIDE`]; otherwise from the repository's root as it is).
const MESHES: [(&str, &str, bool); 10] = [
    ("t_shape", "examples/meshes/t_shape.obj", false),
    (
        "sheared_cylinder",
        "examples/meshes/sheared_cylinder.obj",
        false,
    ),
    ("hinged_arm", "examples/meshes/hinged_arm.obj", false),
    ("spot", "examples/meshes/spot.obj", false),
    ("blub_fish", "examples/meshes/blub_fish.obj", false),
    ("hammer_example", "examples/meshes/hammer.obj", false),
    ("rocker_arm", "rocker_arm.obj", true),
    ("boat", "boat.obj", true),
    ("hammer_60k", "hammer.obj", true),
    ("hammer_240k", "large/hammer_240k.obj", true),
];

fn main() {
    let filter = std::env::var("BALLAST_BENCH_FILTER").unwrap_or_default();
    println!(
        "| mesh | triangles | cell (mm) | nodes | deferred | grid (s) | skeleton (s) | every node read (s) |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for (label, path, scaled) in MESHES {
        if !label.contains(filter.as_str()) {
            continue;
        }
        let path: PathBuf = if scaled {
            shared().join(path)
        } else {
            manifest().join(path)
        };
        let mut mesh = match load_mesh(&path, &MeshSelector::Whole) {
            Ok(mesh) => mesh,
            Err(error) => {
                eprintln!("skipping {label}: {error}");
                continue;
            }
        };
        if scaled {
            scale_to(&mut mesh, SIDE);
        }
        let cell = default_cell(&mesh, MIN_RADIUS);
        let clock = Instant::now();
        let grid = DistanceGrid::new(&mesh, cell);
        let grid_time = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let skeleton = Skeleton::from_grid(&mesh, &grid);
        let skeleton_time = clock.elapsed().as_secs_f64();
        std::hint::black_box(skeleton);
        let deferred = grid.deferred_nodes();
        let clock = Instant::now();
        let [nx, ny, nz] = grid.dims();
        let mut sum = 0.0;
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    sum += grid.node_value([i, j, k]).expect("in the grid");
                }
            }
        }
        std::hint::black_box(sum);
        let read_time = clock.elapsed().as_secs_f64();
        if let Some(folder) = std::env::var_os("BALLAST_BENCH_EXPORT") {
            export(&PathBuf::from(folder), label, &mesh, &grid).expect("writing the export");
        }
        let nodes: usize = grid.dims().iter().product();
        println!(
            "| {label} | {} | {cell:.3} | {nodes} | {deferred} | {grid_time:.3} | {skeleton_time:.3} | {read_time:.3} |",
            mesh.triangles.len()
        );
    }
}

/// Writes `mesh` and `grid` into `folder` as `label.obj`, `label.grid.json` and `label.grid.f64`.
fn export(
    folder: &std::path::Path,
    label: &str,
    mesh: &TriMesh,
    grid: &DistanceGrid,
) -> std::io::Result<()> {
    use std::fmt::Write as _;
    let mut obj = String::new();
    for p in &mesh.positions {
        let _ = writeln!(obj, "v {:?} {:?} {:?}", p.x, p.y, p.z);
    }
    for t in &mesh.triangles {
        let _ = writeln!(obj, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(folder.join(format!("{label}.obj")), obj)?;
    let origin = grid.origin();
    let dims = grid.dims();
    let header = format!(
        "{{\"origin\": [{:?}, {:?}, {:?}], \"cell\": {:?}, \"dims\": [{}, {}, {}]}}\n",
        origin.x,
        origin.y,
        origin.z,
        grid.cell(),
        dims[0],
        dims[1],
        dims[2]
    );
    std::fs::write(folder.join(format!("{label}.grid.json")), header)?;
    // Every node, the deferred ones computed now.
    let [nx, ny, nz] = dims;
    let bytes: Vec<u8> = (0..nz)
        .flat_map(|k| (0..ny).flat_map(move |j| (0..nx).map(move |i| [i, j, k])))
        .flat_map(|index| grid.node_value(index).expect("in the grid").to_le_bytes())
        .collect();
    std::fs::write(folder.join(format!("{label}.grid.f64")), bytes)
}

/// The folder of the shared meshes: `BALLAST_SHARED_MESHES`, or `../shared/meshes` beside the
/// checkout.
fn shared() -> PathBuf {
    std::env::var_os("BALLAST_SHARED_MESHES")
        .map(PathBuf::from)
        .unwrap_or_else(|| manifest().join("../shared/meshes"))
}

/// Scales `mesh` about the origin so its bounding box's longest side is `side`.
fn scale_to(mesh: &mut TriMesh, side: f64) {
    let Some((lo, hi)) = mesh.bounding_box() else {
        return;
    };
    let factor = side / (hi - lo).max();
    for p in &mut mesh.positions {
        *p = (p.coords * factor).into();
    }
}
