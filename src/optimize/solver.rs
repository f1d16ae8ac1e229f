//! One local solve of the nonlinear program: an [`Objective`] handed to a constrained solver.
//!
//! Two solvers are wired in, both pure-Rust translations of NLopt's: SLSQP (`slsqp` crate,
//! sequential quadratic programming with the exact gradients) and COBYLA (`cobyla` crate, linear
//! approximations, no gradients). `docs/benchmarks.md` compares them on the examples. The
//! default, [`Method::Hybrid`], runs SLSQP and falls back to COBYLA where SLSQP misses.
//!
//! The solvers see a scaled design vector `u = (x − shift) / scale`: positions relative to the
//! centre of their component's bounding box and lengths divided by the model's extent, so every
//! unknown is of order one whatever the project's units.

use std::cell::RefCell;

use crate::cancel::Cancel;

use crate::objective::Objective;

/// Which solver runs a local solve.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Method {
    /// SLSQP, then COBYLA from SLSQP's best point when that misses a goal or a constraint
    /// (default: SLSQP is fast and precise when it converges; COBYLA gets out of the places
    /// where its line search fails).
    #[default]
    Hybrid,
    /// Sequential quadratic programming with exact gradients.
    Slsqp,
    /// Derivative-free linear approximations.
    Cobyla,
}

/// Box bounds on every entry of the design vector, with the scaling the solvers see.
#[derive(Debug, Clone, PartialEq)]
pub struct Bounds {
    /// Per entry: lowest and highest value, project units.
    pub range: Vec<(f64, f64)>,
    /// Per entry: the value that scales to 0.
    pub shift: Vec<f64>,
    /// Per entry: the length that scales to 1.
    pub scale: Vec<f64>,
}

/// What one local solve reached.
#[derive(Debug, Clone, PartialEq)]
pub struct Solve {
    /// The design vector reached, project units.
    pub x: Vec<f64>,
    /// The objective there.
    pub value: f64,
    /// The largest constraint violation there, each constraint divided by its gradient's length
    /// at the start (roughly a fraction of the model's extent): 0 when every `g ≥ 0` holds.
    pub violation: f64,
    /// Objective evaluations the solver asked for.
    pub evaluations: usize,
    /// Whether the solver reported success (a stop on a tolerance or the evaluation budget).
    pub converged: bool,
}

/// Stops for a local solve.
#[derive(Debug, Clone)]
pub struct Budget {
    /// Most objective evaluations.
    pub evaluations: usize,
    /// Stop when the objective changes by less than this, relative.
    pub relative_tolerance: f64,
    /// When set, the solve gives up at once: the solver sees a flat objective and returns within
    /// a few trivial evaluations, and its result means nothing.
    pub cancel: Cancel,
    /// Stop, as when cancelled but keeping the best point, after this many evaluations in a row
    /// that gain nothing worth having over the best point before them (`worth_having`);
    /// `None`: run to the budget or the solver's own tolerances.
    pub stall: Option<usize>,
    /// Whether [`Method::Hybrid`]'s COBYLA pass also follows an SLSQP pass that ends within the
    /// constraints but misses a goal (a goal term above 0), or only one that ends outside
    /// them. A solve from a design already solved with nearly the same objective (the
    /// refinement's) turns it off: there COBYLA rarely gains, and its linear models of every
    /// constraint cost more than the SLSQP pass.
    pub fallback_on_goals: bool,
}

impl Default for Budget {
    fn default() -> Self {
        Budget {
            evaluations: 400,
            relative_tolerance: 1e-6,
            cancel: Cancel::new(),
            stall: None,
            fallback_on_goals: true,
        }
    }
}

/// Every constraint at the last point asked for, reused while the solver asks for one constraint
/// at a time at the same point.
struct ConstraintCache {
    u: Vec<f64>,
    with_gradients: bool,
    values: Vec<(f64, Vec<f64>)>,
}

