//! Loading every component's mesh into the rest frame (its [`MeshFrame`]: unit, up axis, scale)
//! and checking it is a printable solid, with each failure turned into a diagnostic on the
//! component's `mesh=` value.

use std::path::Path;

use nalgebra::Point3;

use super::design::round;
use super::mesh_cache::MeshCache;
use crate::diagnostic::Problem;
use crate::geometry::{LoadError, MeshCheck, TriMesh};
use crate::spec::model::{Component, MeshFrame, Project};

/// How many offending edges or triangles a diagnostic lists before it only counts the rest.
const LISTED: usize = 3;

/// Loads and checks the mesh of every component, in order, through `cache`. Returns the meshes
/// when all of them are usable, and the problems found (every component is tried, so all are
/// reported at once).
pub fn load_components(
    project: &Project,
    cache: &mut MeshCache,
) -> (Option<Vec<TriMesh>>, Vec<Problem>) {
    let mut meshes = Vec::with_capacity(project.components.len());
    let mut problems = Vec::new();
    for component in &project.components {
        match cache.load(&component.mesh.value, &component.selector) {
            Ok((mesh, check)) => {
                let (mesh, check) = into_rest_frame(mesh, check, &component.frame, project);
                let found = mesh_problems(component, &mesh, &check);
                if found.is_empty() {
                    meshes.push(mesh);
                }
                problems.extend(found);
            }
            Err(error) => problems.push(load_problem(component, &error)),
        }
    }
    let usable = meshes.len() == project.components.len();
    (usable.then_some(meshes), problems)
}

/// `mesh` (and its `check`) from its file's coordinates into the rest frame: turned from the
/// mesh's up axis to the project's, then scaled into project units. Untouched when the frame is
/// the identity, so a mesh in project units keeps its exact coordinates.
fn into_rest_frame(
    mesh: TriMesh,
    mut check: MeshCheck,
    frame: &MeshFrame,
    project: &Project,
) -> (TriMesh, MeshCheck) {
    if frame.is_identity(project.units, project.up) {
        return (mesh, check);
    }
    let rotation = frame.rotation(project.up);
    let factor = frame.factor(project.units);
    // A proper rotation and a positive factor keep every triangle's orientation, so the check's
    // edge and triangle lists still hold; only the volume scales.
    check.signed_volume *= factor * factor * factor;
    let mesh = TriMesh {
        positions: mesh
            .positions
            .iter()
            .map(|p| Point3::from(rotation * p.coords * factor))
            .collect(),
        triangles: mesh.triangles,
    };
    (mesh, check)
}

fn load_problem(component: &Component, error: &LoadError) -> Problem {
    let name = &component.name.value;
    let span = component.mesh.span;
    let shown = display_path(&component.mesh.value);
    match error {
        LoadError::NotFound { .. } => Problem::error(
            "ballast::mesh::not_found",
            format!("mesh file `{shown}` of component `{name}` does not exist"),
        )
        .with_label(span, "no such file")
        .with_help("paths are relative to the folder of the project file"),
        LoadError::UnknownPart {
            name: part,
            available,
        } => {
            let mut problem = Problem::error(
                "ballast::mesh::unknown_part",
                format!("`{shown}` has no part named `{part}`"),
            )
            .with_label(span, "in this file");
            let suggestion =
                crate::spec::vocabulary::suggest(part, available.iter().map(String::as_str));
            problem.help = Some(match suggestion {
                Some(close) => format!("did you mean `{close}`?"),
                None if available.is_empty() => "the file has no named parts".to_string(),
                None => format!("the file has: {}", available.join(", ")),
            });
            problem
        }
        other => Problem::error(
            "ballast::mesh::unreadable",
            format!("cannot load the mesh of component `{name}`: {other}"),
        )
        .with_label(span, "this mesh"),
    }
    .with_label(component.name.span, "component")
}

