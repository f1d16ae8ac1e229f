//! The independent check: every goal of a compiled project re-measured by a rigid-body simulation
//! (rapier), not by ballast's own physics.
//!
//! [`verify`] takes a [`Compilation`] and, pose by pose, builds the model as the simulation sees
//! it (one rigid body for all components, placed by the pose; mass from parry's mass properties of
//! the meshes minus the capsule voids; one sphere body per ball on a prismatic joint along its
//! capsule; a convex-hull collider per component), then:
//!
//! - `stand`: sets it down on a ground and tilts the ground slowly, in the worst direction ballast
//!   computed and eleven others around it, until it topples (`stand`);
//! - `imbalance`: sets it down and sees whether it topples;
//! - `suspend`: hangs it from a spherical joint and lets it go from several orientations
//!   (`suspend`);
//! - `immerse`: floats it with buoyancy at its centre of buoyancy and lets it go from several
//!   orientations (`immerse`).
//!
//! Each goal's measured value is put beside the computed one; they agree when they are within
//! [`AGREEMENT_DEGREES`] and the state (stands or topples, where each ball ends) is the same.
//! `docs/physics.md` ("The independent check") says what is simulated and what is not.

mod body;
mod immerse;
mod release;
mod stand;
mod suspend;

use serde::Serialize;

pub use body::BallEnd;
pub use release::{FinalState, Release};
pub use stand::{SlopeRun, TiltRun};

use crate::balance::{BallRest, Equilibria, GoalOutcome, PoseEvaluation, Support};
use crate::compile::Compilation;
use crate::spec::model::Goal;
use body::Model;
use rapier3d_f64::prelude::{Rotation, Vector};

/// Measured and computed agree when they differ by at most this many degrees.
pub const AGREEMENT_DEGREES: f64 = 1.0;

/// Every goal of a project, simulated.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verification {
    /// One per pose, in project order.
    pub poses: Vec<PoseCheck>,
}

impl Verification {
    /// Whether every goal's measured value agrees with the computed one.
    pub fn agrees(&self) -> bool {
        self.poses
            .iter()
            .all(|pose| pose.goals.iter().all(|goal| goal.agrees))
    }
}

/// The goals of one pose, simulated.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PoseCheck {
    /// The pose's name.
    pub pose: String,
    /// One per goal of the pose, in the pose's order.
    pub goals: Vec<GoalCheck>,
}

/// One goal: the value ballast computed beside the one the simulation measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GoalCheck {
    /// The computed value, degrees: the tilt margin for `stand` and `imbalance`, the goal's angle
    /// for `suspend` and `immerse`.
    pub computed: f64,
    /// The measured value, degrees: the smallest ground tilt that toppled the model for `stand`,
    /// minus the gentlest slope it stood on for `imbalance`, the angle after release from the
    /// pose for `suspend` and `immerse`. `None` when there is no such number: a `stand` whose
    /// model toppled as it was set down, or one that still stood at the steepest tilt tried; an
    /// `imbalance` whose model stood on level ground, or toppled on every slope tried.
    pub measured: Option<f64>,
    /// Whether measured and computed agree: same state, values within [`AGREEMENT_DEGREES`].
    pub agrees: bool,
    /// What disagrees, in words, when something does.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub disagreement: Option<String>,
    /// What was simulated, by goal kind.
    #[serde(flatten)]
    pub detail: Detail,
}

/// What was simulated for one goal. Serialised with a `kind` field naming the goal.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Detail {
    /// Set down, then the ground tilted in several directions.
    Stand {
        /// The worst tilt direction ballast computed (horizontal, world, downhill).
        worst_direction: [f64; 3],
        /// One per direction, the worst first; empty when the model toppled as it was set down.
        runs: Vec<TiltRun>,
    },
    /// Set down on level ground and, when it toppled there, on slopes in several directions.
    Imbalance {
        /// Whether the model toppled by itself on level ground.
        topples: bool,
        /// The direction ballast computed the gentlest standing slope in (horizontal, world,
        /// downhill); absent when the model stood on level ground.
        #[serde(skip_serializing_if = "Option::is_none")]
        worst_direction: Option<[f64; 3]>,
        /// One per direction, the computed one first; empty when the model stood on level
        /// ground.
        slopes: Vec<SlopeRun>,
    },
    /// Hung and let go from several orientations.
    Suspend {
        /// One per starting orientation, the pose's own first.
        releases: Vec<Release>,
        /// The distinct final states the releases reached.
        states: Vec<FinalState>,
    },
    /// Floated and let go from several orientations.
    Immerse {
        /// One per starting orientation, the pose's own first.
        releases: Vec<Release>,
        /// The distinct final states the releases reached.
        states: Vec<FinalState>,
    },
}