/// The evaluations so far and the best point among them: the lowest objective among feasible
/// points, or the smallest violation while none is feasible. The solvers' own final point is not
/// always the best they saw (SLSQP stops on a failed line search and hands back its start).
struct Tracker {
    evaluations: usize,
    best: Option<(Vec<f64>, f64, f64)>,
    /// The value and violation of the last best point that was worth having over the one
    /// before, and the evaluation that reached it.
    mark: Option<((f64, f64), usize)>,
}

impl Tracker {
    /// Counts the evaluation at `u`, and keeps it when it is the best so far. A point with a
    /// coordinate or objective that is not a number (a solver step through a NaN gradient) is
    /// never kept.
    fn record(&mut self, u: &[f64], value: f64, violation: f64) {
        self.evaluations += 1;
        if value.is_nan() || violation.is_nan() || u.iter().any(|v| !v.is_finite()) {
            return;
        }
        let better = match &self.best {
            None => true,
            Some((_, best_value, best_violation)) => {
                preferred((value, violation), (*best_value, *best_violation))
            }
        };
        if better {
            self.best = Some((u.to_vec(), value, violation));
            let worth = match self.mark {
                None => true,
                Some((mark, _)) => worth_having((value, violation), mark),
            };
            if worth {
                self.mark = Some(((value, violation), self.evaluations));
            }
        }
    }

    /// Whether the last `window` evaluations gained nothing worth having.
    fn stalled(&self, window: usize) -> bool {
        let since = self.mark.map_or(0, |(_, at)| at);
        self.evaluations - since >= window
    }
}

/// The least fall of the objective (radians: 0.006°) that counts as a gain for
/// [`Budget::stall`].
pub(crate) const WORTH_HAVING: f64 = 1e-4;

/// Whether a point with `(value, violation)` improves on `(other_value, other_violation)` by
/// enough to go on looking: feasible where the other is not, an objective lower by
/// [`WORTH_HAVING`] among feasible points, any smaller violation among infeasible ones (a design
/// outside the constraints is of no use, so every step towards them counts).
fn worth_having(
    (value, violation): (f64, f64),
    (other_value, other_violation): (f64, f64),
) -> bool {
    match (violation <= FEASIBLE, other_violation <= FEASIBLE) {
        (true, true) => value < other_value - WORTH_HAVING,
        (true, false) => true,
        (false, true) => false,
        (false, false) => violation < other_violation,
    }
}

/// Evaluations per free unknown without a gain after which a pass of the hybrid stops.
const STALL_PER_UNKNOWN: usize = 10;

/// Evaluations without a gain after which a pass of the hybrid stops, beside those per unknown.
const STALL_BASE: usize = 50;

/// Whether a point with `(value, violation)` is preferred to one with `(other_value,
/// other_violation)`: a feasible point to an infeasible one, then the lower objective among
/// feasible points, the smaller violation among infeasible ones.
pub(crate) fn preferred(
    (value, violation): (f64, f64),
    (other_value, other_violation): (f64, f64),
) -> bool {
    match (violation <= FEASIBLE, other_violation <= FEASIBLE) {
        (true, true) => value < other_value,
        (true, false) => true,
        (false, true) => false,
        (false, false) => violation < other_violation,
    }
}

/// The largest scaled constraint violation (a fraction of the model's extent) a point may have
/// and still count as feasible.
pub(crate) const FEASIBLE: f64 = 1e-7;

