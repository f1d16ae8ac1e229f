//! The print plan: how each component lies on the bed, at which heights the print pauses, and
//! which balls go in at each pause. The back end writes it out (STL, slicer projects, the
//! insertion sheet); `verify --gcode` maps a sliced program back through it.
//!
//! The whole bed pauses at once: [`PrintPlan::plate_pauses`] merges the components' pauses after
//! one layer into one [`PlatePause`] with the message the printer shows: the pauses of the
//! PrusaSlicer project and those `ballast pauses` puts into a sliced file.
//!
//! Lengths are project units; heights are measured up from the bed.

use std::collections::BTreeMap;

use nalgebra::{Isometry3, Vector3};
use serde::Serialize;

/// How every component of a project is printed.
#[derive(Debug, Clone, PartialEq)]
pub struct PrintPlan {
    /// Height of the first layer (its top is the first layer boundary).
    pub first_layer_height: f64,
    /// Height of every later layer.
    pub layer_height: f64,
    /// Least gap between the top of a resting ball and the top of the paused layer.
    pub pause_clearance: f64,
    /// One per component, in project order.
    pub components: Vec<ComponentPlan>,
}

impl PrintPlan {
    /// The pauses of the whole bed, lowest first: every component's pause after the same layer
    /// merged into one, its message each pausing component's in project order, joined by ` / `
    /// (not `;`, which would start a comment in the `M117` line the printer shows it with: the
    /// printer, and `verify --gcode`, would see the first component's message alone). On a bed
    /// of several components each message starts with its component's name, `names` holding
    /// them by component index.
    ///
    /// Pauses are merged by the layers printed before them, so heights that differ by float
    /// noise alone are one pause; a merged pause's heights are its first component's.
    pub fn plate_pauses(&self, names: &[&str]) -> Vec<PlatePause> {
        let several = self.components.len() > 1;
        let mut by_layer: BTreeMap<usize, PlatePause> = BTreeMap::new();
        for component in &self.components {
            for pause in &component.pauses {
                let message = match names.get(component.component) {
                    Some(name) if several => format!("{name}: {}", pause.message),
                    _ => pause.message.clone(),
                };
                by_layer
                    .entry(pause.layers_done)
                    .and_modify(|merged| {
                        merged.message.push_str(" / ");
                        merged.message.push_str(&message);
                    })
                    .or_insert_with(|| PlatePause {
                        layers_done: pause.layers_done,
                        height: pause.height,
                        resume_height: pause.resume_height,
                        message,
                    });
            }
        }
        by_layer.into_values().collect()
    }
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
    /// The rest-frame direction the layers stack along: the print frame's +z, from the
    /// orientation's rotation (`to_bed`'s went through a quaternion), so the plan's insertion
    /// windows are measured along the very direction the optimizer's checks use.
    pub up: Vector3<f64>,
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

/// One pause of the whole bed: every component's planned pause after the same layer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlatePause {
    /// Layers printed before it, as the plan counts them.
    pub layers_done: usize,
    /// Top of the last layer printed before it, above the bed.
    pub height: f64,
    /// Top of the first layer printed after it, above the bed: the height slicers key a pause
    /// by.
    pub resume_height: f64,
    /// What the printer shows: the planned message, or on a bed of several components each
    /// pausing component's name and message, joined by ` / `.
    pub message: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Component `index`, declared upright, pausing after each of `pauses`' layer counts with
    /// its message, on a grid of 0.035 then 0.03 (centimetres).
    fn component(index: usize, pauses: &[(usize, &str)]) -> ComponentPlan {
        ComponentPlan {
            component: index,
            to_bed: Isometry3::identity(),
            down: -Vector3::z(),
            up: Vector3::z(),
            orientation: OrientationChoice::Declared,
            capsules: Vec::new(),
            pauses: pauses
                .iter()
                .map(|&(layers_done, message)| Pause {
                    layers_done,
                    height: 0.035 + 0.03 * (layers_done - 1) as f64,
                    resume_height: 0.035 + 0.03 * layers_done as f64,
                    capsules: vec![0],
                    message: message.to_string(),
                })
                .collect(),
        }
    }

    fn plan(components: Vec<ComponentPlan>) -> PrintPlan {
        PrintPlan {
            first_layer_height: 0.035,
            layer_height: 0.03,
            pause_clearance: 0.02,
            components,
        }
    }

    #[test]
    fn the_plans_pauses_after_one_layer_are_one_pause_of_the_bed() {
        let two = plan(vec![
            component(0, &[(46, "Insert a"), (50, "Insert b")]),
            component(1, &[(46, "Insert c")]),
        ]);
        let pauses = two.plate_pauses(&["left", "right"]);
        let summary: Vec<(usize, &str)> = pauses
            .iter()
            .map(|p| (p.layers_done, p.message.as_str()))
            .collect();
        assert_eq!(
            summary,
            [
                (46, "left: Insert a / right: Insert c"),
                (50, "left: Insert b")
            ]
        );
        assert!((pauses[0].height - 1.385).abs() < 1e-12);
        assert!((pauses[0].resume_height - 1.415).abs() < 1e-12);
        assert!((pauses[1].resume_height - 1.535).abs() < 1e-12);
        // A bed of one component shows its messages alone.
        let one = plan(vec![component(0, &[(46, "Insert a"), (50, "Insert b")])]);
        let messages: Vec<String> = one
            .plate_pauses(&["left"])
            .into_iter()
            .map(|p| p.message)
            .collect();
        assert_eq!(messages, ["Insert a", "Insert b"]);
    }

    #[test]
    fn pauses_after_one_layer_merge_whatever_the_float_noise_in_their_heights() {
        let mut noisy = component(1, &[(46, "Insert c")]);
        noisy.pauses[0].height += 1e-9;
        noisy.pauses[0].resume_height += 1e-9;
        let two = plan(vec![component(0, &[(46, "Insert a")]), noisy]);
        let pauses = two.plate_pauses(&["left", "right"]);
        assert_eq!(pauses.len(), 1);
        assert_eq!(pauses[0].message, "left: Insert a / right: Insert c");
        // The heights are the first component's.
        assert_eq!(
            pauses[0].resume_height,
            two.components[0].pauses[0].resume_height
        );
    }
}
