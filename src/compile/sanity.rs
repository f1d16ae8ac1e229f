//! Warnings for a valid project that is probably not what its author meant: a model of
//! implausible size or mass for a print (most often a mesh in another unit), a string tied far
//! from the model, and a stand on a point, an edge, a tiny facet or a sliver.

use nalgebra::{Point3, Vector3};

use crate::balance::PoseEvaluation;
use crate::diagnostic::Problem;
use crate::geometry::{distance_to_point, winding_number, TriMesh};
use crate::spec::model::{Goal, Project, Units};

/// A model under this many millimetres across is too small to print as meant.
pub const MIN_SIZE_MM: f64 = 5.0;
/// A model over this many millimetres across is larger than printers print.
pub const MAX_SIZE_MM: f64 = 1000.0;
/// A print lighter than this many grams is implausible.
pub const MIN_MASS_G: f64 = 0.5;
/// A suspension point outside the model farther than this fraction of its size from the surface
/// is not where a string can be tied.
pub const SUSPEND_FRACTION: f64 = 0.05;
/// A support polygon whose area is under the square of this fraction of the model's size is tiny.
pub const TINY_SUPPORT_FRACTION: f64 = 0.05;
/// A support polygon narrower than this fraction of the model's size is a sliver.
pub const SLIVER_FRACTION: f64 = 0.02;

/// Every sanity warning of `project`, whose components' rest-frame meshes are `meshes` and whose
/// poses evaluate to `poses`.
pub fn warnings(project: &Project, meshes: &[TriMesh], poses: &[PoseEvaluation]) -> Vec<Problem> {
    let Some(size) = model_size(meshes) else {
        return Vec::new();
    };
    let mut warnings = Vec::new();
    let too_small = size_warning(project, size, &mut warnings);
    if !too_small {
        mass_warning(project, poses, &mut warnings);
    }
    for (pose, evaluation) in project.poses.iter().zip(poses) {
        for goal in &pose.goals {
            match goal.value {
                Goal::Suspend {
                    point, component, ..
                } => {
                    if let Some(mesh) = meshes.get(component) {
                        warnings.extend(suspend_warning(
                            project, mesh, component, &point, size, goal.span,
                        ));
                    }
                }
                Goal::Stand { .. } => {
                    warnings.extend(stand_warning(project, evaluation, size, goal.span));
                }
                _ => {}
            }
        }
    }
    warnings
}

/// The largest side of the bounding box of every mesh together, project units.
fn model_size(meshes: &[TriMesh]) -> Option<f64> {
    let (lo, hi) = meshes
        .iter()
        .filter_map(TriMesh::bounding_box)
        .reduce(|(lo, hi), (l, h)| (lo.inf(&l), hi.sup(&h)))?;
    Some((hi - lo).max())
}

/// The warning for a model under [`MIN_SIZE_MM`] or over [`MAX_SIZE_MM`] across; whether it is
/// too small.
fn size_warning(project: &Project, size: f64, warnings: &mut Vec<Problem>) -> bool {
    let units = project.units;
    let mm = size * units.millimetres();
    if (MIN_SIZE_MM..=MAX_SIZE_MM).contains(&mm) {
        return false;
    }
    let shown = |value: f64| format!("{} {}", rounded(value), units.keyword());
    let mut warning = Problem::warning(
        "ballast::model::size",
        format!(
            "the model is {} across ({} mm): {} for a print",
            shown(size),
            rounded(mm),
            if mm < MIN_SIZE_MM {
                "too small"
            } else {
                "too large"
            }
        ),
    );
    for component in &project.components {
        warning = warning.with_label(component.mesh.span, "this mesh");
    }
    let first = &project.components[0].frame;
    let suggestion = [
        Units::Millimetre,
        Units::Centimetre,
        Units::Inch,
        Units::Metre,
    ]
    .into_iter()
    .filter(|&unit| unit != first.units)
    .map(|unit| (unit, mm * unit.millimetres() / first.units.millimetres()))
    .filter(|(_, size)| (MIN_SIZE_MM..=MAX_SIZE_MM).contains(size))
    .min_by(|a, b| {
        (a.1 / 100.0)
            .ln()
            .abs()
            .total_cmp(&(b.1 / 100.0).ln().abs())
    });
    let help = match suggestion {
        Some((unit, size)) => format!(
            "the mesh is read in {}: if it is in another unit, say which, e.g. `mesh-units={}` makes it {} mm across; or scale it with `scale=`",
            first.units.keyword(),
            unit.keyword(),
            rounded(size)
        ),
        None => "scale the mesh with `scale=` (or say its unit with `mesh-units=`)".to_string(),
    };
    warnings.push(warning.with_help(help));
    mm < MIN_SIZE_MM
}