/// Minimizes `objective` from `x0` within `bounds` by `method`, and returns the best point
/// evaluated.
///
/// Deterministic: the same inputs give the same bits. Never panics on a mismatched `x0`: it is
/// padded or cut to the objective's layout.
pub fn solve(
    objective: &Objective,
    x0: &[f64],
    bounds: &Bounds,
    method: Method,
    budget: Budget,
) -> Solve {
    if method != Method::Hybrid {
        return solve_by(objective, x0, bounds, method, &budget);
    }
    // Each pass stops once it has gone a while without a gain worth having. SLSQP near a
    // minimum can creep on by gains of a millionth for the whole budget (restarting after each
    // failed line search); most COBYLA fallbacks start where SLSQP has already done what COBYLA
    // can, and the rest of a full budget there costs COBYLA's own algebra (linear models of
    // every constraint), not the objective.
    let free = bounds.range.iter().filter(|(lo, hi)| lo < hi).count();
    let pass = Budget {
        stall: Some(STALL_PER_UNKNOWN * free + STALL_BASE),
        ..budget
    };
    let first = solve_by(objective, x0, bounds, Method::Slsqp, &pass);
    let fixed = free == 0;
    // A goal is missed where its own term is above 0: `f`, their smooth maximum, lies above the
    // largest by up to ln(n)/α, and a design meeting every goal by a little can have `f > 0`.
    let met = first.violation <= FEASIBLE
        && (!pass.fallback_on_goals || objective.worst_goal_term(&first.x) <= 0.0);
    if fixed || met || pass.cancel.is_cancelled() {
        return first;
    }
    let from = if first.violation <= FEASIBLE {
        &first.x
    } else {
        x0
    };
    let second = solve_by(objective, from, bounds, Method::Cobyla, &pass);
    let evaluations = first.evaluations + second.evaluations;
    let better = preferred(
        (second.value, second.violation),
        (first.value, first.violation),
    );
    let best = if better { second } else { first };
    Solve {
        evaluations,
        ..best
    }
}

/// What a cancelled solve's solver sees everywhere: zero, with a zero gradient.
fn flat(gradient: Option<&mut [f64]>) -> f64 {
    if let Some(g) = gradient {
        g.fill(0.0);
    }
    0.0
}

