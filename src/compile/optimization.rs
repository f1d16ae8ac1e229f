//! What the optimizer stage did, as the report and the terminal show it: the capsule counts
//! tried, the seeds, where each capsule came from, conflicts, timings, and the warnings for written
//! seeds it had to move.

use serde::Serialize;

use super::design::round;
use crate::cancel::Interruption;
use crate::diagnostic::Problem as Diagnostic;
use crate::fabrication::CapsuleIssue;
use crate::optimize::{Candidate, Conflict, Origin, Ranking, SeedRepair, SeedSite, StartCapsule};
use crate::spec::model::Project;

/// What the optimizer did: every capsule count tried and which one was chosen.
#[derive(Debug, Clone, Serialize)]
pub struct Optimization {
    /// The capsule count asked for, if any.
    pub requested: Option<usize>,
    /// Capsules in the chosen design.
    pub chosen: usize,
    /// Whether the chosen design meets every goal.
    pub meets_goals: bool,
    /// The tolerance of the choice, degrees.
    pub tolerance: f64,
    /// Whether the heuristic started from the previous build's design (watch mode) rather than
    /// from the skeleton seeds.
    pub warm_started: bool,
    /// What stopped the search before its end (`build` interrupted or out of time), if anything:
    /// the design is then the best of the rounds finished before.
    pub interrupted: Option<Interruption>,
    /// Every capsule count the heuristic tried, most capsules first.
    pub candidates: Vec<CandidateReport>,
    /// Every skeleton segment's midpoint and whether a capsule was seeded there.
    pub seeds: Vec<SeedReport>,
    /// How many capsules the search started from, by where they came from (the terminal's
    /// summary; the report says it per capsule in `origins`).
    #[serde(skip)]
    pub starts: Starts,
    /// Where each capsule of the chosen design came from, in design order.
    pub origins: Vec<CapsuleOrigin>,
    /// Random starts solved because no capsule count the heuristic tried met every goal (0 when
    /// one did): [`rescue`](crate::optimize::rescue).
    pub rescue_starts: usize,
    /// Where the heuristic ranks among random starts, per capsule count (empty unless asked).
    pub exhaustive: Vec<Ranking>,
    /// When the chosen design misses some goal: the goals that cannot be met even alone, and the
    /// pairs that cannot be met together.
    pub conflicts: Vec<ConflictReport>,
    /// Whether the explanation of the goals missed was interrupted before it had tried every
    /// goal and pair: `conflicts` then holds only those it had shown.
    pub conflicts_cut_short: bool,
    /// Wall-clock seconds per stage. Not deterministic, so never written to a file.
    #[serde(skip)]
    pub timings: Timings,
    /// Warnings for the written seeds that had to be moved before the search (the diagnostics
    /// travel with the compilation's warnings, not in the report).
    #[serde(skip)]
    pub warnings: Vec<Diagnostic>,
}

/// The capsules a search started from, counted by where they came from.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Starts {
    /// Written with `pinned=#true`: kept as written.
    pub pinned: usize,
    /// Written in the project file, not pinned (after any repair; a seed dropped is not counted).
    pub written: usize,
    /// Seeded at skeleton segments' midpoints.
    pub skeleton: usize,
    /// Capsules of the previous build's design (watch mode's warm start).
    pub earlier: usize,
}

impl Starts {
    /// The counts of `seeds`.
    pub(super) fn of(seeds: &[StartCapsule]) -> Starts {
        let mut starts = Starts::default();
        for seed in seeds {
            let count = match seed.origin {
                _ if seed.pinned => &mut starts.pinned,
                Origin::Written => &mut starts.written,
                Origin::Skeleton(_) => &mut starts.skeleton,
                Origin::Earlier | Origin::Random => &mut starts.earlier,
            };
            *count += 1;
        }
        starts
    }
}

/// Wall-clock seconds of each optimizer stage.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Timings {
    /// Distance grids and skeletons.
    pub precompute: f64,
    /// The heuristic, all rounds.
    pub heuristic: f64,
    /// Exhaustive search.
    pub exhaustive: f64,
    /// Explaining conflicts.
    pub conflicts: f64,
}

/// Goals the optimizer cannot meet: one goal that is out of reach even alone, or two that can each
/// be met but not together.
#[derive(Debug, Clone, Serialize)]
pub struct ConflictReport {
    /// The goals, each as `pose name` and index within the pose.
    pub goals: Vec<GoalName>,
    /// How short the best design for just these goals falls, degrees of the smooth objective.
    pub shortfall: f64,
}

/// A goal, named by its pose.
#[derive(Debug, Clone, Serialize)]
pub struct GoalName {
    /// The pose's name.
    pub pose: String,
    /// The goal's index within the pose, from 0.
    pub goal: usize,
    /// The goal's kind: `stand`, `imbalance`, `suspend` or `immerse`.
    pub kind: &'static str,
}

/// One capsule count the heuristic tried.
#[derive(Debug, Clone, Serialize)]
pub struct CandidateReport {
    /// Number of capsules.
    pub capsules: usize,
    /// The smooth objective `f` reached, degrees (at most 0 when every goal is met; lower is
    /// better).
    pub objective: f64,
    /// The smallest tilt margin over every `stand` goal, degrees, when there are stand goals.
    pub worst_tilt_margin: Option<f64>,
    /// Whether every goal is met and every capsule can be printed.
    pub meets_goals: bool,
    /// Whether every capsule can be printed where it is: the fabrication checks pass, every
    /// ball insertable at a pause in its component's print orientation.
    pub printable: bool,
    /// Wall-clock seconds. Not deterministic, so never written to a file.
    #[serde(skip)]
    pub seconds: f64,
}

