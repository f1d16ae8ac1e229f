//! Loading every component's mesh into the rest frame (its [`MeshFrame`]: unit, up axis, scale)
//! and checking it is a printable solid, with each failure turned into a diagnostic on the
//! component's `mesh=` value.

use std::path::Path;

use nalgebra::Point3;

use super::design::round;
use super::mesh_cache::MeshCache;
use super::mesh_repairs::repair_problems;
use crate::diagnostic::Problem;
use crate::geometry::{
    convex_hull, ConvexHull, LoadError, LoadedMesh, MassProperties, MeshCheck, ReadPolicy, Repairs,
    TriMesh,
};
use crate::spec::model::{Component, MeshFrame, Project};

/// How many offending edges or triangles a diagnostic lists before it only counts the rest.
const LISTED: usize = 3;

/// Every component's mesh in the rest frame, the mass properties of the solid it bounds, and its
/// convex hull (`None` for a mesh that spans no volume).
pub type LoadedComponents = (Vec<TriMesh>, Vec<MassProperties>, Vec<Option<ConvexHull>>);

/// Loads and checks the mesh of every component, in order, through `cache`, reading only what
/// `policy` allows. Returns the meshes when all of them are usable, with the mass properties of
/// the solid each bounds (the union of its shells, [`MeshCheck::solid`]) and its convex hull in
/// the rest frame (computed while the mesh is checked), and the problems found (every component
/// is tried, so all are reported at once), warnings included.
pub fn load_components(
    project: &Project,
    cache: &mut MeshCache,
    policy: &ReadPolicy,
) -> (Option<LoadedComponents>, Vec<Problem>) {
    let mut meshes = Vec::with_capacity(project.components.len());
    let mut solids = Vec::with_capacity(project.components.len());
    let mut hulls = Vec::with_capacity(project.components.len());
    // Each component's problems, in component order.
    let mut found: Vec<Vec<Problem>> = vec![Vec::new(); project.components.len()];
    // Loading failures, one per mesh file and error: the first component that met it, and every
    // component that shares it. Its one diagnostic goes where the first component's would.
    let mut failures: Vec<(&Path, String, usize, Vec<&Component>, LoadError)> = Vec::new();
    for (index, component) in project.components.iter().enumerate() {
        // The positions in the rest frame (unless the frame is the identity) and their hull,
        // while the mesh is checked.
        let in_rest_frame = |mesh: &TriMesh| match rest_frame(&component.frame, project) {
            None => (None, convex_hull(&mesh.positions)),
            Some(to_rest) => {
                let positions: Vec<Point3<f64>> = mesh.positions.iter().map(to_rest).collect();
                let hull = convex_hull(&positions);
                (Some(positions), hull)
            }
        };
        match cache.load(
            &component.mesh.value,
            &component.selector,
            policy,
            in_rest_frame,
        ) {
            Ok((
                LoadedMesh {
                    mesh,
                    short_faces,
                    mut repairs,
                },
                check,
                (positions, hull),
            )) => {
                found[index].extend(short_face_warning(component, &short_faces));
                let (mesh, check) = into_rest_frame(
                    mesh,
                    check,
                    &mut repairs,
                    positions,
                    &component.frame,
                    project,
                );
                let extent = mesh
                    .bounding_box()
                    .map_or(0.0, |(low, high)| (high - low).max());
                found[index].extend(repair_problems(component, &repairs, project.wall, extent));
                let problems = mesh_problems(component, &mesh, &check);
                if problems.iter().all(|problem| !problem.is_error()) {
                    solids.push(check.solid(&mesh));
                    meshes.push(mesh);
                    hulls.push(hull);
                }
                found[index].extend(problems);
            }
            Err(error) => {
                let path = component.mesh.value.as_path();
                let key = error.to_string();
                match failures
                    .iter_mut()
                    .find(|(p, k, ..)| *p == path && *k == key)
                {
                    Some((.., sharing, _)) => sharing.push(component),
                    None => failures.push((path, key, index, vec![component], error)),
                }
            }
        }
    }
    for (_, _, first, sharing, error) in &failures {
        found[*first].push(load_problem(sharing, error, policy));
    }
    let problems = found.into_iter().flatten().collect();
    let usable = meshes.len() == project.components.len();
    (usable.then_some((meshes, solids, hulls)), problems)
}

