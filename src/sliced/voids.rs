//! No plastic inside a void: an extrusion lands in a capsule's void when its material centre
//! line, in the component's rest frame, passes closer to the capsule's axis than the capsule's
//! radius less [`VOID_TOLERANCE`] of the extrusion width.

use nalgebra::Point3;
use serde::Serialize;

use crate::compile::Compilation;
use crate::geometry::segment_segment_distance;

/// How far a bead's centre line may run inside a capsule's void, as a fraction of the extrusion
/// width: a quarter (0.11 mm at 0.45 mm). A slicer that keeps the void empty runs its innermost
/// perimeter's centre line on the void's surface (PrusaSlicer: within 0.02 mm of it); the
/// tolerance allows for that, for the void's facets lying inside the true surface (by
/// `r(1 − cos(π/32))`, 0.04 mm at `r` = 8.5 mm) and for the slicer's path simplification, while
/// a bead further in (more than three quarters of its width in the void) is caught.
pub const VOID_TOLERANCE: f64 = 0.25;

/// One capsule's void in the sliced file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VoidCheck {
    /// The capsule's name.
    pub capsule: String,
    /// Extrusion moves closer to the axis than `limit`.
    pub intrusions: usize,
    /// The smallest distance of any extrusion of the capsule's component from its axis, project
    /// units; `None` when the component extrudes nothing.
    pub closest: Option<f64>,
    /// The distance below which an extrusion is inside: radius less [`VOID_TOLERANCE`] of the
    /// extrusion width.
    pub limit: f64,
    /// Line of the first extrusion inside, when there is one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub first_line: Option<usize>,
}

impl VoidCheck {
    /// The failure in words, when something is inside.
    pub fn problem(&self) -> Option<String> {
        let line = self.first_line?;
        Some(format!(
            "capsule `{}`: {} extrusion{} inside the void (the first on line {line}), {:.2} from \
             the axis where the void's radius less {VOID_TOLERANCE} of an extrusion width is {:.2}",
            self.capsule,
            self.intrusions,
            if self.intrusions == 1 { "" } else { "s" },
            self.closest.unwrap_or(0.0),
            self.limit
        ))
    }
}

/// Every capsule of the design, nothing yet seen: one check per capsule, in design order, for
/// [`visit`] to fill in.
pub(super) fn start(compilation: &Compilation) -> Vec<VoidCheck> {
    let tolerance = VOID_TOLERANCE * compilation.project.print.extrusion_width;
    compilation
        .design
        .capsules
        .iter()
        .map(|capsule| VoidCheck {
            capsule: capsule.name.clone(),
            intrusions: 0,
            closest: None,
            limit: capsule.radius - tolerance,
            first_line: None,
        })
        .collect()
}

/// One extrusion of line `line`, its material centre line from `a` to `b` in the rest frame
/// of its component, against the capsules `capsules` (indices into the design) of that
/// component; `checks` are [`start`]'s. The extrusions of each component are visited in print
/// order.
pub(super) fn visit(
    compilation: &Compilation,
    checks: &mut [VoidCheck],
    capsules: &[usize],
    (a, b, line): (&Point3<f64>, &Point3<f64>, usize),
) {
    for &index in capsules {
        let capsule = &compilation.design.capsules[index];
        let check = &mut checks[index];
        let distance = segment_segment_distance(a, b, &capsule.from, &capsule.to);
        check.closest = Some(check.closest.map_or(distance, |c: f64| c.min(distance)));
        if distance < check.limit {
            check.intrusions += 1;
            check.first_line = check.first_line.or(Some(line));
        }
    }
}
