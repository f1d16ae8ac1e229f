//! The print plan: how each component lies on the bed, at which heights the print pauses, and
//! which balls go in at each pause. The back end writes it out (STL, slicer projects, the
//! insertion sheet); `verify --gcode` maps a sliced program back through it.
//!
//! Lengths are project units; heights are measured up from the bed.

use nalgebra::{Isometry3, Vector3};

/// How every component of a project is printed.
#[derive(Debug, Clone, PartialEq)]
pub struct PrintPlan {
    /// Height of the first layer (its top is the first layer boundary).
    pub first_layer_height: f64,
    /// Height of every later layer.
    pub layer_height: f64,
    /// One per component, in project order.
    pub components: Vec<ComponentPlan>,
}

/// How one component is printed.
#[derive(Debug, Clone, PartialEq)]
pub struct ComponentPlan {
    /// Index of the component in the project.
    pub component: usize,
    /// Rest frame to bed frame. The bed frame has +z up, the bed at z = 0 with the part's lowest
    /// point on it, and the part at its own place on the bed (parts side by side, not touching).
    pub to_bed: Isometry3<f64>,
    /// The rest-frame direction that points down onto the bed.
    pub down: Vector3<f64>,
    /// Why this orientation.
    pub orientation: OrientationChoice,
    /// One per capsule of this component, in design order.
    pub capsules: Vec<CapsuleInsertion>,
    /// The pauses, lowest first.
    pub pauses: Vec<Pause>,
}

/// Where a component's print orientation came from.
#[derive(Debug, Clone, PartialEq)]
pub enum OrientationChoice {
    /// The project file states it (the component's `print` block).
    Declared,
    /// ballast chose it: a flat facet of the component's hull on the bed, of this area
    /// (squared project units), for the reason given in plain words.
    Chosen {
        /// Area of the facet on the bed.
        area: f64,
        /// Why this facet, e.g. "the largest flat facet; every capsule insertable in 1 pause".
        reason: String,
    },
}

/// When one capsule's ball can go in.
#[derive(Debug, Clone, PartialEq)]
pub struct CapsuleInsertion {
    /// Index of the capsule in the design.
    pub capsule: usize,
    /// Heights above the bed at which the print may pause for this ball, `(low, high)`: paused
    /// there, the dropped ball rests wholly below the printed height and the opening is still
    /// wide enough for it to pass. `None` when no height works.
    pub window: Option<(f64, f64)>,
    /// Index into [`ComponentPlan::pauses`] of the pause this ball goes in at; `None` when the
    /// window holds no layer boundary.
    pub pause: Option<usize>,
    /// Widest span of the void's ceiling that the slicer must bridge (overhang past 45°).
    pub ceiling_bridge: f64,
}

/// One pause of the print.
#[derive(Debug, Clone, PartialEq)]
pub struct Pause {
    /// Layers finished before the pause (1 = only the first layer).
    pub layers_done: usize,
    /// Top of the last layer printed before the pause, above the bed.
    pub height: f64,
    /// Top of the first layer printed after the pause: the height slicers key a pause by
    /// (PrusaSlicer's `print_z`, OrcaSlicer's `top_z`).
    pub resume_height: f64,
    /// Indices of the capsules whose balls go in at this pause, in design order.
    pub capsules: Vec<usize>,
    /// What the printer shows, e.g. "Insert one 8 mm steel ball into capsule `keel`".
    pub message: String,
}
