//! The printed objects found on the bed and mapped back to their components' rest frames.
//!
//! Objects are matched to components by name (the object's label without the slicer's suffix
//! equals the component's name), else in order when the file has as many labelled objects as
//! the plan has parts; a file without labels holds one object, which is the plan's only part.
//!
//! A slicer may move a part on the bed (PrusaSlicer's command line centres or arranges what it
//! loads): the shift is the offset, in x and y, between the centre of the object's extrusions'
//! bounding box and the centre of the planned part's bounding box on the bed. G-code heights are
//! the nozzle's, at the top of the layer: each extrusion's material is taken half its layer's
//! thickness lower. Then `to_bed` is undone.

use nalgebra::{Point3, Vector3};
use serde::Serialize;

use super::SlicedError;
use crate::compile::Compilation;
use crate::fabrication::PrintPlan;
use crate::gcode::{filament_area, PrintedObject, Program};

/// One component as the file prints it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlicedComponent {
    /// The component's name.
    pub component: String,
    /// The label of the printed object found for it; `None` when the file labels no objects.
    pub object: Option<String>,
    /// How far the slicer moved the part on the bed from where the plan put it, x and y,
    /// project units.
    pub shift: [f64; 2],
    /// Extent of the planned part on the bed, x, y, z, project units.
    pub planned_size: [f64; 3],
    /// Extent of the object's extrusions (the nozzle's path), x, y, z, project units.
    pub printed_size: [f64; 3],
    /// Why the printed object does not look like the planned part, when it does not: an extent
    /// differs by more than twice the extrusion width plus a layer height.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mismatch: Option<String>,
    /// Extrusion moves.
    pub segments: usize,
    /// Volume of the extruded filament, cubic project units.
    pub volume: f64,
    /// Its mass, grams, at the material's density.
    pub mass: f64,
    /// Its centroid, the component's rest frame.
    pub centroid: [f64; 3],
}

/// A component's printed object, mapped back.
#[derive(Debug, Clone)]
pub(super) struct Placed {
    /// What is reported.
    pub summary: SlicedComponent,
    /// Its extrusion segments' material centre lines, rest frame, with their line numbers.
    pub segments: Vec<(Point3<f64>, Point3<f64>, usize)>,
}