/// [`solve`] with one solver.
fn solve_by(
    objective: &Objective,
    x0: &[f64],
    bounds: &Bounds,
    method: Method,
    budget: &Budget,
) -> Solve {
    let n = objective.layout().len();
    let tracker = RefCell::new(Tracker {
        evaluations: 0,
        best: None,
        mark: None,
    });
    // Cancelled, or (with a stall window) gone that long without a gain: the solver then sees a
    // flat objective and stops.
    let cancelled = || {
        budget.cancel.is_cancelled()
            || budget
                .stall
                .is_some_and(|window| tracker.borrow().stalled(window))
    };
    let start: Vec<f64> = (0..n)
        .map(|i| {
            let (lo, hi) = bounds.range[i];
            x0.get(i).copied().unwrap_or(0.0).clamp(lo, hi)
        })
        .collect();
    // Entries whose range is a single value (pinned capsules) are not the solver's unknowns.
    let free: Vec<usize> = (0..n)
        .filter(|&i| bounds.range[i].0 < bounds.range[i].1)
        .collect();
    let to_x = |u: &[f64]| -> Vec<f64> {
        let mut x = start.clone();
        for (&i, &v) in free.iter().zip(u) {
            x[i] = bounds.shift[i] + bounds.scale[i] * v;
        }
        x
    };
    let u0: Vec<f64> = free
        .iter()
        .map(|&i| (start[i] - bounds.shift[i]) / bounds.scale[i])
        .collect();
    let u_bounds: Vec<(f64, f64)> = free
        .iter()
        .map(|&i| {
            let (lo, hi) = bounds.range[i];
            (
                (lo - bounds.shift[i]) / bounds.scale[i],
                (hi - bounds.shift[i]) / bounds.scale[i],
            )
        })
        .collect();
    let cache = RefCell::new(ConstraintCache {
        u: Vec::new(),
        with_gradients: false,
        values: Vec::new(),
    });
    // COBYLA never asks for gradients, so its constraints are evaluated without them.
    let gradients = method != Method::Cobyla;
    let constraints_at = |u: &[f64], with_gradients: bool| {
        let mut cache = cache.borrow_mut();
        if cache.u != u || (with_gradients && !cache.with_gradients) {
            let x = to_x(u);
            cache.values = if with_gradients {
                objective.constraints(&x)
            } else {
                objective
                    .constraint_values(&x)
                    .into_iter()
                    .map(|g| (g, Vec::new()))
                    .collect()
            };
            cache.u = u.to_vec();
            cache.with_gradients = with_gradients;
        }
    };
    // Each constraint divided by the length of its gradient in `u` at the start, so that its
    // value is roughly the distance (in `u`) to its boundary, whatever its units.
    let norms: Vec<f64> = {
        constraints_at(&u0, true);
        let cache = cache.borrow();
        cache
            .values
            .iter()
            .map(|(_, dx)| {
                let norm = free
                    .iter()
                    .map(|&i| (dx[i] * bounds.scale[i]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                if norm > 1e-12 {
                    norm
                } else {
                    1.0
                }
            })
            .collect()
    };
    let m = norms.len();
    let constraint = |u: &[f64], k: usize, gradient: Option<&mut [f64]>| -> f64 {
        if cancelled() {
            return flat(gradient);
        }
        constraints_at(u, gradients);
        let cache = cache.borrow();
        let (value, dx) = &cache.values[k];
        if let Some(g) = gradient {
            for (g, &i) in g.iter_mut().zip(&free) {
                *g = dx[i] * bounds.scale[i] / norms[k];
            }
        }
        value / norms[k]
    };
    let record = |u: &[f64], value: f64| {
        constraints_at(u, gradients);
        let violation = cache
            .borrow()
            .values
            .iter()
            .zip(&norms)
            .map(|((g, _), norm)| {
                if g.is_nan() {
                    f64::INFINITY
                } else {
                    (-g / norm).max(0.0)
                }
            })
            .fold(0.0, f64::max);
        tracker.borrow_mut().record(u, value, violation);
    };
    let (outcome_u, converged) = match method {
        // Nothing to move (no capsules, or only pinned ones, and a fixed infill).
        _ if free.is_empty() => (u0.clone(), true),
        Method::Slsqp | Method::Hybrid => {
            let f = |u: &[f64], gradient: Option<&mut [f64]>, _: &mut ()| -> f64 {
                if cancelled() {
                    return flat(gradient);
                }
                let x = to_x(u);
                let value = match gradient {
                    Some(g) => {
                        let (value, dx) = objective.value_and_gradient(&x);
                        for (g, &i) in g.iter_mut().zip(&free) {
                            *g = dx[i] * bounds.scale[i];
                        }
                        value
                    }
                    None => objective.value(&x),
                };
                record(u, value);
                value
            };
            // SLSQP wants c(u) ≤ 0.
            let closures: Vec<Box<dyn slsqp::Func<()> + '_>> = (0..m)
                .map(|k| {
                    let constraint = &constraint;
                    Box::new(move |u: &[f64], gradient: Option<&mut [f64]>, _: &mut ()| {
                        let value = match gradient {
                            Some(g) => {
                                let value = constraint(u, k, Some(&mut *g));
                                g.iter_mut().for_each(|v| *v = -*v);
                                value
                            }
                            None => constraint(u, k, None),
                        };
                        -value
                    }) as Box<dyn slsqp::Func<()> + '_>
                })
                .collect();
            let cons: Vec<&dyn slsqp::Func<()>> = closures.iter().map(|c| c.as_ref()).collect();
            let tols = slsqp::StopTols {
                ftol_rel: budget.relative_tolerance,
                xtol_abs: vec![1e-9; u0.len()],
                ..Default::default()
            };
            // SLSQP stops when a line search fails, often far from a minimum; restarting from
            // the best point seen (with a fresh Hessian estimate) carries on until a restart
            // gains nothing.
            let mut start = u0.clone();
            let mut converged = false;
            let mut previous: Option<(f64, f64)> = None;
            loop {
                let used = tracker.borrow().evaluations;
                if used >= budget.evaluations || cancelled() {
                    break;
                }
                let outcome = slsqp::minimize(
                    f,
                    &start,
                    &u_bounds,
                    &cons,
                    (),
                    budget.evaluations - used,
                    Some(tols.clone()),
                );
                converged = outcome.is_ok();
                let Some((best, value, violation)) = tracker.borrow().best.clone() else {
                    break;
                };
                let gained = match previous {
                    None => true,
                    Some((v, c)) => {
                        value < v - budget.relative_tolerance * v.abs().max(1e-3)
                            || violation < c * 0.5
                    }
                };
                if converged || !gained {
                    break;
                }
                previous = Some((value, violation));
                start = best;
            }
            (start, converged)
        }
        Method::Cobyla => {
            let f = |u: &[f64], _: &mut ()| -> f64 {
                if cancelled() {
                    return 0.0;
                }
                let value = objective.value(&to_x(u));
                record(u, value);
                value
            };
            let closures: Vec<Box<dyn cobyla::Func<()> + '_>> = (0..m)
                .map(|k| {
                    let constraint = &constraint;
                    Box::new(move |u: &[f64], _: &mut ()| constraint(u, k, None))
                        as Box<dyn cobyla::Func<()> + '_>
                })
                .collect();
            let cons: Vec<&dyn cobyla::Func<()>> = closures.iter().map(|c| c.as_ref()).collect();
            let tols = cobyla::StopTols {
                ftol_rel: budget.relative_tolerance,
                xtol_abs: vec![1e-7; u0.len()],
                ..Default::default()
            };
            match cobyla::minimize(
                f,
                &u0,
                &u_bounds,
                &cons,
                (),
                budget.evaluations,
                cobyla::RhoBeg::All(0.05),
                Some(tols),
            ) {
                Ok((_, u, _)) => (u, true),
                Err((_, u, _)) => (u, false),
            }
        }
    };
    if !cancelled() {
        record(&outcome_u, objective.value(&to_x(&outcome_u)));
    }
    let tracker = tracker.into_inner();
    let (u, value, violation) = tracker.best.unwrap_or((u0, f64::INFINITY, f64::INFINITY));
    Solve {
        x: to_x(&u),
        value,
        violation,
        evaluations: tracker.evaluations,
        converged,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tracker() -> Tracker {
        Tracker {
            evaluations: 0,
            best: None,
            mark: None,
        }
    }

    #[test]
    fn a_run_stalls_after_a_window_of_gains_too_small_to_matter() {
        let mut creeping = tracker();
        for k in 0..100 {
            // Feasible, each point 1e-6 lower: better every time, never by enough.
            creeping.record(&[k as f64], 1.0 - 1e-6 * k as f64, 0.0);
        }
        assert!(creeping.stalled(99));
        assert!(!creeping.stalled(101));
        // The best point is still the last, lowest one.
        assert_eq!(creeping.best.as_ref().map(|b| b.1), Some(1.0 - 1e-6 * 99.0));

        let mut falling = tracker();
        for k in 0..100 {
            falling.record(&[k as f64], 1.0 - 1e-3 * k as f64, 0.0);
        }
        assert!(!falling.stalled(2));
    }

    #[test]
    fn a_run_outside_the_constraints_goes_on_while_the_violation_falls() {
        let mut nearing = tracker();
        for k in 0..100 {
            nearing.record(&[k as f64], 5.0, 1e-3 / (k + 1) as f64);
        }
        assert!(!nearing.stalled(2));
        // Then feasible, and nothing better after.
        nearing.record(&[100.0], 6.0, 0.0);
        for k in 0..10 {
            nearing.record(&[k as f64], 7.0, 0.0);
        }
        assert!(nearing.stalled(10));
        assert!(!nearing.stalled(11));
    }
}
