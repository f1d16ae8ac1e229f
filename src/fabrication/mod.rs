//! Fabrication: can the capsules of a design be printed where they are?
//!
//! [`check_design`] looks at every capsule of a [`Design`](crate::design::Design) against the
//! component meshes, all in the shared rest frame, and returns one [`CapsuleIssue`] per problem:
//!
//! - the axis is long enough to drop the ball in during the print pause (eq. 16 of the paper);
//! - the ball fits with the ball clearance left around it;
//! - the capsule, with a wall of material around it, lies inside the component it is assigned
//!   to (eq. 15 with the wall added), and if not, which component it is in instead;
//! - two capsules of one component keep a wall between them (eq. 14 with the wall added);
//! - the ball can be dropped in at a pause on the layer grid and lie below the printed height,
//!   the component printed as its [`PrintSetup`] says (eq. 16 in general, [`insertion_window`]).
//!
//! [`PrintPlan`] is how the design is printed: each component's orientation on the bed
//! ([`choose`] or a declared one, `orientation.rs`; laid out by [`lay_out`], `bed.rs`), the pauses
//! and the balls that go in at each, and the pauses of the whole bed
//! ([`PrintPlan::plate_pauses`]);
//! [`plan_insertions`] fills in a component's windows and pauses in its [`PrintFrame`]: the
//! heights at which each ball can go in (eq. 16 in general, [`insertion_window`]), grouped into
//! the fewest pauses on the layer grid.
//!
//! Issues are plain data without spans or messages: the driver knows which project node each
//! capsule came from and turns an issue into a diagnostic there. Whether a ball clearly rolls to
//! one end (eq. 22) depends on the pose and is left to the physics stage.

mod bed;
mod check;
mod frame;
mod insertion;
mod issue;
mod orientation;
mod overlap;
mod placement;
mod plan;
mod tolerance;

pub use bed::{lay_out, Bed};
pub use check::check_design;
pub use frame::{LayerGrid, PrintFrame, PrintSetup};
pub use insertion::{ceiling_bridge, has_window, insertion_window, plan_insertions, required_rise};
pub use issue::CapsuleIssue;
pub use orientation::{
    choose, declared_down, declared_rotation, height, InsertionHook, InsertionRank, Orientation,
    AREA_TIE,
};
pub use plan::{CapsuleInsertion, ComponentPlan, OrientationChoice, Pause, PlatePause, PrintPlan};
