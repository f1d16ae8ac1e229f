//! ballast: compile a project file into 3D-printable objects that balance with movable masses.
//!
//! The crate is a compiler pipeline; each stage is a module with one job and a typed output:
//!
//! 1. [`spec`]: KDL text to a typed, span-carrying [`spec::Project`], with every diagnostic at once.
//! 2. [`geometry`]: meshes loaded, validated, and their mass properties.
//! 3. [`balance`]: per-pose physics: centre of mass, support polygon, goal values.
//! 4. [`fabrication`]: capsule checks (inside the assigned component, no overlaps, printable).
//! 5. [`emit`]: glTF, JSON report, atomic file writes.
//!
//! [`compile`] wires the stages together; the `ballast` binary only parses arguments and prints.

pub mod balance;
pub mod compile;
pub mod emit;
pub mod fabrication;
pub mod geometry;
pub mod spec;