/// Simulates every goal of every pose of `compilation`.
pub fn verify(compilation: &Compilation) -> Verification {
    let poses = compilation
        .project
        .poses
        .iter()
        .zip(&compilation.poses)
        .map(|(pose, evaluation)| {
            let model = Model::new(compilation, pose);
            let goals = pose
                .goals
                .iter()
                .zip(&evaluation.goals)
                .map(|(goal, computed)| {
                    check_goal(&model, &goal.value, &computed.outcome, evaluation)
                })
                .collect();
            PoseCheck {
                pose: evaluation.pose.clone(),
                goals,
            }
        })
        .collect();
    Verification { poses }
}

/// One goal, simulated and compared.
fn check_goal(
    model: &Model,
    goal: &Goal,
    outcome: &GoalOutcome,
    evaluation: &PoseEvaluation,
) -> GoalCheck {
    match (goal, outcome) {
        (_, GoalOutcome::Stand { tilt_margin, .. }) => check_stand(model, *tilt_margin, evaluation),
        (_, GoalOutcome::Imbalance { tilt_margin, .. }) => {
            check_imbalance(model, *tilt_margin, evaluation)
        }
        (
            Goal::Suspend { .. },
            GoalOutcome::Suspend {
                angle,
                point,
                equilibria,
                ..
            },
        ) => {
            let point = to_si(*point, model.scale);
            let damping = (suspend::LINEAR_DAMPING, suspend::ANGULAR_DAMPING);
            let releases = suspend::hang(model, point, damping);
            release_check(
                *angle,
                releases,
                equilibria,
                evaluation,
                |releases, states| Detail::Suspend { releases, states },
            )
        }
        (
            Goal::Immerse { .. },
            GoalOutcome::Immerse {
                angle, equilibria, ..
            },
        ) => {
            let releases = immerse::float(model);
            release_check(
                *angle,
                releases,
                equilibria,
                evaluation,
                |releases, states| Detail::Immerse { releases, states },
            )
        }
        (_, GoalOutcome::Suspend { angle, .. } | GoalOutcome::Immerse { angle, .. }) => GoalCheck {
            computed: *angle,
            measured: None,
            agrees: false,
            disagreement: Some("the goal and its evaluation differ in kind".to_string()),
            detail: Detail::Imbalance {
                topples: false,
                worst_direction: None,
                slopes: Vec::new(),
            },
        },
    }
}

/// An imbalance goal: whether the model topples when set down on level ground, and if it does,
/// the gentlest slope, over every direction tried, that it stands on (its tilt margin is minus
/// that slope).
fn check_imbalance(model: &Model, tilt_margin: f64, evaluation: &PoseEvaluation) -> GoalCheck {
    let topples = stand::topples_when_set_down(model);
    let (worst, slopes) = if topples {
        let worst = worst_direction(&evaluation.support, model.up);
        // The slopes of the directions after the first need be searched only as steep as the
        // gentlest one found so far: the measured margin is the least over the directions.
        let mut least = stand::MAX_TILT;
        let slopes: Vec<SlopeRun> = tilt_directions(worst, model.up)
            .into_iter()
            .map(|direction| {
                let run = stand::gentlest_standing_slope(model, direction, least);
                if let Some(slope) = run.stands_from {
                    least = least.min(slope);
                }
                run
            })
            .collect();
        (Some(worst.to_array()), slopes)
    } else {
        (None, Vec::new())
    };
    let measured = slopes
        .iter()
        .filter_map(|run| run.stands_from)
        .reduce(f64::min)
        .map(|slope| -slope);
    let computed_state = if tilt_margin < 0.0 {
        "topples"
    } else {
        "stands"
    };
    let disagreement = match measured {
        _ if topples != (tilt_margin < 0.0) => Some(format!(
            "computed {computed_state}, simulated {}",
            if topples { "topples" } else { "stands" }
        )),
        None if topples => Some(format!(
            "tilt margin computed {tilt_margin:.1}°, simulated: stands on no slope up to {:.0}°",
            stand::MAX_TILT
        )),
        Some(value) if (value - tilt_margin).abs() > AGREEMENT_DEGREES => Some(format!(
            "tilt margin computed {tilt_margin:.1}°, simulated {value:.1}°"
        )),
        _ => None,
    };
    GoalCheck {
        computed: tilt_margin,
        measured,
        agrees: disagreement.is_none(),
        disagreement,
        detail: Detail::Imbalance {
            topples,
            worst_direction: worst,
            slopes,
        },
    }
}

