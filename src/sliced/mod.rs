//! The sliced file checked against the design: [`verify_gcode`] reads a G-code program sliced
//! from a project's print files and, through the [`PrintPlan`] the files were made from,
//!
//! - finds each component's printed object and the shift the slicer gave it on the bed, by
//!   fitting the outer perimeter of a few layers to the part's outline at those heights
//!   (`fit.rs`), and maps its extrusions back to the component's rest frame (`placement.rs`);
//! - re-evaluates every goal with each component's material replaced by what the file deposits
//!   (mass = extruded volume × the material's density, at the deposit's centroid), the capsule
//!   voids already empty in it and the balls at their ends as usual;
//! - checks that every planned pause is in the file right after the planned layer with its
//!   message, that the file has no other pause (`pauses.rs`), and that no extrusion lies inside a
//!   capsule void (`voids.rs`).
//!
//! `docs/fabrication.md` ("Checking the sliced file") says what is checked and how.

mod fit;
mod pauses;
mod placement;
mod voids;

use serde::Serialize;
use thiserror::Error;

pub use fit::{PlacementFit, MAX_FIT_RESIDUAL, MIN_FIT_COVERAGE, MIN_FIT_LAYERS, MIN_FIT_SPREAD};
pub use pauses::{FoundPause, PauseCheck, PlannedPause};
pub use placement::SlicedComponent;
use placement::{FitSamples, NozzleBoxes};
pub use voids::{VoidCheck, VOID_TOLERANCE};

use crate::balance::{
    component_material, evaluate_pose, ComponentBody, GoalOutcome, PoseEvaluation,
};
use crate::compile::Compilation;
use crate::fabrication::PrintPlan;
use crate::gcode::{scan_program, GcodeError, ReadOptions};
use crate::geometry::{PrintCorrection, Region};

/// The largest G-code file `ballast verify --gcode` reads, bytes (1 GiB): the file is read
/// whole, and its size is checked before it is.
pub const MAX_GCODE_BYTES: u64 = 1 << 30;

/// The filament diameters ballast reads a sliced file with, mm: 0.5 to 5 (printers feed 1.75,
/// 2.85 or 3).
pub const FILAMENT_DIAMETER_MM: std::ops::RangeInclusive<f64> = 0.5..=5.0;

/// How to read the sliced file.
#[derive(Debug, Clone, PartialEq)]
pub struct SlicedOptions {
    /// Diameter of the filament, mm (1.75 unless told), within [`FILAMENT_DIAMETER_MM`].
    pub filament_diameter: f64,
    /// The command the slicer pauses with (`M601` unless told).
    pub pause_gcode: String,
}

impl Default for SlicedOptions {
    fn default() -> Self {
        SlicedOptions {
            filament_diameter: 1.75,
            pause_gcode: "M601".to_string(),
        }
    }
}

/// Why a sliced file cannot be checked at all.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SlicedError {
    /// A line does not read.
    #[error(transparent)]
    Gcode(#[from] GcodeError),
    /// The filament diameter is outside [`FILAMENT_DIAMETER_MM`].
    #[error(
        "a filament diameter of {0} mm is outside {low} to {high} mm",
        low = FILAMENT_DIAMETER_MM.start(),
        high = FILAMENT_DIAMETER_MM.end()
    )]
    FilamentDiameter(f64),
    /// Nothing is extruded.
    #[error("the G-code extrudes nothing")]
    Empty,
    /// A component has no plan.
    #[error("component `{0}` is not in the print plan")]
    Unplanned(String),
    /// The printed objects cannot be told apart or matched to the components.
    #[error("{0}")]
    Unmatched(String),
}

/// What the sliced file does, beside what the design computed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlicedCheck {
    /// One per component, in project order.
    pub components: Vec<SlicedComponent>,
    /// Layers in the file.
    pub layers: usize,
    /// One per planned pause (lowest first), then one per pause of the file that was not planned.
    pub pauses: Vec<PauseCheck>,
    /// One per capsule of the design, in design order.
    pub voids: Vec<VoidCheck>,
    /// One per pose, in project order.
    pub poses: Vec<SlicedPose>,
}

