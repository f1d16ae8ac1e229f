//! The print direction of each component and the layer grid: what the insertion windows are
//! measured against.

use nalgebra::{Point3, Rotation3, Vector3};

use super::PrintPlan;
use crate::geometry::TriMesh;

/// Slack, in layers, when a height is compared with a layer boundary: a window that ends a
/// rounding error short of a boundary still holds it.
const GRID_SLACK: f64 = 1e-9;

/// How one component lies for printing: the direction that points up from the bed, in the
/// component's rest frame, and the bed's height along it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrintFrame {
    /// Unit vector, rest frame, pointing away from the bed.
    pub up: Vector3<f64>,
    /// `up · v` of the component's lowest vertex `v`: where the bed is.
    pub bed: f64,
}

impl PrintFrame {
    /// The frame of `mesh` printed along `up` (normalised here; a zero vector stays zero), the
    /// bed at the mesh's lowest vertex along it (0 for an empty mesh).
    pub fn new(mesh: &TriMesh, up: Vector3<f64>) -> PrintFrame {
        let up = up.try_normalize(0.0).unwrap_or_else(Vector3::zeros);
        let bed = mesh
            .positions
            .iter()
            .map(|v| up.dot(&v.coords))
            .reduce(f64::min)
            .unwrap_or(0.0);
        PrintFrame { up, bed }
    }

    /// Height above the bed of the rest-frame point `point`.
    pub fn height(&self, point: &Point3<f64>) -> f64 {
        self.up.dot(&point.coords) - self.bed
    }
}

/// The heights at which layers end: `first_layer_height + k × layer_height`, `k ≥ 0`; and how
/// far below the top of the last layer before a pause a dropped ball must come to rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LayerGrid {
    /// Height of the first layer.
    pub first_layer_height: f64,
    /// Height of every later layer (positive).
    pub layer_height: f64,
    /// Least gap between the top of a resting ball and the top of the paused layer (the ball's
    /// `pause-clearance`).
    pub pause_clearance: f64,
}

impl LayerGrid {
    /// Top of the layer that leaves `layers_done` layers printed (`layers_done ≥ 1`).
    pub fn boundary(&self, layers_done: usize) -> f64 {
        self.first_layer_height + layers_done.saturating_sub(1) as f64 * self.layer_height
    }

    /// The layer counts whose boundaries lie in `[low, high]`, as an inclusive range
    /// `(first, last)` of `layers_done`; `None` when no boundary does.
    pub fn boundaries_in(&self, low: f64, high: f64) -> Option<(usize, usize)> {
        let step = |height: f64| (height - self.first_layer_height) / self.layer_height;
        let first = step(low) - GRID_SLACK;
        let last = step(high) + GRID_SLACK;
        if !(first.is_finite() && last.is_finite() && self.layer_height > 0.0) {
            return None;
        }
        let first = first.ceil().max(0.0);
        let last = last.floor();
        (last >= first).then(|| (first as usize + 1, last as usize + 1))
    }

    /// The lowest boundary at or above `height` (the first layer's when `height` is below it).
    pub fn boundary_from(&self, height: f64) -> f64 {
        let step = ((height - self.first_layer_height) / self.layer_height - GRID_SLACK).ceil();
        self.first_layer_height + step.max(0.0) * self.layer_height
    }
}

/// How a project's components are printed: each one's up direction (rest frame) and the layer
/// grid.
#[derive(Debug, Clone, PartialEq)]
pub struct PrintSetup {
    /// Per component, the unit rest-frame direction pointing away from the bed.
    pub up: Vec<Vector3<f64>>,
    /// Where layers end.
    pub grid: LayerGrid,
}

impl PrintSetup {
    /// How components are printed when each turns to its print frame (+z up) by its rotation in
    /// `to_print` (rest frame to print frame), on `grid`.
    pub fn from_rotations(to_print: &[Rotation3<f64>], grid: LayerGrid) -> PrintSetup {
        PrintSetup {
            up: to_print
                .iter()
                .map(|rotation| rotation.inverse() * Vector3::z())
                .collect(),
            grid,
        }
    }

    /// How the components of `plan` are printed: each along its `up`, on the plan's layers
    /// (the same bits as [`PrintSetup::from_rotations`] of the plan's orientations, which the
    /// optimizer's checks use).
    pub fn from_plan(plan: &PrintPlan) -> PrintSetup {
        PrintSetup {
            up: plan
                .components
                .iter()
                .map(|component| component.up)
                .collect(),
            grid: LayerGrid {
                first_layer_height: plan.first_layer_height,
                layer_height: plan.layer_height,
                pause_clearance: plan.pause_clearance,
            },
        }
    }

    /// The frame component `component` (mesh `mesh`) is printed in; `+z` for a component past
    /// the list.
    pub fn frame(&self, component: usize, mesh: &TriMesh) -> PrintFrame {
        PrintFrame::new(
            mesh,
            self.up.get(component).copied().unwrap_or_else(Vector3::z),
        )
    }
}