/// The warning for a model lighter than [`MIN_MASS_G`].
fn mass_warning(project: &Project, poses: &[PoseEvaluation], warnings: &mut Vec<Problem>) {
    let Some(mass) = poses.first().map(|pose| pose.mass) else {
        return;
    };
    if mass >= MIN_MASS_G {
        return;
    }
    let mut warning = Problem::warning(
        "ballast::model::mass",
        format!("the model weighs {mass:.3} g: implausibly light for a print"),
    );
    for component in &project.components {
        warning = warning.with_label(component.mesh.span, "this mesh");
    }
    warnings.push(warning.with_help(
        "check the mesh's unit (`mesh-units=`, `scale=`), the material's density and the infill",
    ));
}

/// The warning for a suspension point outside the model farther than [`SUSPEND_FRACTION`] of its
/// size from the surface of its component.
fn suspend_warning(
    project: &Project,
    mesh: &TriMesh,
    component: usize,
    point: &Point3<f64>,
    size: f64,
    span: miette::SourceSpan,
) -> Option<Problem> {
    let distance = distance_to_point(mesh, point);
    if distance <= SUSPEND_FRACTION * size || winding_number(mesh, point) > 0.5 {
        return None;
    }
    let units = project.units.keyword();
    Some(
        Problem::warning(
            "ballast::goal::suspend_far",
            format!(
                "the suspension point is {} {units} outside component `{}`, {:.0}% of the model's size",
                rounded(distance),
                project.component_name(component),
                100.0 * distance / size
            ),
        )
        .with_label(span, "this point")
        .with_help("a string is tied at the surface: move the point onto the model (its coordinates are in the component's rest frame)"),
    )
}

/// The warning for a `stand` goal whose support is a point, an edge, a polygon of area under
/// ([`TINY_SUPPORT_FRACTION`] × size)² or one narrower than [`SLIVER_FRACTION`] × size.
fn stand_warning(
    project: &Project,
    evaluation: &PoseEvaluation,
    size: f64,
    span: miette::SourceSpan,
) -> Option<Problem> {
    let up = project.up.unit_vector();
    let polygon: Vec<Vector3<f64>> = evaluation
        .support
        .polygon
        .iter()
        .map(|&p| Vector3::from(p))
        .collect();
    let units = project.units.keyword();
    let what = match polygon.len() {
        0 => return None,
        1 => "a single point".to_string(),
        2 => "an edge".to_string(),
        _ => {
            let (area, width) = area_and_width(&polygon, &up);
            let tiny = TINY_SUPPORT_FRACTION * size;
            if area < tiny * tiny {
                format!(
                    "a facet of {} {units}², tiny beside the model",
                    rounded(area)
                )
            } else if width < SLIVER_FRACTION * size {
                format!("a sliver {} {units} wide", rounded(width))
            } else {
                return None;
            }
        }
    };
    Some(
        Problem::warning(
            "ballast::goal::small_support",
            format!(
                "in pose `{}`, the model stands on {what} ({} {units} across)",
                evaluation.pose,
                rounded(size)
            ),
        )
        .with_label(span, "this goal")
        .with_help("a print does not stand reliably there: `ballast poses` lists the facets it can stand on, with their areas; choose a larger one with `down`"),
    )
}

/// The area of the convex `polygon` (on a plane perpendicular to `up`) and its width: the
/// smallest, over its edges, of the farthest vertex's distance from the edge's line.
fn area_and_width(polygon: &[Vector3<f64>], up: &Vector3<f64>) -> (f64, f64) {
    let n = polygon.len();
    let mut twice_area = 0.0;
    let mut width = f64::INFINITY;
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        twice_area += a.cross(&b).dot(up);
        let edge = b - a;
        let length = edge.norm();
        if length > 0.0 {
            let farthest = polygon
                .iter()
                .map(|v| edge.cross(&(v - a)).dot(up).abs() / length)
                .fold(0.0, f64::max);
            width = width.min(farthest);
        }
    }
    (0.5 * twice_area.abs(), width)
}

/// `value` to three significant digits (at least), for messages.
fn rounded(value: f64) -> String {
    let magnitude = value.abs().log10().floor();
    let decimals = if magnitude.is_finite() {
        (2.0 - magnitude).clamp(0.0, 12.0) as usize
    } else {
        0
    };
    format!("{value:.decimals$}")
}