/// A stand goal: the smallest toppling tilt over every direction tried.
fn check_stand(model: &Model, tilt_margin: f64, evaluation: &PoseEvaluation) -> GoalCheck {
    let worst = worst_direction(&evaluation.support, model.up);
    let mut runs = Vec::new();
    for direction in tilt_directions(worst, model.up) {
        match stand::tilt(model, direction) {
            Some(run) => runs.push(run),
            None => {
                runs.clear();
                break;
            }
        }
    }
    let measured = if runs.is_empty() {
        None
    } else {
        Some(
            runs.iter()
                .map(|run| run.topples_at.unwrap_or(stand::MAX_TILT))
                .fold(f64::INFINITY, f64::min),
        )
    };
    let disagreement = match measured {
        None if tilt_margin > 0.0 => {
            Some("computed stands, simulated topples when set down".to_string())
        }
        None => None,
        Some(_) if tilt_margin <= 0.0 => Some("computed topples, simulated stands".to_string()),
        Some(value) if (value - tilt_margin).abs() > AGREEMENT_DEGREES => Some(format!(
            "tilt margin computed {tilt_margin:.1}°, simulated {value:.1}°"
        )),
        Some(_) => None,
    };
    let measured = measured.filter(|value| *value < stand::MAX_TILT);
    GoalCheck {
        computed: tilt_margin,
        measured,
        agrees: disagreement.is_none(),
        disagreement,
        detail: Detail::Stand {
            worst_direction: worst.to_array(),
            runs,
        },
    }
}

/// The horizontal direction (world, unit, downhill) in which ballast computed the model topples
/// first: the support's `tilt_direction`, made horizontal; any horizontal direction when it has
/// none.
fn worst_direction(support: &Support, up: Vector) -> Vector {
    support
        .tilt_direction
        .map(Vector::from_array)
        .map(|v| v - up * v.dot(up))
        .filter(|flat| flat.length() > 1e-12)
        .map(|flat| flat.normalize())
        .unwrap_or_else(|| body::horizontal_axes(up).0)
}

/// How many directions the ground is tilted in: the worst one and the others around it, evenly
/// spaced (so the opposite and the two perpendicular ones are among them).
pub const TILT_DIRECTIONS: usize = 12;

/// The directions the ground is tilted in: `worst` first, then the others, turned about `up` in
/// equal steps.
fn tilt_directions(worst: Vector, up: Vector) -> Vec<Vector> {
    let mut directions = vec![worst];
    for k in 1..TILT_DIRECTIONS {
        let angle = (360.0 * k as f64 / TILT_DIRECTIONS as f64).to_radians();
        directions.push(Rotation::from_axis_angle(up, angle) * worst);
    }
    directions
}

/// The check of a hanging or floating goal from its simulated `releases`: their distinct final
/// states, compared with the computed angle and states ([`compare_release`]), kept in the detail
/// `detail` makes of them.
fn release_check(
    computed: f64,
    releases: Vec<Release>,
    equilibria: &Equilibria,
    evaluation: &PoseEvaluation,
    detail: fn(Vec<Release>, Vec<FinalState>) -> Detail,
) -> GoalCheck {
    let states = release::distinct_states(&releases);
    let (measured, disagreement) =
        compare_release(computed, &releases, &states, equilibria, evaluation);
    GoalCheck {
        computed,
        measured,
        agrees: disagreement.is_none(),
        disagreement,
        detail: detail(releases, states),
    }
}

/// The release from the pose's own orientation against the computed angle, the balls' ends
/// against the computed ones, and every state the releases came to rest in against the stable
/// states ballast lists (`equilibria`, angles off the goal's orientation): the measured angle and
/// what disagrees.
fn compare_release(
    computed: f64,
    releases: &[Release],
    states: &[FinalState],
    equilibria: &Equilibria,
    evaluation: &PoseEvaluation,
) -> (Option<f64>, Option<String>) {
    let Some(first) = releases.first() else {
        return (None, Some("nothing was simulated".to_string()));
    };
    let mut problems = Vec::new();
    if !first.settled {
        problems.push("the model did not come to rest".to_string());
    }
    if (first.angle - computed).abs() > AGREEMENT_DEGREES {
        problems.push(format!(
            "angle computed {computed:.1}°, simulated {:.1}°",
            first.angle
        ));
    }
    for (ball, end) in evaluation.balls.iter().zip(&first.balls) {
        let same = matches!(
            (ball.rest, end),
            (BallRest::Undetermined, _)
                | (BallRest::From, BallEnd::From)
                | (BallRest::To, BallEnd::To)
        );
        if !same {
            problems.push(format!("ball `{}` ends elsewhere", ball.capsule));
        }
    }
    // Only a complete list can be checked for what it leaves out.
    if equilibria.complete {
        for state in states {
            let listed = equilibria
                .states
                .iter()
                .any(|known| (known.angle - state.angle).abs() <= AGREEMENT_DEGREES);
            if !listed {
                problems.push(format!(
                    "the simulation also comes to rest {:.1}° off, a state ballast does not list",
                    state.angle
                ));
            }
        }
    }
    let disagreement = (!problems.is_empty()).then(|| problems.join("; "));
    (Some(first.angle), disagreement)
}

/// A point of the report, project units, in metres.
fn to_si(point: [f64; 3], scale: f64) -> Vector {
    Vector::from_array(point) * scale
}
