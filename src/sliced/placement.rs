//! The printed objects found on the bed and mapped back to their components' rest frames.
//!
//! Objects are matched to components by name (the object's label without the slicer's suffix
//! equals the component's name), else in order when the file has as many labelled objects as
//! the plan has parts; a file without labels holds one object, which is the plan's only part.
//!
//! A slicer may move a part on the bed (PrusaSlicer's command line centres or arranges what it
//! loads): the shift is found by fitting the object's outer perimeter on a few layers to the
//! planned part's outline at those heights (`fit.rs`), starting from the offset between the
//! centres of the extrusions' and the planned part's bounding boxes; a fit that cannot be
//! trusted is reported and the plan's place kept. G-code heights are
//! the nozzle's, at the top of the layer: each extrusion's material is taken half its layer's
//! thickness lower. Then `to_bed` is undone.

use nalgebra::{Isometry3, Point3, Vector2, Vector3};
use serde::Serialize;

use super::fit::{self, FitLayer, Outline2, PlacementFit, Sample};
use super::voids::{self, VoidCheck};
use super::SlicedError;
use crate::compile::Compilation;
use crate::fabrication::PrintPlan;
use crate::gcode::{filament_area, ObjectOutline, Outline, Segment};

/// One component as the file prints it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlicedComponent {
    /// The component's name.
    pub component: String,
    /// The label of the printed object found for it; `None` when the file labels no objects.
    pub object: Option<String>,
    /// How far the slicer moved the part on the bed from where the plan put it, x and y,
    /// project units: the fit's shift when it is trusted, else none (the plan's place).
    pub shift: [f64; 2],
    /// The part's place found from its outer perimeter (`fit.rs`).
    pub fit: PlacementFit,
    /// Why the fit is not trusted (and not applied), when it is not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub doubt: Option<String>,
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

/// Each printed object's extent by [`ObjectOutline::id`]; `None` for an object with no
/// extrusion.
pub(super) type NozzleBoxes = Vec<Option<Extent>>;

/// The bounding box of a printed object's nozzle path, project units, and its first and last
/// layers.
#[derive(Debug, Clone, Copy)]
pub(super) struct Extent {
    low: Point3<f64>,
    high: Point3<f64>,
    first_layer: usize,
    last_layer: usize,
}

/// Grows `boxes` by `segment` of object `id` (project units at `mm` per mm), its start then its
/// end: the first pass over the file.
pub(super) fn grow_box(boxes: &mut NozzleBoxes, id: usize, segment: &Segment, mm: f64) {
    if boxes.len() <= id {
        boxes.resize(id + 1, None);
    }
    for p in [segment.start, segment.end] {
        let p = Point3::from(p.coords * mm);
        let layer = segment.layer;
        boxes[id] = Some(boxes[id].map_or(
            Extent {
                low: p,
                high: p,
                first_layer: layer,
                last_layer: layer,
            },
            |e| Extent {
                low: e.low.inf(&p),
                high: e.high.sup(&p),
                first_layer: e.first_layer.min(layer),
                last_layer: e.last_layer.max(layer),
            },
        ));
    }
}

/// Per printed object, the samples of its extrusions on the layers its placement is fitted on
/// (`fit.rs`): the second pass over the file.
pub(super) struct FitSamples {
    /// Per object id, its fitted layers, each with its samples.
    layers: Vec<Vec<(usize, Vec<Sample>)>>,
    spacing: f64,
    mm: f64,
}

impl FitSamples {
    /// Nothing yet sampled, on the layers [`fit::fit_layers`] chooses for each object of
    /// `boxes`, at `mm` project units per mm.
    pub fn new(boxes: &NozzleBoxes, mm: f64) -> FitSamples {
        let layers = boxes
            .iter()
            .map(|extent| match extent {
                Some(e) => fit::fit_layers(e.first_layer, e.last_layer)
                    .into_iter()
                    .map(|layer| (layer, Vec::new()))
                    .collect(),
                None => Vec::new(),
            })
            .collect();
        FitSamples {
            layers,
            spacing: fit::spacing(mm),
            mm,
        }
    }

    /// Samples `segment` of object `id` when it is on one of the object's fitted layers.
    pub fn add(&mut self, id: usize, segment: &Segment) {
        let Some(layers) = self.layers.get_mut(id) else {
            return;
        };
        if let Some((_, samples)) = layers.iter_mut().find(|(l, _)| *l == segment.layer) {
            let a = Point3::from(segment.start.coords * self.mm);
            let b = Point3::from(segment.end.coords * self.mm);
            fit::sample(&a, &b, self.spacing, samples);
        }
    }
}

