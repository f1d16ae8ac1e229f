//! Every stable state of a hanging or floating model: each assignment of ball ends, its centre of
//! mass, the orientation it settles in, and whether every ball stays at its assigned end there.
//!
//! The pose's articulation is fixed (components keep their pose transforms); only the whole model
//! turns. Directions are in the pose's world frame, which turns with the model: "gravity" below is
//! the direction gravity points in that frame once the model has settled.

use nalgebra::{Isometry3, Point3, Vector3};

use super::mass::MassTotals;
use super::{ball, BallPlacement, BallRest, ComponentBody, Equilibria, Equilibrium, StateBall};
use crate::design::Design;
use crate::spec::model::{Ball, Pose, Project};

/// With at most this many balls that can roll, every one of the `2^n` assignments of ball ends is
/// tried; with more, only the assignments that differ from the wanted one in at most
/// [`CUT_FLIPS`] balls (and [`Equilibria::complete`] is false).
pub const MAX_ENUMERATED_BALLS: usize = 12;

/// How many balls an assignment may differ in from the wanted one once the enumeration is cut.
pub const CUT_FLIPS: usize = 2;

/// Fixed-point iterations for the balls resting against their end caps (see [`Model::settle`]).
const SETTLE_ITERATIONS: usize = 50;

/// The sets of balls (indices in `0..count`) to move to their other end, starting with the empty
/// set (the wanted assignment): every subset when `count ≤ limit`, else those of at most
/// [`CUT_FLIPS`] balls. Deterministic: subsets in increasing binary order, or by size then index.
pub(crate) fn flip_sets(count: usize, limit: usize) -> Vec<Vec<usize>> {
    if count <= limit {
        return (0u64..1 << count)
            .map(|mask| (0..count).filter(|i| mask >> i & 1 == 1).collect())
            .collect();
    }
    let mut sets = vec![Vec::new()];
    sets.extend((0..count).map(|i| vec![i]));
    for i in 0..count {
        sets.extend((i + 1..count).map(|j| vec![i, j]));
    }
    sets
}

/// One ball that weighs in the model's mass, at either end of its capsule (the two ends are equal
/// for a spherical cavity).
struct Roller {
    /// Index in the design's capsules.
    capsule: usize,
    /// The `from` and `to` ends, world.
    ends: [Point3<f64>; 2],
    /// Ball mass, grams.
    mass: f64,
    /// `r − b` (at least 0): how far the ball's centre lies below its end point.
    drop: f64,
    /// The end the pose puts it at: `Some(false)` for `from`, `Some(true)` for `to`, `None` when
    /// undetermined.
    wanted: Option<bool>,
}

/// What every assignment of one pose shares: the mass without the rolling balls and the balls.
pub(crate) struct Model<'a> {
    design: &'a Design,
    frames: Vec<Isometry3<f64>>,
    ball: &'a Ball,
    /// Unit up, world.
    up: Vector3<f64>,
    /// Total mass, grams.
    mass: f64,
    /// Σ m·x over everything but the rolling balls, world.
    fixed_moment: Vector3<f64>,
    rollers: Vec<Roller>,
    /// Two points closer than this coincide.
    coincidence: f64,
}