/// One skeleton segment's midpoint.
#[derive(Debug, Clone, Serialize)]
pub struct SeedReport {
    /// The component whose skeleton it is on.
    pub component: String,
    /// The midpoint, rest frame of the component.
    pub midpoint: [f64; 3],
    /// Distance to the component's surface, project units (positive inside).
    pub depth: f64,
    /// Whether a capsule was seeded there.
    pub seeded: bool,
}

/// Where one capsule of the chosen design came from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CapsuleOrigin {
    /// The capsule's name in the design.
    pub capsule: String,
    /// `pinned` (written with `pinned=#true`, kept as written), `written` (a seed written in the
    /// project file), `skeleton` (seeded at a skeleton segment's midpoint) or `earlier` (a
    /// capsule of the previous build, in watch mode).
    pub seed: &'static str,
    /// The name of the capsule it started from, in the project file or the previous build; `None`
    /// for a skeleton seed.
    pub seed_name: Option<String>,
    /// For a skeleton seed, the index of its site in [`Optimization::seeds`].
    pub site: Option<usize>,
}

/// The warning for a written seed that broke a fabrication rule: what was wrong, and where the
/// optimizer starts it instead (or that it goes on without it).
pub(super) fn repair_warning(project: &Project, repair: &SeedRepair) -> Diagnostic {
    let units = project.units.keyword();
    let name = |i: usize| {
        project
            .capsules
            .get(i)
            .map_or("?", |c| c.name.value.as_str())
    };
    let written = project.capsules.get(repair.seed);
    let seed = name(repair.seed);
    let component = |i: usize| project.component_name(i).to_string();
    let wrong: Vec<String> = repair
        .issues
        .iter()
        .map(|issue| match *issue {
            CapsuleIssue::TooShort { length, radius, .. } => {
                format!("is shorter ({} {units}) than its radius ({radius} {units})", round(length))
            }
            CapsuleIssue::BallDoesNotFit { .. } => "is too thin for a ball".to_string(),
            CapsuleIssue::UnknownComponent { .. } => "names no component".to_string(),
            CapsuleIssue::NoInsertionWindow { .. } => {
                "cannot take its ball at any pause".to_string()
            }
            CapsuleIssue::Outside { component: c, .. } => {
                format!("is outside its component `{}`", component(c))
            }
            CapsuleIssue::InOtherComponent { assigned, actual, .. } => format!(
                "lies inside `{}`, not its component `{}`",
                component(actual),
                component(assigned)
            ),
            CapsuleIssue::TooCloseToSurface {
                component: c,
                distance,
                required,
                ..
            } => format!(
                "comes within {} {units} of the surface of `{}` (its radius plus the wall needs {} {units})",
                round(distance),
                component(c),
                round(required)
            ),
            CapsuleIssue::Overlap {
                first,
                second,
                distance,
                required,
                ..
            } => {
                let other = if first == repair.seed { second } else { first };
                format!(
                    "is {} {units} from `{}` (their radii plus the wall need {} {units})",
                    round(distance),
                    name(other),
                    round(required)
                )
            }
        })
        .collect();
    let wrong = wrong.join("; ");
    let warning = match &repair.repaired {
        Some(moved) => {
            let point = |p: &nalgebra::Point3<f64>| {
                format!("{} {} {}", round(p.x), round(p.y), round(p.z))
            };
            let shift = written.map_or(0.0, |w| {
                (nalgebra::center(&moved.from, &moved.to) - nalgebra::center(&w.from, &w.to))
                    .norm()
            });
            Diagnostic::warning(
                "ballast::capsule::seed_moved",
                format!(
                    "seed `{seed}` {wrong}: the optimizer starts it {}, from {} to {}, radius {} {units}",
                    if shift > 0.0 {
                        format!("{} {units} away", round(shift))
                    } else {
                        "in place".to_string()
                    },
                    point(&moved.from),
                    point(&moved.to),
                    round(moved.radius)
                ),
            )
        }
        None => Diagnostic::warning(
            "ballast::capsule::seed_dropped",
            format!("seed `{seed}` {wrong}, and no valid place was found near it: the optimizer goes on without it"),
        ),
    };
    let warning = match written {
        Some(w) => warning.with_label(w.span, "this seed"),
        None => warning,
    };
    warning.with_help("a seed is only where the optimizer starts; write `pinned=#true` to keep a capsule exactly as written (it must then be valid)")
}

pub(super) fn conflict_report(project: &Project, conflict: &Conflict) -> ConflictReport {
    ConflictReport {
        goals: conflict
            .goals
            .iter()
            .map(|g| {
                let pose = &project.poses[g.pose];
                GoalName {
                    pose: pose.name.value.clone(),
                    goal: g.goal,
                    kind: pose.goals[g.goal].value.keyword(),
                }
            })
            .collect(),
        shortfall: conflict.shortfall,
    }
}

pub(super) fn candidate_report(candidate: &Candidate) -> CandidateReport {
    CandidateReport {
        capsules: candidate.capsules,
        objective: candidate.outcome.value.to_degrees(),
        worst_tilt_margin: candidate.outcome.worst_tilt_margin,
        meets_goals: candidate.outcome.meets_goals,
        printable: candidate.outcome.fabrication.is_empty(),
        seconds: candidate.seconds,
    }
}

pub(super) fn seed_report(project: &Project, site: &SeedSite) -> SeedReport {
    SeedReport {
        component: project.component_name(site.component).to_string(),
        midpoint: site.midpoint.coords.into(),
        depth: site.depth,
        seeded: site.seeded,
    }
}