/// The problems that make `mesh` unusable as the solid of `component`.
fn mesh_problems(component: &Component, mesh: &TriMesh, check: &MeshCheck) -> Vec<Problem> {
    let name = &component.name.value;
    let span = component.mesh.span;
    let mut problems = Vec::new();
    let mut edge_problem = |code, what: &str, edges: &[[u32; 2]], help: &str| {
        if !edges.is_empty() {
            problems.push(
                Problem::error(
                    code,
                    format!(
                        "the mesh of component `{name}` has {} {what}: {}",
                        edges.len(),
                        list_edges(mesh, edges)
                    ),
                )
                .with_label(span, "this mesh")
                .with_help(help.to_string()),
            );
        }
    };
    edge_problem(
        "ballast::mesh::open",
        "boundary edges (holes)",
        &check.boundary_edges,
        "a printable solid must be closed: fill the holes in a mesh editor",
    );
    edge_problem(
        "ballast::mesh::non_manifold",
        "edges shared by more than two triangles",
        &check.non_manifold_edges,
        "split or repair the mesh so every edge borders exactly two triangles",
    );
    edge_problem(
        "ballast::mesh::misoriented",
        "edges where neighbouring triangles disagree on the outside",
        &check.misoriented_edges,
        "make the triangle winding consistent (recalculate normals in a mesh editor)",
    );
    problems.extend(solid_problems(component, mesh, check));
    problems
}

fn solid_problems(component: &Component, mesh: &TriMesh, check: &MeshCheck) -> Vec<Problem> {
    let name = &component.name.value;
    let span = component.mesh.span;
    let mut problems = Vec::new();
    if !check.degenerate_triangles.is_empty() {
        let count = check.degenerate_triangles.len();
        let first = check.degenerate_triangles[0] as usize;
        let corners: Vec<String> = mesh
            .triangles
            .get(first)
            .into_iter()
            .flatten()
            .map(|&corner| format_point(mesh, corner))
            .collect();
        problems.push(
            Problem::error(
                "ballast::mesh::degenerate",
                format!(
                    "the mesh of component `{name}` has {count} degenerate triangle{} (zero area or a repeated vertex), the first at {}",
                    if count == 1 { "" } else { "s" },
                    corners.join(", ")
                ),
            )
            .with_label(span, "this mesh")
            .with_help("remove the degenerate triangles (merge by distance, then dissolve degenerate)"),
        );
    }
    if check.is_closed() && check.is_oriented() {
        if check.is_inverted() {
            problems.push(
                Problem::error(
                    "ballast::mesh::inverted",
                    format!(
                        "the mesh of component `{name}` is inside out (its volume is {})",
                        round(check.signed_volume)
                    ),
                )
                .with_label(span, "this mesh")
                .with_help("flip every triangle's winding so the normals point outwards"),
            );
        } else if check.signed_volume == 0.0 {
            problems.push(
                Problem::error(
                    "ballast::mesh::flat",
                    format!("the mesh of component `{name}` encloses no volume"),
                )
                .with_label(span, "this mesh"),
            );
        }
    }
    problems
}

/// `(x, y, z)–(x, y, z), …, and n more`: the end points of the first few edges.
fn list_edges(mesh: &TriMesh, edges: &[[u32; 2]]) -> String {
    let mut listed: Vec<String> = edges
        .iter()
        .take(LISTED)
        .map(|&[a, b]| format!("{}–{}", format_point(mesh, a), format_point(mesh, b)))
        .collect();
    if edges.len() > LISTED {
        listed.push(format!("and {} more", edges.len() - LISTED));
    }
    listed.join(", ")
}

fn format_point(mesh: &TriMesh, index: u32) -> String {
    match mesh.positions.get(index as usize) {
        Some(p) => format!("({}, {}, {})", round(p.x), round(p.y), round(p.z)),
        None => "(?)".to_string(),
    }
}

fn display_path(path: &Path) -> String {
    path.file_name()
        .map(|name| name.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}