impl SlicedCheck {
    /// Every failure, one sentence each: a mismatched part, a part whose place on the bed is not
    /// found, a pause problem, an extrusion in a
    /// void, a goal not met with the sliced mass. Empty when the file is as planned.
    pub fn failures(&self) -> Vec<String> {
        let mut failures = Vec::new();
        failures.extend(self.components.iter().filter_map(|c| c.mismatch.clone()));
        failures.extend(self.components.iter().filter_map(|c| c.doubt.clone()));
        failures.extend(self.pauses.iter().filter_map(|p| p.problem.clone()));
        failures.extend(self.voids.iter().filter_map(VoidCheck::problem));
        for pose in &self.poses {
            for goal in pose.goals.iter().filter(|goal| !goal.met) {
                failures.push(format!(
                    "pose \"{}\": the {} goal is not met with the sliced mass ({} {:.2}, computed {:.2})",
                    pose.pose, goal.kind, goal.quantity, goal.sliced, goal.computed
                ));
            }
        }
        failures
    }

    /// Whether the file is as planned and every goal is met with its mass.
    pub fn passes(&self) -> bool {
        self.failures().is_empty()
    }
}

/// One pose with the design's mass and with the sliced file's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlicedPose {
    /// The pose's name.
    pub pose: String,
    /// Total mass, grams, as the design computed it (material and balls).
    pub computed_mass: f64,
    /// Total mass, grams, with the sliced material.
    pub sliced_mass: f64,
    /// Centre of mass, world, as computed.
    pub computed_centre: [f64; 3],
    /// Centre of mass, world, with the sliced material.
    pub sliced_centre: [f64; 3],
    /// One per goal of the pose, in the pose's order.
    pub goals: Vec<SlicedGoal>,
}

/// One goal with the design's mass and with the sliced file's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlicedGoal {
    /// The goal's kind, as in the project file.
    pub kind: &'static str,
    /// What is compared, in words: "tilt margin (°)" or "angle (°)".
    pub quantity: &'static str,
    /// The value with the design's mass model.
    pub computed: f64,
    /// The value with the sliced mass.
    pub sliced: f64,
    /// Whether the goal is met with the design's mass model.
    pub computed_met: bool,
    /// Whether it is met with the sliced mass.
    pub met: bool,
}

