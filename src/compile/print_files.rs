//! A design and its print plan as the back end's print-file input: each component on the bed in
//! millimetres with its capsule voids and pauses ([`bed_parts`]), the whole bed's pauses
//! ([`bed_plate_pauses`]), and the print settings of the project's mass model
//! ([`print_settings`]).

use nalgebra::Vector3;

use super::BED_CENTRE_MM;
use crate::design::Design;
use crate::emit::print_files::{BedMesh, BedPart, BedPause, BedPlatePause, BedVoid, PrintSettings};
use crate::fabrication::{OrientationChoice, PrintPlan};
use crate::geometry::TriMesh;
use crate::spec::model::Project;

/// Every component of `plan` on the bed, in millimetres: its mesh and the design's capsules in
/// it moved by the plan's `to_bed`, its pauses with the capsules renumbered within the
/// component.
pub fn bed_parts(
    project: &Project,
    meshes: &[TriMesh],
    design: &Design,
    plan: &PrintPlan,
) -> Vec<BedPart> {
    let mm = project.units.in_metres() * 1000.0;
    plan.components
        .iter()
        .map(|component| {
            let to_bed = &component.to_bed;
            let mesh = &meshes[component.component];
            let surface = BedMesh {
                positions: mesh.positions.iter().map(|p| (to_bed * p) * mm).collect(),
                triangles: mesh.triangles.clone(),
            };
            // The component's capsules in design order; a void's index is its place here.
            let capsules: Vec<usize> = (0..design.capsules.len())
                .filter(|&i| design.capsules[i].component == component.component)
                .collect();
            let voids = capsules
                .iter()
                .map(|&i| {
                    let capsule = &design.capsules[i];
                    BedVoid {
                        name: capsule.name.clone(),
                        from: (to_bed * capsule.from) * mm,
                        to: (to_bed * capsule.to) * mm,
                        radius: capsule.radius * mm,
                        ball_diameter: 2.0 * capsule.ball_radius * mm,
                    }
                })
                .collect();
            let pauses = component
                .pauses
                .iter()
                .map(|pause| BedPause {
                    layers_done: pause.layers_done,
                    height: pause.height * mm,
                    resume_height: pause.resume_height * mm,
                    voids: pause
                        .capsules
                        .iter()
                        .filter_map(|i| capsules.iter().position(|c| c == i))
                        .collect(),
                    message: pause.message.clone(),
                })
                .collect();
            BedPart {
                name: project.components[component.component].name.value.clone(),
                surface,
                voids,
                pauses,
                orientation: orientation(&component.orientation, &component.down, mm),
            }
        })
        .collect()
}

/// The pauses of the whole bed ([`PrintPlan::plate_pauses`], the components named as in the
/// project), resume heights in millimetres.
pub fn bed_plate_pauses(project: &Project, plan: &PrintPlan) -> Vec<BedPlatePause> {
    let mm = project.units.in_metres() * 1000.0;
    let names: Vec<&str> = (0..project.components.len())
        .map(|index| project.component_name(index))
        .collect();
    plan.plate_pauses(&names)
        .into_iter()
        .map(|pause| BedPlatePause {
            resume_height: pause.resume_height * mm,
            message: pause.message,
        })
        .collect()
}

/// The orientation in plain words: where it came from and which rest-frame direction is down;
/// `mm` millimetres to the project unit.
fn orientation(choice: &OrientationChoice, down: &Vector3<f64>, mm: f64) -> String {
    let down = format!("({:.3}, {:.3}, {:.3})", down.x, down.y, down.z);
    match choice {
        OrientationChoice::Declared => {
            format!("as the project file declares, rest-frame direction {down} down")
        }
        OrientationChoice::Chosen { area, reason } => format!(
            "chosen by ballast, rest-frame direction {down} down onto a facet of {:.1} mm²: \
             {reason}",
            area * mm * mm
        ),
    }
}

/// The print settings the mass model assumed, in millimetres, with the design's infill; the bed
/// the plan lays the parts out on.
pub fn print_settings(project: &Project, design: &Design) -> PrintSettings {
    let mm = project.units.in_metres() * 1000.0;
    let print = &project.print;
    PrintSettings {
        layer_height: print.layer_height * mm,
        first_layer_height: print.first_layer_height * mm,
        perimeters: print.perimeters,
        top_solid_layers: print.top_solid_layers,
        bottom_solid_layers: print.bottom_solid_layers,
        infill: design.infill,
        extrusion_width: print.extrusion_width * mm,
        solid_infill_below_area: print.solid_infill_below_area * mm * mm,
        bed: BED_CENTRE_MM.map(|centre| 2.0 * centre),
    }
}