/// A component's printed object, found: how its extrusions map back, and what they add up to.
#[derive(Debug, Clone)]
pub(super) struct Placed {
    /// What is reported (the volume, mass and centroid once every extrusion is counted).
    pub summary: SlicedComponent,
    shift: Vector3<f64>,
    to_rest: Isometry3<f64>,
    /// Filament of the extrusions counted so far, mm.
    filament: f64,
    /// Their first moment in the rest frame, mm × project units.
    moment: Vector3<f64>,
}

/// Every component's printed object in `outline` (with its nozzle `boxes`), placed; the
/// extrusions are counted by [`Placement::count`], then [`Placement::finish`].
pub(super) struct Placement {
    /// One per component, in project order.
    pub placed: Vec<Placed>,
    /// Per object id, the components it is (usually none or one).
    components_of: Vec<Vec<usize>>,
    /// Per component, its capsules (indices into the design).
    capsules_of: Vec<Vec<usize>>,
    mm: f64,
}

/// Every component's printed object in `outline`, matched and placed on the bed.
pub(super) fn place(
    compilation: &Compilation,
    plan: &PrintPlan,
    outline: &Outline,
    boxes: &NozzleBoxes,
    samples: FitSamples,
) -> Result<Placement, SlicedError> {
    let mut samples = samples.layers;
    let project = &compilation.project;
    let objects = match_objects(compilation, outline)?;
    let mm = project.units.from_millimetres(1.0);
    let print = &project.print;
    let width = print.extrusion_width;
    let tolerance = 2.0 * width + print.layer_height;
    let mut placed = Vec::with_capacity(objects.len());
    let mut components_of = vec![Vec::new(); outline.objects.len()];
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
        let origin = Point3::origin();
        let (low, high) = boxes
            .get(object.id)
            .copied()
            .flatten()
            .map_or((origin, origin), |e| (e.low, e.high));
        // The fit starts from the offset between the two boxes' centres.
        let start = Vector2::new(
            (low.x + high.x - planned_low.x - planned_high.x) / 2.0,
            (low.y + high.y - planned_low.y - planned_high.y) / 2.0,
        );
        let mesh = &compilation.meshes[index];
        let layers: Vec<FitLayer> = samples
            .get_mut(object.id)
            .map(std::mem::take)
            .unwrap_or_default()
            .into_iter()
            .map(|(layer, samples)| {
                let z = (outline.layers[layer] - outline.layer_thickness(layer) / 2.0) * mm;
                FitLayer {
                    outline: Outline2::cut(&planned, &mesh.triangles, z, 2.0 * width),
                    samples,
                }
            })
            .collect();
        let found = fit::fit(&layers, start, width);
        let doubt = found.doubt(width).map(|why| {
            format!(
                "component `{name}`: its place on the bed is not found from the file ({why}): \
                 the plan's place is assumed"
            )
        });
        let shift = if doubt.is_none() {
            Vector3::new(found.shift[0], found.shift[1], 0.0)
        } else {
            Vector3::zeros()
        };
        let planned_size = planned_high - planned_low;
        let printed_size = Vector3::new(high.x - low.x, high.y - low.y, high.z);
        let off = |axis: usize| (planned_size[axis] - printed_size[axis]).abs() > tolerance;
        // Without object labels every extrusion is the object's: a skirt, brim or purge line
        // widens it on the bed but leaves its height.
        let widened_by_more = object.label.is_none()
            && !off(2)
            && (0..2).all(|axis| printed_size[axis] + tolerance >= planned_size[axis]);
        let mismatch = (0..3).any(off).then(|| {
            let why = if widened_by_more {
                "the file labels no object, so a skirt, brim or purge line counts as the part: \
                 slice with object labels on (PrusaSlicer's `--gcode-label-objects`) or without a \
                 skirt or brim"
            } else {
                "not the planned part in its planned orientation"
            };
            format!(
                "component `{name}`: the printed object measures {:.2} × {:.2} × {:.2}, the \
                 planned part {:.2} × {:.2} × {:.2}: {why}",
                printed_size.x,
                printed_size.y,
                printed_size.z,
                planned_size.x,
                planned_size.y,
                planned_size.z
            )
        });
        if let Some(components) = components_of.get_mut(object.id) {
            components.push(index);
        }
        placed.push(Placed {
            summary: SlicedComponent {
                component: name,
                object: object.label.clone(),
                shift: [shift.x, shift.y],
                fit: found,
                doubt,
                planned_size: planned_size.into(),
                printed_size: printed_size.into(),
                mismatch,
                segments: object.segments,
                volume: 0.0,
                mass: 0.0,
                centroid: [0.0; 3],
            },
            shift,
            to_rest: component.to_bed.inverse(),
            // The start of a sum of `f64`s, so the total is bit for bit that of summing a list.
            filament: std::iter::empty::<f64>().sum(),
            moment: Vector3::zeros(),
        });
    }
    let mut capsules_of = vec![Vec::new(); placed.len()];
    for (index, capsule) in compilation.design.capsules.iter().enumerate() {
        if let Some(capsules) = capsules_of.get_mut(capsule.component) {
            capsules.push(index);
        }
    }
    Ok(Placement {
        placed,
        components_of,
        capsules_of,
        mm,
    })
}

