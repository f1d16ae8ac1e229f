//! Meshes and outcomes the optimizer's unit tests build from.

use nalgebra::Point3;

use super::Outcome;
use crate::design::{Design, PlacedCapsule};
use crate::geometry::TriMesh;

/// A closed cube of edge `side`, moved by `shift` along x, its triangles facing out.
pub(super) fn cube(side: f64, shift: f64) -> TriMesh {
    let p = |x: f64, y: f64, z: f64| Point3::new(x * side + shift, y * side, z * side);
    TriMesh {
        positions: vec![
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.0),
            p(1.0, 1.0, 0.0),
            p(0.0, 1.0, 0.0),
            p(0.0, 0.0, 1.0),
            p(1.0, 0.0, 1.0),
            p(1.0, 1.0, 1.0),
            p(0.0, 1.0, 1.0),
        ],
        triangles: vec![
            [0, 2, 1],
            [0, 3, 2],
            [4, 5, 6],
            [4, 6, 7],
            [0, 1, 5],
            [0, 5, 4],
            [1, 2, 6],
            [1, 6, 5],
            [2, 3, 7],
            [2, 7, 6],
            [3, 0, 4],
            [3, 4, 7],
        ],
    }
}

/// A feasible outcome of `capsules` (full infill) at objective `value`, meeting every goal or
/// not, with no poses evaluated.
pub(super) fn outcome(capsules: Vec<PlacedCapsule>, value: f64, meets_goals: bool) -> Outcome {
    Outcome {
        design: Design {
            capsules,
            infill: 1.0,
        },
        value,
        feasible: true,
        meets_goals,
        worst_tilt_margin: None,
        poses: Vec::new(),
        fabrication: Vec::new(),
        evaluations: 0,
    }
}