/// `mesh` (and its `check`, and the holes its `repairs` capped) from its file's coordinates into
/// the rest frame: turned from the mesh's up axis to the project's, then scaled into project
/// units; `positions` are its positions moved so ([`rest_frame`]), `None` when the frame is the
/// identity. Untouched then, so a mesh in project units keeps its exact coordinates.
fn into_rest_frame(
    mesh: TriMesh,
    mut check: MeshCheck,
    repairs: &mut Repairs,
    positions: Option<Vec<Point3<f64>>>,
    frame: &MeshFrame,
    project: &Project,
) -> (TriMesh, MeshCheck) {
    let (Some(positions), Some(to_rest)) = (positions, rest_frame(frame, project)) else {
        return (mesh, check);
    };
    let rotation = frame.rotation(project.up);
    let factor = frame.factor(project.units);
    // A proper rotation and a positive factor keep every triangle's orientation, so the check's
    // edge and triangle lists still hold; only the volume scales.
    check.signed_volume *= factor * factor * factor;
    if let Some(overlap) = &mut check.overlap {
        *overlap = overlap.turned_and_scaled(&rotation, factor);
    }
    for hole in &mut repairs.holes {
        hole.width *= factor;
        hole.centre = to_rest(&hole.centre);
    }
    let mesh = TriMesh {
        positions,
        triangles: mesh.triangles,
    };
    (mesh, check)
}

/// A point's move from its file's coordinates into the rest frame of `frame` (turned from the
/// mesh's up axis to the project's, then scaled into project units); `None` when the frame is
/// the identity.
fn rest_frame(
    frame: &MeshFrame,
    project: &Project,
) -> Option<impl Fn(&Point3<f64>) -> Point3<f64>> {
    if frame.is_identity(project.units, project.up) {
        return None;
    }
    let rotation = frame.rotation(project.up);
    let factor = frame.factor(project.units);
    Some(move |p: &Point3<f64>| Point3::from(rotation * p.coords * factor))
}