impl Placement {
    /// Counts `segment` of object `id` (of a program whose layers `outline` has) in the deposit
    /// of each component it is, and checks it against that component's capsule voids
    /// (`voids`, as [`voids::start`] made them): the second pass over the file, in print order.
    pub fn count(
        &mut self,
        compilation: &Compilation,
        outline: &Outline,
        voids: &mut [VoidCheck],
        (id, segment): (usize, &Segment),
    ) {
        let Some(components) = self.components_of.get(id) else {
            return;
        };
        let mm = self.mm;
        // Material centre lines on the bed, project units.
        let lower = Vector3::new(0.0, 0.0, outline.layer_thickness(segment.layer) / 2.0);
        let a = Point3::from((segment.start - lower).coords * mm);
        let b = Point3::from((segment.end - lower).coords * mm);
        for &index in components {
            let placed = &mut self.placed[index];
            let a = placed.to_rest * (a - placed.shift);
            let b = placed.to_rest * (b - placed.shift);
            placed.filament += segment.filament;
            placed.moment += (a.coords + b.coords) * (segment.filament / 2.0);
            voids::visit(
                compilation,
                voids,
                &self.capsules_of[index],
                (&a, &b, segment.line),
            );
        }
    }

    /// Each component as the file prints it, with filament of `filament_diameter` mm.
    pub fn finish(self, compilation: &Compilation, filament_diameter: f64) -> Vec<SlicedComponent> {
        let project = &compilation.project;
        // Filament fed (mm) times its cross-section (mm²) is mm³: cubic project units at `mm³`.
        let area = filament_area(filament_diameter) * self.mm.powi(3);
        let density = project.material.density * project.units.cubic_in_cm3();
        self.placed
            .into_iter()
            .enumerate()
            .map(|(index, placed)| {
                let centroid = if placed.filament > 0.0 {
                    Point3::from(placed.moment / placed.filament)
                } else {
                    compilation.mass[index].centroid
                };
                let volume = placed.filament * area;
                SlicedComponent {
                    volume,
                    mass: volume * density,
                    centroid: centroid.into(),
                    ..placed.summary
                }
            })
            .collect()
    }
}

/// The most objects an error names.
const MAX_NAMED_OBJECTS: usize = 10;

/// The printed object of each component, in project order.
fn match_objects<'a>(
    compilation: &Compilation,
    outline: &'a Outline,
) -> Result<Vec<&'a ObjectOutline>, SlicedError> {
    let project = &compilation.project;
    let count = project.components.len();
    let labelled: Vec<&ObjectOutline> = outline
        .objects
        .iter()
        .filter(|o| o.label.is_some())
        .collect();
    if labelled.is_empty() {
        return match outline.objects.first() {
            Some(object) if count == 1 => Ok(vec![object]),
            _ => Err(SlicedError::Unmatched(format!(
                "the G-code labels no objects and the project has {count} components: slice \
                 with object labels on (PrusaSlicer: `--gcode-label-objects`)"
            ))),
        };
    }
    let by_name: Option<Vec<&ObjectOutline>> = (0..count)
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
    let mut names: Vec<String> = labelled
        .iter()
        .take(MAX_NAMED_OBJECTS)
        .filter_map(|o| o.label.as_deref())
        .map(|label| format!("`{label}`"))
        .collect();
    if labelled.len() > MAX_NAMED_OBJECTS {
        names.push(format!("{} more", labelled.len() - MAX_NAMED_OBJECTS));
    }
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