/// Every component's printed object in `program`, with filament of `filament_diameter` mm.
pub(super) fn place(
    compilation: &Compilation,
    plan: &PrintPlan,
    program: &Program,
    filament_diameter: f64,
) -> Result<Vec<Placed>, SlicedError> {
    let project = &compilation.project;
    let objects = match_objects(compilation, program)?;
    let mm = project.units.from_millimetres(1.0);
    // Filament fed (mm) times its cross-section (mm²) is mm³: cubic project units at `mm³`.
    let area = filament_area(filament_diameter) * mm.powi(3);
    let density = project.material.density * project.units.cubic_in_cm3();
    let print = &project.print;
    let tolerance = 2.0 * print.extrusion_width + print.layer_height;
    let mut placed = Vec::with_capacity(objects.len());
    for (index, object) in objects.into_iter().enumerate() {
        let name = project.component_name(index).to_string();
        let component = plan
            .components
            .iter()
            .find(|c| c.component == index)
            .ok_or_else(|| SlicedError::Unplanned(name.clone()))?;
        let planned: Vec<Point3<f64>> = compilation.meshes[index]
            .positions
            .iter()
            .map(|p| component.to_bed * p)
            .collect();
        let (planned_low, planned_high) = bounds(planned.iter().copied());
        // Material centre lines on the bed, project units.
        let bed: Vec<(Point3<f64>, Point3<f64>, f64, usize)> = object
            .segments
            .iter()
            .map(|s| {
                let lower = Vector3::new(0.0, 0.0, program.layer_thickness(s.layer) / 2.0);
                (
                    Point3::from((s.start - lower).coords * mm),
                    Point3::from((s.end - lower).coords * mm),
                    s.filament,
                    s.line,
                )
            })
            .collect();
        let nozzle = object.segments.iter().flat_map(|s| [s.start, s.end]);
        let (low, high) = bounds(nozzle.map(|p| Point3::from(p.coords * mm)));
        let shift = Vector3::new(
            (low.x + high.x - planned_low.x - planned_high.x) / 2.0,
            (low.y + high.y - planned_low.y - planned_high.y) / 2.0,
            0.0,
        );
        let planned_size = planned_high - planned_low;
        let printed_size = Vector3::new(high.x - low.x, high.y - low.y, high.z);
        let mismatch = (0..3)
            .any(|axis| (planned_size[axis] - printed_size[axis]).abs() > tolerance)
            .then(|| {
                format!(
                    "component `{name}`: the printed object measures {:.2} × {:.2} × {:.2}, the \
                     planned part {:.2} × {:.2} × {:.2}: not the planned part in its planned \
                     orientation",
                    printed_size.x,
                    printed_size.y,
                    printed_size.z,
                    planned_size.x,
                    planned_size.y,
                    planned_size.z
                )
            });
        let to_rest = component.to_bed.inverse();
        let segments: Vec<(Point3<f64>, Point3<f64>, usize)> = bed
            .iter()
            .map(|(a, b, _, line)| (to_rest * (a - shift), to_rest * (b - shift), *line))
            .collect();
        let filament: f64 = bed.iter().map(|s| s.2).sum();
        let moment: Vector3<f64> = segments
            .iter()
            .zip(&bed)
            .map(|((a, b, _), s)| (a.coords + b.coords) * (s.2 / 2.0))
            .sum();
        let centroid = if filament > 0.0 {
            Point3::from(moment / filament)
        } else {
            compilation.mass[index].centroid
        };
        let volume = filament * area;
        placed.push(Placed {
            summary: SlicedComponent {
                component: name,
                object: object.label.clone(),
                shift: [shift.x, shift.y],
                planned_size: planned_size.into(),
                printed_size: printed_size.into(),
                mismatch,
                segments: object.segments.len(),
                volume,
                mass: volume * density,
                centroid: centroid.into(),
            },
            segments,
        });
    }
    Ok(placed)
}

/// The printed object of each component, in project order.
fn match_objects<'a>(
    compilation: &Compilation,
    program: &'a Program,
) -> Result<Vec<&'a PrintedObject>, SlicedError> {
    let project = &compilation.project;
    let count = project.components.len();
    let labelled: Vec<&PrintedObject> = program
        .objects
        .iter()
        .filter(|o| o.label.is_some())
        .collect();
    if labelled.is_empty() {
        return match program.objects.first() {
            Some(object) if count == 1 => Ok(vec![object]),
            _ => Err(SlicedError::Unmatched(format!(
                "the G-code labels no objects and the project has {count} components: slice \
                 with object labels on (PrusaSlicer: `--gcode-label-objects`)"
            ))),
        };
    }
    let by_name: Option<Vec<&PrintedObject>> = (0..count)
        .map(|i| {
            let name = project.component_name(i);
            let mut found = labelled.iter().filter(|o| o.name() == Some(name));
            match (found.next(), found.next()) {
                (Some(object), None) => Some(*object),
                _ => None,
            }
        })
        .collect();
    if let Some(objects) = by_name {
        return Ok(objects);
    }
    if labelled.len() == count {
        return Ok(labelled);
    }
    let names: Vec<String> = labelled
        .iter()
        .filter_map(|o| o.label.as_deref())
        .map(|label| format!("`{label}`"))
        .collect();
    Err(SlicedError::Unmatched(format!(
        "the G-code prints {} objects ({}) and the project has {count} components, not all \
         named alike: name each printed object after its component",
        labelled.len(),
        names.join(", ")
    )))
}

/// The bounding box of `points`; the origin for none.
fn bounds(points: impl IntoIterator<Item = Point3<f64>>) -> (Point3<f64>, Point3<f64>) {
    let mut points = points.into_iter();
    let Some(first) = points.next() else {
        return (Point3::origin(), Point3::origin());
    };
    points.fold((first, first), |(lo, hi), p| (lo.inf(&p), hi.sup(&p)))
}
