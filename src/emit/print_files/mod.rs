//! The files a user prints from: one STL per part, slicer projects with the pauses, and the
//! insertion sheet.
//!
//! The input is plain data in bed coordinates (millimetres, +z up, the bed at z = 0): each
//! [`BedPart`] is a component as it lies on the bed, with its capsule voids and the pauses at
//! which its balls go in; the [`BedPlatePause`]s are the whole bed's pauses, every part's pauses
//! at one height merged as the print plan merges them. The voids are cut without a boolean: each
//! capsule's closed surface is added with reversed orientation as an inner shell of the part's
//! mesh ([`solid_mesh`]), which slicers read as a solid with a cavity as long as the capsule lies
//! strictly inside the part.

mod prusa;
mod sheet;
mod stl;
mod xml;
mod zip;

use nalgebra::Point3;

use super::number::number;
use super::shapes::{capsule, capsule_within};

pub use prusa::write_prusa_3mf;
pub use sheet::{file_name, write_sheet, Sheet};
pub use stl::write_stl;

/// A component as it lies on the bed.
#[derive(Clone, Debug, PartialEq)]
pub struct BedPart {
    /// The component's name: the slicer object's name, so a G-code's `; printing object NAME`
    /// labels map back to it.
    pub name: String,
    /// The outer surface in bed coordinates (mm), closed, counter-clockwise seen from outside.
    pub surface: BedMesh,
    /// The capsule voids, in design order.
    pub voids: Vec<BedVoid>,
    /// The pauses, lowest first.
    pub pauses: Vec<BedPause>,
    /// How the part lies on the bed, in plain words for the insertion sheet (e.g. "rest-frame
    /// -z down, declared").
    pub orientation: String,
}

/// An indexed triangle mesh.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct BedMesh {
    /// Vertex positions, mm.
    pub positions: Vec<Point3<f64>>,
    /// Triangles indexing `positions`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// One capsule-shaped void and its ball, bed coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct BedVoid {
    /// The capsule's name.
    pub name: String,
    /// One end of the axis, mm.
    pub from: Point3<f64>,
    /// The other end of the axis, mm.
    pub to: Point3<f64>,
    /// Radius of the void, mm.
    pub radius: f64,
    /// Diameter of the steel ball that goes in, mm.
    pub ball_diameter: f64,
}

impl BedVoid {
    /// Where the centre of the dropped ball comes to rest: the lowest point of the lower end's
    /// hemisphere, the ball touching it from inside.
    pub fn ball_rest(&self) -> Point3<f64> {
        let lower = if self.from.z <= self.to.z {
            self.from
        } else {
            self.to
        };
        lower - nalgebra::Vector3::z() * (self.radius - self.ball_diameter / 2.0)
    }
}

/// One pause of a part's print.
#[derive(Clone, Debug, PartialEq)]
pub struct BedPause {
    /// Layers finished before the pause (1 = only the first layer).
    pub layers_done: usize,
    /// Top of the last layer printed before the pause, mm.
    pub height: f64,
    /// Top of the first layer printed after the pause, mm: the height slicers key a pause by.
    pub resume_height: f64,
    /// Indices into [`BedPart::voids`] of the capsules whose balls go in.
    pub voids: Vec<usize>,
    /// What the printer shows.
    pub message: String,
}

/// One pause of the whole bed: every part's pause at the same height, merged.
#[derive(Clone, Debug, PartialEq)]
pub struct BedPlatePause {
    /// Top of the first layer printed after the pause, mm: the height slicers key a pause by.
    pub resume_height: f64,
    /// What the printer shows: each pausing part's message, named on a bed of several parts.
    pub message: String,
}

/// The print settings the mass model assumes, written into the slicer projects.
#[derive(Clone, Debug, PartialEq)]
pub struct PrintSettings {
    /// Height of every layer after the first, mm.
    pub layer_height: f64,
    /// Height of the first layer, mm.
    pub first_layer_height: f64,
    /// Perimeter loops.
    pub perimeters: u64,
    /// Solid layers under a top surface.
    pub top_solid_layers: u64,
    /// Solid layers over a bottom surface.
    pub bottom_solid_layers: u64,
    /// Infill density, a fraction in (0, 1].
    pub infill: f64,
    /// Extrusion width, mm.
    pub extrusion_width: f64,
    /// Interior regions smaller than this (mm²) are filled solid.
    pub solid_infill_below_area: f64,
    /// Size of the bed in x and y, mm, its origin at a corner.
    pub bed: [f64; 2],
}

/// The G-code a pause runs (Marlin and Prusa firmware: pause and wait for the user).
pub const PAUSE_GCODE: &str = "M601";

/// How far inside the true capsule a void's printed surface may lie, mm. The mass model weighs
/// the true capsule; a void tessellated as coarsely as the glTF draws one (32 segments) holds
/// 0.8 % less volume, which prints as plastic the model does not count, and its faces' centres
/// lie 1 % of its radius inside (0.11 mm in the sheared cylinder's, a third of the ball's
/// clearance). A hundredth of a millimetre is below what a slicer resolves (PrusaSlicer
/// simplifies its paths to 0.0125 mm).
pub const VOID_INSET: f64 = 0.01;

/// The part's printable solid: the outer surface followed by each void as a reversed
/// (inward-facing) closed capsule shell, within [`VOID_INSET`] of the true capsule. Closed
/// and consistently oriented when the surface is.
pub fn solid_mesh(part: &BedPart) -> BedMesh {
    let mut mesh = part.surface.clone();
    for void in &part.voids {
        let shell = capsule_within(&void.from, &void.to, void.radius, VOID_INSET);
        let base = u32::try_from(mesh.positions.len()).expect("mesh fits u32 indices");
        mesh.positions.extend(shell.positions);
        mesh.triangles.extend(
            shell
                .triangles
                .iter()
                .map(|&[a, b, c]| [base + a, base + c, base + b]),
        );
    }
    mesh
}

/// How far a support blocker reaches past its void, mm. A slicer blocks support of an overhang
/// only where the blocker's slice covers it, and the overhang of a void's ceiling at a layer is
/// the ring between the void's sections at that layer and the one below: outside the void's
/// own section. A margin of a few layers covers it.
pub const BLOCKER_MARGIN: f64 = 1.0;

/// The support blocker of `void`: its capsule grown by [`BLOCKER_MARGIN`], outward.
fn blocker_mesh(void: &BedVoid) -> BedMesh {
    let shell = capsule(&void.from, &void.to, void.radius + BLOCKER_MARGIN);
    BedMesh {
        positions: shell.positions,
        triangles: shell.triangles,
    }
}

#[cfg(test)]
pub(crate) mod test_parts;
