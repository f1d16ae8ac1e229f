//! ballast: compile a project file into 3D-printable objects that balance with movable masses.
//!
//! The crate is a compiler pipeline; each stage is a module with one job and a typed output.
//! The stages present so far:
//!
//! - [`spec`]: the front end: [`spec::parse_project`] reads a project file into a typed
//!   [`spec::model::Project`] and reports every problem in it, driven by the grammar table
//!   [`spec::vocabulary`].
//! - [`geometry`]: meshes loaded, validated, their mass properties and distance queries.
//! - [`balance`]: the physics of one pose: centre of mass, ball positions, support, goals.
//! - [`fabrication`]: whether the capsules of a design can be printed where they are.
//! - [`objective`]: the smooth objective and constraints, with exact gradients, an optimizer
//!   descends.
//! - [`emit`]: glTF scenes (one per pose) and atomic file writes.
//! - [`gcode`]: what a slicer's G-code deposits, object by object and layer by layer, and where
//!   it pauses.
//! - [`cancel`]: a flag another thread sets to stop a long build early.
//! - [`regular_file`]: every input file opened as a regular file only, read within a limit.
//! - [`verify`]: every goal re-measured by a rigid-body simulation, independent of [`balance`].
//! - [`sliced`]: a sliced G-code file checked against the design: the goals with its mass, its
//!   pauses, its voids.
//! - [`pauses`]: the print plan's pauses put into a sliced G-code file, at the layers of their
//!   heights.
//! - [`watch`]: watch mode's loop: rebuild once per burst of changes to a project's files.
//!
//! `docs/architecture.md` describes the whole pipeline, including the stages still to come.
//! The `ballast` binary will only parse arguments and print; the pipeline lives here.

pub mod balance;
pub mod cancel;
pub mod cli;
pub mod compile;
pub mod design;
pub mod diagnostic;
pub mod emit;
pub mod fabrication;
pub mod file_identity;
pub mod gcode;
pub mod geometry;
pub mod objective;
pub mod optimize;
mod parallel;
pub mod pauses;
pub mod random;
pub mod regular_file;
pub mod sliced;
pub mod spec;
pub mod verify;
pub mod watch;
