//! What can be wrong with a capsule, as plain data.

/// One fabrication problem with a capsule of a design.
///
/// Capsules are named by their index in [`Design::capsules`](crate::design::Design::capsules),
/// components by their index in the mesh slice given to
/// [`check_design`](super::check_design). Lengths are in the units of the meshes. The variants
/// are declared in the order [`check_design`](super::check_design) reports them for one capsule.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CapsuleIssue {
    /// The axis is shorter than the radius, `|to − from| < radius` (eq. 16): the printer cannot
    /// close the void over a ball dropped in during the pause.
    TooShort {
        /// The capsule.
        capsule: usize,
        /// `|to − from|`.
        length: f64,
        /// The capsule's radius, the least length allowed.
        radius: f64,
    },
    /// The ball does not fit: its radius is not positive, or it leaves less than the ball
    /// clearance between itself and the capsule's wall.
    BallDoesNotFit {
        /// The capsule.
        capsule: usize,
        /// The ball's radius.
        ball_radius: f64,
        /// The largest radius that fits, `radius − clearance` (not positive when no ball fits).
        max: f64,
    },
    /// The capsule names a component that is not in the mesh slice.
    UnknownComponent {
        /// The capsule.
        capsule: usize,
        /// The component index it names.
        component: usize,
    },
    /// The middle of the axis is outside every component.
    Outside {
        /// The capsule.
        capsule: usize,
        /// The component it is assigned to.
        component: usize,
    },
    /// The middle of the axis is outside the assigned component but inside another one: the
    /// capsule is probably assigned to the wrong component.
    InOtherComponent {
        /// The capsule.
        capsule: usize,
        /// The component it is assigned to.
        assigned: usize,
        /// The component the middle of its axis is in (of several, the one whose surface is
        /// farthest from the axis).
        actual: usize,
    },
    /// The middle of the axis is inside the assigned component, but the axis comes closer to the
    /// surface than the radius plus the wall (eq. 15), or crosses it: the capsule breaks through
    /// the surface or leaves too thin a wall.
    TooCloseToSurface {
        /// The capsule.
        capsule: usize,
        /// The component it is assigned to.
        component: usize,
        /// Least distance from the axis to the component's surface (0 when the axis crosses it).
        distance: f64,
        /// The least distance allowed, `radius + wall`.
        required: f64,
    },
    /// The capsule is inside its component, but no layer boundary lies in its insertion window
    /// with the component printed as planned (the general eq. 16,
    /// [`insertion_window`](super::insertion_window)): at no pause can the ball be dropped in and
    /// lie below the printed height.
    NoInsertionWindow {
        /// The capsule.
        capsule: usize,
        /// How far the axis rises along the print direction.
        rise: f64,
        /// How far it must rise, its lower end kept, for the window to hold a layer boundary.
        required: f64,
    },
    /// Two capsules of the same component come closer than their radii plus the wall (eq. 14).
    Overlap {
        /// The capsule with the lower index.
        first: usize,
        /// The capsule with the higher index.
        second: usize,
        /// Least distance between the two axes.
        distance: f64,
        /// The least distance allowed, `radius₁ + radius₂ + wall`.
        required: f64,
    },
}

impl CapsuleIssue {
    /// The capsule the issue is reported on: the lower index of an [`Overlap`](Self::Overlap),
    /// the only capsule otherwise.
    pub fn capsule(&self) -> usize {
        match *self {
            CapsuleIssue::TooShort { capsule, .. }
            | CapsuleIssue::BallDoesNotFit { capsule, .. }
            | CapsuleIssue::UnknownComponent { capsule, .. }
            | CapsuleIssue::Outside { capsule, .. }
            | CapsuleIssue::InOtherComponent { capsule, .. }
            | CapsuleIssue::TooCloseToSurface { capsule, .. }
            | CapsuleIssue::NoInsertionWindow { capsule, .. } => capsule,
            CapsuleIssue::Overlap { first, .. } => first,
        }
    }

    /// The same issue with every capsule index `i` replaced by `index(i)` (for issues found on a
    /// selection of a design's capsules).
    pub fn renumbered(self, index: impl Fn(usize) -> usize) -> CapsuleIssue {
        let mut issue = self;
        match &mut issue {
            CapsuleIssue::TooShort { capsule, .. }
            | CapsuleIssue::BallDoesNotFit { capsule, .. }
            | CapsuleIssue::UnknownComponent { capsule, .. }
            | CapsuleIssue::Outside { capsule, .. }
            | CapsuleIssue::InOtherComponent { capsule, .. }
            | CapsuleIssue::TooCloseToSurface { capsule, .. }
            | CapsuleIssue::NoInsertionWindow { capsule, .. } => *capsule = index(*capsule),
            CapsuleIssue::Overlap { first, second, .. } => {
                *first = index(*first);
                *second = index(*second);
            }
        }
        issue
    }
}