impl<'a> Model<'a> {
    /// The model of `design` in `pose` of `project`, from the pose's ball placements and mass
    /// totals.
    pub(crate) fn new(
        bodies: &[ComponentBody],
        design: &'a Design,
        pose: &Pose,
        project: &'a Project,
        placements: &[BallPlacement],
        totals: &MassTotals,
        coincidence: f64,
    ) -> Model<'a> {
        let frames: Vec<Isometry3<f64>> = design
            .capsules
            .iter()
            .map(|capsule| pose.component_frame(capsule.component))
            .collect();
        let mut fixed_moment = totals.centre_of_mass.coords * totals.mass;
        let mut rollers = Vec::new();
        for (j, (capsule, placed)) in design.capsules.iter().zip(placements).enumerate() {
            if capsule.component >= bodies.len() {
                continue;
            }
            fixed_moment -= Vector3::from(placed.centre_world) * placed.mass;
            // A spherical cavity's ball has one place whatever the orientation: two equal ends.
            let wanted = match placed.rest {
                _ if capsule.to == capsule.from => None,
                BallRest::From => Some(false),
                BallRest::To => Some(true),
                BallRest::Undetermined => None,
            };
            rollers.push(Roller {
                capsule: j,
                ends: [frames[j] * capsule.from, frames[j] * capsule.to],
                mass: placed.mass,
                drop: (capsule.radius - capsule.ball_radius).max(0.0),
                wanted,
            });
        }
        Model {
            design,
            frames,
            ball: &project.ball,
            up: project.up.unit_vector(),
            mass: totals.mass,
            fixed_moment,
            rollers,
            coincidence,
        }
    }

    /// Every stable state when the model turns freely about `anchor` (world): the suspension
    /// point of a hang, the centre of buoyancy of a submerged float. Both settle with gravity
    /// along `c − anchor`, the centre of mass `c` below the anchor.
    pub(crate) fn states(&self, anchor: &Point3<f64>) -> Equilibria {
        let movable: Vec<usize> = (0..self.rollers.len())
            .filter(|&k| self.rollers[k].ends[0] != self.rollers[k].ends[1])
            .collect();
        let complete = movable.len() <= MAX_ENUMERATED_BALLS;
        let sets = flip_sets(movable.len(), MAX_ENUMERATED_BALLS);
        let mut states = Vec::new();
        if self.mass.is_finite() && self.mass > 0.0 {
            for set in &sets {
                let mut at_to: Vec<bool> = self
                    .rollers
                    .iter()
                    .map(|r| r.wanted.unwrap_or(false))
                    .collect();
                for &k in set {
                    at_to[movable[k]] = !at_to[movable[k]];
                }
                if let Some(state) = self.state(anchor, &at_to) {
                    states.push(state);
                }
            }
        }
        Equilibria {
            complete,
            assignments: sets.len(),
            states,
        }
    }

    /// The centre of mass with each roller at the end `at_to` says, its ball against that end's
    /// cap for gravity `gravity` (unit, world).
    fn centre(&self, at_to: &[bool], gravity: &Vector3<f64>) -> Point3<f64> {
        let mut moment = self.fixed_moment;
        for (roller, &to) in self.rollers.iter().zip(at_to) {
            let end = roller.ends[usize::from(to)];
            moment += (end.coords + gravity * roller.drop) * roller.mass;
        }
        Point3::from(moment / self.mass)
    }

    /// The gravity direction (unit, world) the assignment `at_to` settles with about `anchor`, or
    /// `None` when its centre of mass is at the anchor (a neutral hang: no orientation is
    /// preferred).
    ///
    /// The balls rest against their end caps, `r − b` below the end along gravity, so the centre
    /// depends on the orientation it decides. A fixed point `g = (c(g) − s) / |c(g) − s|` is
    /// iterated from `c` without the drop; the map's contraction factor is at most
    /// `Σ m_i (r_i − b_i) / (M |c − s|)`, far below 1 for any real design.
    fn settle(&self, anchor: &Point3<f64>, at_to: &[bool]) -> Option<Vector3<f64>> {
        let mut gravity = Vector3::zeros();
        for _ in 0..SETTLE_ITERATIONS {
            let offset = self.centre(at_to, &gravity) - anchor;
            let length = offset.norm();
            if !(length > self.coincidence && length.is_finite()) {
                return None;
            }
            let next = offset / length;
            let change = (next - gravity).norm();
            gravity = next;
            if change <= 1e-14 {
                break;
            }
        }
        Some(gravity)
    }

    /// The assignment `at_to` as a state when it is one: settled, every ball where gravity sends
    /// it, or within the ball's min-angle of horizontal (marginal).
    fn state(&self, anchor: &Point3<f64>, at_to: &[bool]) -> Option<Equilibrium> {
        let gravity = self.settle(anchor, at_to)?;
        let mut balls = Vec::with_capacity(self.rollers.len());
        let mut marginal = false;
        for (roller, &to) in self.rollers.iter().zip(at_to) {
            let capsule = &self.design.capsules[roller.capsule];
            // The same rule as the pose's own placement, with this state's gravity.
            let placed = ball::place_ball(
                capsule,
                &self.frames[roller.capsule],
                &-gravity,
                self.ball,
                0.0,
            );
            let assigned = if to { BallRest::To } else { BallRest::From };
            match placed.rest {
                BallRest::Undetermined => marginal = true,
                rest if rest != assigned => return None,
                _ => {}
            }
            balls.push(StateBall {
                capsule: capsule.name.clone(),
                rest: assigned,
                elevation: placed.elevation,
                moved: roller.wanted.is_some_and(|wanted| wanted != to),
            });
        }
        let wanted = self
            .rollers
            .iter()
            .zip(at_to)
            .all(|(roller, &to)| roller.wanted.is_none_or(|wanted| wanted == to));
        let angle = gravity.dot(&-self.up).clamp(-1.0, 1.0).acos().to_degrees();
        Some(Equilibrium {
            wanted,
            angle,
            gravity: gravity.into(),
            centre_of_mass: self.centre(at_to, &gravity).into(),
            marginal,
            balls,
        })
    }
}
