//! The design vector: the optimizer's unknowns as one flat `Vec<f64>`, and the way back to a
//! [`Design`].

use nalgebra::Point3;

use crate::design::{Design, PlacedCapsule};
use crate::spec::model::{Ball, Project};

/// Number of entries per capsule in the design vector.
pub const CAPSULE_STRIDE: usize = 7;
/// Offset of `p` (the `from` end, 3 entries) within a capsule's entries.
pub const P: usize = 0;
/// Offset of `q` (the `to` end, 3 entries) within a capsule's entries.
pub const Q: usize = 3;
/// Offset of the radius `r` within a capsule's entries.
pub const R: usize = 6;

/// How a design is laid out in the design vector `x`.
///
/// Capsule `j` occupies `x[7j .. 7j + 7]` = `[p.x, p.y, p.z, q.x, q.y, q.z, r]`: its axis ends
/// in the rest frame of its component and its void radius, in project units. When the project
/// gives an infill range, the infill fraction follows the capsules as the last entry. Each
/// capsule's component (σ(j) in the paper) and name are fixed and kept here, not in `x`.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignLayout {
    /// Per capsule, in design order: its name.
    pub names: Vec<String>,
    /// Per capsule, in design order: the index of its component.
    pub components: Vec<usize>,
    /// The infill range when the infill is a variable; `None` keeps the project's infill.
    pub infill_range: Option<(f64, f64)>,
}

impl DesignLayout {
    /// The layout for the capsules of `design` (names and components), with the infill a variable
    /// when `project` gives an infill range.
    pub fn for_design(project: &Project, design: &Design) -> DesignLayout {
        DesignLayout {
            names: design.capsules.iter().map(|c| c.name.clone()).collect(),
            components: design.capsules.iter().map(|c| c.component).collect(),
            infill_range: project.infill.range,
        }
    }

    /// Number of capsules.
    pub fn capsule_count(&self) -> usize {
        self.components.len()
    }

    /// Length of the design vector.
    pub fn len(&self) -> usize {
        self.capsule_count() * CAPSULE_STRIDE + usize::from(self.infill_range.is_some())
    }

    /// Whether the design vector is empty (no capsules, fixed infill).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Index of the infill fraction in `x`, when it is a variable.
    pub fn infill_index(&self) -> Option<usize> {
        self.infill_range
            .map(|_| self.capsule_count() * CAPSULE_STRIDE)
    }

    /// The design vector of `design`: its first [`capsule_count`](Self::capsule_count) capsules'
    /// ends and radii, then its infill when that is a variable. Capsules the design lacks are
    /// zeros.
    pub fn to_vector(&self, design: &Design) -> Vec<f64> {
        let mut x = vec![0.0; self.len()];
        for (j, capsule) in design
            .capsules
            .iter()
            .take(self.capsule_count())
            .enumerate()
        {
            let base = j * CAPSULE_STRIDE;
            x[base + P..base + P + 3].copy_from_slice(capsule.from.coords.as_slice());
            x[base + Q..base + Q + 3].copy_from_slice(capsule.to.coords.as_slice());
            x[base + R] = capsule.radius;
        }
        if let Some(i) = self.infill_index() {
            x[i] = design.infill;
        }
        x
    }

    /// The design that `x` describes. Each ball's radius is the capsule radius less the ball
    /// clearance (0 when the capsule is no wider than the clearance), as
    /// [`Ball::radius_for`] chooses without a list of diameters. The infill is `x`'s when it is a
    /// variable, `fixed_infill` otherwise. Entries missing from a short `x` count as 0.
    pub fn to_design(&self, x: &[f64], ball: &Ball, fixed_infill: f64) -> Design {
        let at = |i: usize| x.get(i).copied().unwrap_or(0.0);
        let point = |i: usize| Point3::new(at(i), at(i + 1), at(i + 2));
        let capsules = (0..self.capsule_count())
            .map(|j| {
                let base = j * CAPSULE_STRIDE;
                let radius = at(base + R);
                PlacedCapsule {
                    name: self.names.get(j).cloned().unwrap_or_default(),
                    component: self.components[j],
                    from: point(base + P),
                    to: point(base + Q),
                    radius,
                    ball_radius: (radius - ball.clearance).max(0.0),
                }
            })
            .collect();
        Design {
            capsules,
            infill: self.infill_index().map_or(fixed_infill, at),
        }
    }
}