/// Checks the G-code `gcode`, sliced from the print files of `compilation` laid out by `plan`.
///
/// Fails only when the file cannot be checked at all: a line does not read, nothing is
/// extruded, a component has no plan, or the printed objects cannot be matched to the components
/// (see `placement.rs`). Everything else is in the returned check; [`SlicedCheck::failures`] lists
/// what is wrong.
pub fn verify_gcode(
    compilation: &Compilation,
    plan: &PrintPlan,
    gcode: &str,
    options: &SlicedOptions,
) -> Result<SlicedCheck, SlicedError> {
    let range = FILAMENT_DIAMETER_MM;
    if !range.contains(&options.filament_diameter) {
        return Err(SlicedError::FilamentDiameter(options.filament_diameter));
    }
    let read = ReadOptions {
        pause_gcode: options.pause_gcode.clone(),
    };
    let mm = compilation.project.units.from_millimetres(1.0);
    // Three passes over the text, so that memory does not grow with the moves: the objects,
    // layers, pauses and each object's extent first, then the extrusions of the few layers each
    // object's place is fitted on, then each extrusion mapped back.
    let mut boxes = NozzleBoxes::new();
    let outline = scan_program(gcode, &read, |id, segment| {
        placement::grow_box(&mut boxes, id, segment, mm)
    })?;
    if outline.objects.iter().all(|o| o.segments == 0) {
        return Err(SlicedError::Empty);
    }
    let mut samples = FitSamples::new(&boxes, mm);
    scan_program(gcode, &read, |id, segment| samples.add(id, segment))?;
    let mut placement = placement::place(compilation, plan, &outline, &boxes, samples)?;
    let mut voids = voids::start(compilation);
    scan_program(gcode, &read, |id, segment| {
        placement.count(compilation, &outline, &mut voids, (id, segment))
    })?;
    let components = placement.finish(compilation, options.filament_diameter);
    let pauses = pauses::check(plan, &outline, mm);
    let bodies: Vec<ComponentBody> = compilation
        .meshes
        .iter()
        .zip(compilation.hulls.iter())
        .zip(&compilation.mass)
        .zip(&components)
        .map(|(((mesh, hull), solid), component)| {
            ComponentBody::measured(
                mesh,
                *solid,
                Region {
                    volume: component.volume,
                    centroid: component.centroid.into(),
                },
            )
            .with_hull(hull.as_ref())
        })
        .collect();
    let poses = compilation
        .project
        .poses
        .iter()
        .zip(&compilation.poses)
        .map(|(pose, computed)| {
            let sliced = evaluate_pose(&compilation.project, &bodies, &compilation.design, pose);
            sliced_pose(computed, &sliced)
        })
        .collect();
    Ok(SlicedCheck {
        components,
        layers: outline.layers.len(),
        pauses,
        voids,
        poses,
    })
}

/// A pose's computed evaluation beside its sliced one.
fn sliced_pose(computed: &PoseEvaluation, sliced: &PoseEvaluation) -> SlicedPose {
    let goals = computed
        .goals
        .iter()
        .zip(&sliced.goals)
        .map(|(computed, sliced)| {
            let (kind, quantity, before) = goal_value(&computed.outcome);
            let (_, _, after) = goal_value(&sliced.outcome);
            SlicedGoal {
                kind,
                quantity,
                computed: before,
                sliced: after,
                computed_met: computed.met,
                met: sliced.met,
            }
        })
        .collect();
    SlicedPose {
        pose: computed.pose.clone(),
        computed_mass: computed.mass,
        sliced_mass: sliced.mass,
        computed_centre: computed.centre_of_mass,
        sliced_centre: sliced.centre_of_mass,
        goals,
    }
}

/// A goal's kind, what its value is, and the value.
fn goal_value(outcome: &GoalOutcome) -> (&'static str, &'static str, f64) {
    match outcome {
        GoalOutcome::Stand { tilt_margin, .. } => ("stand", "tilt margin (°)", *tilt_margin),
        GoalOutcome::Imbalance { tilt_margin, .. } => {
            ("imbalance", "tilt margin (°)", *tilt_margin)
        }
        GoalOutcome::Suspend { angle, .. } => ("suspend", "angle (°)", *angle),
        GoalOutcome::Immerse { angle, .. } => ("immerse", "angle (°)", *angle),
    }
}

/// Per component, the correction that makes the mass model's material what `check` measured in
/// the sliced file: the compilation's own correction (from its calibration file) plus the
/// difference that remains, so that a build with the result has each component's mass and
/// centroid as sliced, for this design. What the calibration file holds (see
/// [`calibration_text`](crate::compile::calibration_text)).
pub fn measured_corrections(
    compilation: &Compilation,
    check: &SlicedCheck,
) -> Vec<PrintCorrection> {
    compilation
        .bodies()
        .iter()
        .zip(&check.components)
        .enumerate()
        .map(|(index, (body, sliced))| {
            let modelled =
                component_material(&compilation.project, body, &compilation.design, index);
            let measured = Region {
                volume: sliced.volume,
                centroid: sliced.centroid.into(),
            };
            compilation
                .corrections
                .get(index)
                .copied()
                .unwrap_or_default()
                .plus_difference(&measured, &modelled)
        })
        .collect()
}