/// The diagnostic for `error`, which loading the mesh of every one of `sharing` (at least one
/// component, all reading one file) met: one diagnostic naming them all.
fn load_problem(sharing: &[&Component], error: &LoadError, policy: &ReadPolicy) -> Problem {
    let component = sharing[0];
    let who = components_named(sharing);
    let span = component.mesh.span;
    let shown = display_path(&component.mesh.value);
    let mut problem = match error {
        LoadError::NotFound { .. } => Problem::error(
            "ballast::mesh::not_found",
            format!("mesh file `{shown}` of {who} does not exist"),
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
        LoadError::Skinned { node } => Problem::error(
            "ballast::mesh::skinned",
            format!(
                "the mesh of {who} is node `{node}` of `{shown}`, a skinned mesh, \
                 which bends with its joints: skinned meshes are not read"
            ),
        )
        .with_label(span, "in this file")
        .with_help(
            "a printed part is rigid: in the editor, separate the mesh into one object per part \
             and parent each to its bone (Blender: Ctrl+P, Bone) instead of an armature modifier",
        ),
        LoadError::OutsideFolder { path, .. } => Problem::error(
            "ballast::mesh::outside_project",
            format!(
                "the mesh of {who} reads `{}`, which is outside the project's folder",
                relative(path, policy)
            ),
        )
        .with_label(span, "this mesh")
        .with_help(
            "move the file into the project's folder, or pass `--read-outside` to let meshes and \
             glTF buffers be read from any folder",
        ),
        LoadError::NotAFile { path } => Problem::error(
            "ballast::mesh::not_a_file",
            format!(
                "the mesh of {who} reads `{}`, which is not a regular file",
                relative(path, policy)
            ),
        )
        .with_label(span, "this mesh")
        .with_help(
            "ballast reads only regular files: never folders, devices, pipes, or files under \
             /proc, /sys or /dev",
        ),
        LoadError::TooLarge { path, limit } => Problem::error(
            "ballast::mesh::too_large",
            format!(
                "the mesh of {who} is larger than the limit of {} MiB (at `{}`)",
                limit >> 20,
                relative(path, policy)
            ),
        )
        .with_label(span, "this mesh")
        .with_help(
            "the limit counts the mesh file and its glTF buffer files together; raise it with \
             `--max-mesh-mb N`",
        ),
        LoadError::TooMany { what, limit } => Problem::error(
            "ballast::mesh::too_many_triangles",
            format!("the mesh of {who} has more than {limit} {what}"),
        )
        .with_label(span, "this mesh")
        .with_help(
            "simplify the mesh (decimate it), or raise the limit with `--max-triangles N` \
             (a mesh may read three vertices per triangle)",
        ),
        LoadError::NonFinite { index } => Problem::error(
            "ballast::mesh::not_finite",
            format!(
                "vertex {} of the mesh of {who} has a coordinate that is infinite, \
                 NaN or too large",
                index + 1
            ),
        )
        .with_label(span, "this mesh")
        .with_help("every coordinate must be a finite number"),
        other => Problem::error(
            "ballast::mesh::unreadable",
            format!("cannot load the mesh of {who}: {other}"),
        )
        .with_label(span, "this mesh"),
    }
    .with_label(component.name.span, "component");
    for other in sharing.iter().skip(1).take(LISTED - 1) {
        problem = problem.with_label(other.mesh.span, "the same file");
    }
    problem
}

/// "component `a`", or for several "components `a`, `b` and `c`" (past [`LISTED`] names, "and
/// N more").
fn components_named(components: &[&Component]) -> String {
    let names: Vec<String> = components
        .iter()
        .map(|component| format!("`{}`", component.name.value))
        .collect();
    match names.as_slice() {
        [one] => format!("component {one}"),
        [first @ .., last] if names.len() <= LISTED => {
            format!("components {} and {last}", first.join(", "))
        }
        _ => format!(
            "components {} and {} more",
            names[..LISTED].join(", "),
            names.len() - LISTED
        ),
    }
}

/// A warning naming the OBJ faces with fewer than three vertices, which the mesh leaves out.
fn short_face_warning(component: &Component, lines: &[usize]) -> Option<Problem> {
    let first = lines.first()?;
    let count = lines.len();
    Some(
        Problem::warning(
            "ballast::mesh::short_face",
            format!(
                "the mesh of component `{}` has {count} face{} with fewer than three vertices \
                 (the first on line {first}), left out of the solid",
                component.name.value,
                if count == 1 { "" } else { "s" }
            ),
        )
        .with_label(component.mesh.span, "this mesh")
        .with_help("a face needs three or more vertices; delete these lines or fix their indices"),
    )
}

/// `fraction` as a percentage, with two decimals or two significant digits, whichever shows
/// more.
fn percent(fraction: f64) -> String {
    let value = fraction * 100.0;
    if value <= 0.0 || !value.is_finite() {
        return format!("{value} %");
    }
    let decimals = (1.0 - value.log10().floor()).clamp(2.0, 12.0) as usize;
    format!("{value:.decimals$} %")
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
        "edges shared by more than two triangles that do not pair up (as many running along \
         the edge as against it)",
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
            Problem::warning(
                "ballast::mesh::degenerate",
                format!(
                    "the mesh of component `{name}` has {count} triangle{} of zero area (three \
                     corners on a line), the first at {}: kept, since {} nothing and close{} \
                     the surface",
                    if count == 1 { "" } else { "s" },
                    corners.join(", "),
                    if count == 1 {
                        "it encloses"
                    } else {
                        "they enclose"
                    },
                    if count == 1 { "s" } else { "" },
                ),
            )
            .with_label(span, "this mesh")
            .with_help(
                "nothing to do; a mesh editor's dissolve degenerate removes them from the file",
            ),
        );
    }
    if let Some(&[a, b]) = check.crossing_triangles.first() {
        let count = check.crossing_triangles.len();
        let crossing = format!(
            "{count} pair{} of triangles cross, the first at {} and {}",
            if count == 1 { "" } else { "s" },
            format_triangle(mesh, a),
            format_triangle(mesh, b)
        );
        let share = check
            .overlap
            .filter(|overlap| overlap.union > 0.0)
            .map(|overlap| overlap.volume / overlap.union);
        match share {
            Some(share) => problems.push(
                Problem::warning(
                    "ballast::mesh::crossing",
                    format!(
                        "the mesh of component `{name}` crosses itself: {crossing}; its shells \
                         overlap by {} of the solid, which is their union, as a slicer prints it",
                        percent(share)
                    ),
                )
                .with_label(span, "this mesh")
                .with_help(
                    "the solid's volume, mass and balance are the union's (the overlap counted \
                     once); a boolean union in a mesh editor makes the file say so too",
                ),
            ),
            None => problems.push(
                Problem::error(
                    "ballast::mesh::self_intersecting",
                    format!("the mesh of component `{name}` intersects itself: {crossing}"),
                )
                .with_label(span, "this mesh")
                .with_help(
                    "its overlap could not be measured: join overlapping shells with a boolean \
                     union, or remove the fold, in a mesh editor",
                ),
            ),
        }
    }
    if let Some(fault) = check.shell_faults.first() {
        let count = check.shell_faults.len();
        let what = if fault.winding > 1 {
            "inside another shell that faces the same way: it is filled, part of the shell \
             around it"
        } else {
            "facing inwards without being inside another shell: it encloses nothing a slicer \
             prints"
        };
        let problem = |problem: Problem| {
            problem.with_label(span, "this mesh").with_help(
                "a cavity must face inwards and be inside the shell around it; a separate \
                     part inside another belongs in its own component",
            )
        };
        let first = format_triangle(mesh, fault.triangle);
        let plural = if count == 1 { "" } else { "s" };
        problems.push(match check.overlap {
            Some(_) => problem(Problem::warning(
                "ballast::mesh::nested_shells",
                format!(
                    "the mesh of component `{name}` has {count} shell{plural} not nested right; \
                     the first, through {first}, is {what}; the solid is the union of its \
                     shells (winding number above 0), as a slicer prints it",
                ),
            )),
            None => problem(Problem::error(
                "ballast::mesh::nested_shells",
                format!(
                    "the mesh of component `{name}` has {count} shell{plural} not nested right \
                     and cannot be measured; the first, through {first}, is {what}",
                ),
            )),
        });
    }
    if check.shells_unchecked {
        problems.push(
            Problem::warning(
                "ballast::mesh::unchecked_shells",
                format!(
                    "the mesh of component `{name}` was not fully checked for crossing triangles \
                     and nested shells: too many triangles overlap in one place"
                ),
            )
            .with_label(span, "this mesh")
            .with_help("its volume is right only if no two of its surfaces cross"),
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

/// `(x, y, z)–(x, y, z)–(x, y, z)`: the corners of a triangle.
fn format_triangle(mesh: &TriMesh, index: u32) -> String {
    let corners: Vec<String> = mesh
        .triangles
        .get(index as usize)
        .into_iter()
        .flatten()
        .map(|&corner| format_point(mesh, corner))
        .collect();
    corners.join("–")
}

fn format_point(mesh: &TriMesh, index: u32) -> String {
    match mesh.positions.get(index as usize) {
        Some(p) => format_position(p),
        None => "(?)".to_string(),
    }
}

/// `(x, y, z)`, each rounded for a diagnostic.
pub(super) fn format_position(p: &Point3<f64>) -> String {
    format!("({}, {}, {})", round(p.x), round(p.y), round(p.z))
}

/// `path` relative to the folder `policy` confines reads to, when it is in it lexically (as
/// mesh paths, joined to the project's folder, are); else as it is.
fn relative(path: &Path, policy: &ReadPolicy) -> String {
    policy
        .within
        .as_deref()
        .and_then(|folder| path.strip_prefix(folder).ok())
        .unwrap_or(path)
        .display()
        .to_string()
}

fn display_path(path: &Path) -> String {
    path.file_name()
        .map(|name| name.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}
