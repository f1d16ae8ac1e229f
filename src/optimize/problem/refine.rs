//! Refining an explored design into the one the judge weighs: the smooth program solved again
//! with its capsule term corrected towards the re-sliced material, the radii snapped to stock
//! balls, capsules the exact check finds too close to the surface moved or shrunk.

use super::{design_bounds, Explored, Outcome, Problem, StartCapsule};
use crate::balance::{component_material, ComponentBody};
use crate::design::Design;
use crate::fabrication::CapsuleIssue;
use crate::geometry::PrintCorrection;
use crate::objective::{DesignLayout, Objective, CAPSULE_STRIDE, R};
use crate::optimize::solver::{solve, Bounds, Solve, FEASIBLE, WORTH_HAVING};
use crate::optimize::stock::{capsule_radius, on_file_grid, snap};
use crate::parallel::map_each;

/// At most this many solves, after the first, with the closed-form capsule term corrected
/// towards the re-sliced material ([`Problem::corrected_bodies`]); as many again once the radii
/// are snapped to stock balls.
const CORRECTIONS: usize = 3;

/// A design whose objective corrected at the design itself is within this many degrees of the
/// one it was solved with is not solved again: a solve gains about what the correction moved
/// (the T's settled designs moved by 0.02-0.04° and gained at most 0.007°), for a solve and a
/// re-sliced cut (60 ms on the T).
const SETTLED_DEGREES: f64 = 0.1;

/// A design whose objective corrected at itself is above this many degrees (a goal missed by
/// that much) is not solved again: no correction of the material brings it within its goals,
/// and it is never chosen over one that meets them (the fish's five, two and one capsules miss
/// by 54-93°; settling them cost a fifth of its build).
const HOPELESS_DEGREES: f64 = 10.0;

/// Whether two sets of bodies have the same material within what moves no goal: volumes within
/// 1e-4 of each component's outer volume, first moments within that volume times 1e-4 of its
/// size (its cube root).
fn same_material(a: &[ComponentBody], b: &[ComponentBody]) -> bool {
    a.iter().zip(b).all(|(a, b)| {
        let volume = a.mass.volume.abs();
        let size = volume.cbrt();
        let moment =
            |body: &ComponentBody| body.print.solid.centroid.coords * body.print.solid.volume;
        (a.print.solid.volume - b.print.solid.volume).abs() <= 1e-4 * volume
            && (moment(a) - moment(b)).norm() <= 1e-4 * volume * size
    })
}

/// Whether solving `after` again from `x`, a solve's result over `before`, could gain nothing
/// worth having: the objective at `x` moves by less than [`WORTH_HAVING`] (to first order a
/// re-solved minimum moves by what its objective moves at the minimum), and no constraint that
/// holds at `x` fails, nor one that fails fails by more.
fn same_verdict(before: &Objective, after: &Objective, x: &[f64]) -> bool {
    (before.value(x) - after.value(x)).abs() < WORTH_HAVING
        && before
            .constraint_values(x)
            .iter()
            .zip(after.constraint_values(x))
            .all(|(&was, now)| now >= was.min(0.0))
}

/// A design the refinement settled on, weighed as the judge weighs it.
#[derive(Clone)]
struct Settled {
    /// The solve that reached it.
    solved: Solve,
    /// The judge's verdict on the design as the solution file would hold it, its capsules too
    /// close to the surface moved or shrunk ([`Problem::repaired`]), with its `value` the
    /// objective corrected at the design itself.
    outcome: Outcome,
}

/// Whether the judge prefers design `a` to `b`: one that meets every goal and can be printed to
/// one that does not, then the lower objective corrected at the design itself.
fn better(a: &Settled, b: &Settled) -> bool {
    (a.outcome.meets_goals, -a.outcome.value) > (b.outcome.meets_goals, -b.outcome.value)
}

/// How far, in all, the capsules with `issues` come closer to a surface than the wall allows.
fn surface_deficit(issues: &[CapsuleIssue]) -> f64 {
    issues
        .iter()
        .map(|issue| match *issue {
            CapsuleIssue::TooCloseToSurface {
                distance, required, ..
            } => (required - distance).max(0.0),
            _ => 0.0,
        })
        .sum()
}

impl<'a> Problem<'a> {
    /// Carries an explored design to the one the judge weighs, and judges it: the smooth
    /// program solved again with its capsule term corrected towards the re-sliced material,
    /// every radius snapped to a stock ball, the correction settled with the radii fixed, and
    /// any capsule the exact check finds too close to the surface moved or shrunk. Every design
    /// it checks is the one the solution file would hold (`on_file_grid`), so the outcome is
    /// that design's.
    pub fn refine(&self, explored: &Explored) -> Outcome {
        let Explored {
            start,
            layout,
            bounds,
            solved,
            ..
        } = explored;
        let start = start.as_slice();
        // The closed-form capsule term is the smooth stand-in for the material the judge weighs:
        // solve again with it corrected, snap the radii to stock balls, and settle the
        // correction with the radii fixed (a stock radius changes the material it was taken at).
        let (solved, objective) = self.corrected(layout, start, bounds, solved.clone());
        let (snapped, fixed) = self.snapped(&objective, layout, bounds, start, solved);
        let settled = self.settled(
            layout,
            start,
            fixed.as_ref().unwrap_or(bounds),
            snapped,
            objective,
        );
        let solved = &settled.solved;
        let mut outcome = settled.outcome;
        outcome.feasible = solved.violation <= FEASIBLE;
        outcome.evaluations = solved.evaluations;
        outcome
    }

    /// Solves the smooth program again from `solved` within `bounds`, its capsule term
    /// corrected towards the material the judge weighs (the design's voids cut from the print)
    /// by their difference at the solved design, and again from there, until the correction at
    /// the new design is the one it was solved with, or moves nothing a solve would count as a
    /// gain (`same_verdict`), at most [`CORRECTIONS`] times. The raster's cells make the
    /// material step as a void moves: the correction itself rarely settles (it moves by 1e-4 to
    /// 1e-3 of the volume from one solve to the next), the objective often does. Returns the
    /// last solve and the objective it was solved with.
    fn corrected(
        &self,
        layout: &DesignLayout,
        start: &[StartCapsule],
        bounds: &Bounds,
        solved: Solve,
    ) -> (Solve, Objective) {
        let budget = self.near_budget(layout);
        let to_design =
            |x: &[f64]| layout.to_design(x, &self.project.ball, self.project.infill.value);
        let corrected_at = |x: &[f64]| {
            let design = to_design(x);
            self.corrected_bodies(&design, &self.cut(&design))
        };
        let mut corrected = corrected_at(&solved.x);
        let mut objective = self.objective_over(&corrected, layout, start);
        let mut solved = solved;
        for correction in 1..=CORRECTIONS {
            let again = solve(&objective, &solved.x, bounds, self.method, budget.clone());
            solved = Solve {
                evaluations: solved.evaluations + again.evaluations,
                ..again
            };
            // After the last solve, or one that ended outside the constraints (a design the
            // judge shrinks: correcting its material again does not bring it inside them), the
            // rest is solved with the correction it was solved with.
            if correction == CORRECTIONS || solved.violation > FEASIBLE {
                break;
            }
            let next = corrected_at(&solved.x);
            let next_objective = self.objective_over(&next, layout, start);
            let settled = same_material(&corrected, &next)
                || same_verdict(&objective, &next_objective, &solved.x);
            (corrected, objective) = (next, next_objective);
            if settled {
                break;
            }
        }
        (solved, objective)
    }

    /// Weighs the design `solved` reached with `objective` (its radii on stock balls) as the
    /// judge does, and, while the objective corrected at that design itself differs from the
    /// one it was solved with by at least [`SETTLED_DEGREES`] there and by a gain worth having
    /// (`same_verdict`), and is below [`HOPELESS_DEGREES`], solves again with that correction
    /// within `bounds`, at most [`CORRECTIONS`] times. A solve with one correction can carry the
    /// design to where another holds (a capsule nearing the wall changes the difference), so of
    /// the designs reached, `solved`'s and those of later solves that end within the
    /// constraints, the one kept is one the judge finds meeting every goal if any does, and of
    /// those the one whose objective corrected at the design itself is the lowest.
    fn settled(
        &self,
        layout: &DesignLayout,
        start: &[StartCapsule],
        bounds: &Bounds,
        solved: Solve,
        objective: Objective,
    ) -> Settled {
        let budget = self.near_budget(layout);
        let weigh = |solved: Solve, objective: &Objective| {
            self.weighed(layout, start, bounds, solved, objective)
        };
        let mut evaluations = solved.evaluations;
        // Every design reached, with the objective corrected at it; the one before each was
        // solved with the objective of the one before it.
        let mut reached = vec![weigh(solved, &objective)];
        for _ in 0..CORRECTIONS {
            let used = match reached.len() {
                1 => &objective,
                n => &reached[n - 2].1,
            };
            let (last, own) = &reached[reached.len() - 1];
            let x = &last.solved.x;
            let value = last.outcome.value;
            if value > HOPELESS_DEGREES.to_radians()
                || (used.value(x) - value).abs() < SETTLED_DEGREES.to_radians()
                || same_verdict(used, own, x)
            {
                break;
            }
            let again = solve(own, x, bounds, self.method, budget.clone());
            evaluations += again.evaluations;
            if again.violation > FEASIBLE {
                break;
            }
            let next = weigh(again, own);
            reached.push(next);
        }
        let best = (0..reached.len())
            .reduce(|a, b| {
                if better(&reached[b].0, &reached[a].0) {
                    b
                } else {
                    a
                }
            })
            .unwrap_or(0);
        let (mut kept, _) = reached.swap_remove(best);
        kept.solved.evaluations = evaluations;
        kept
    }

    /// `outcome`, a design [`Problem::refine`] reached from `starts`, or the design reached from
    /// it with a smaller stock ball where the judge prefers that (`other_balls`),
    /// when the design has one movable capsule: its ball carries the whole design. For the one
    /// design a search settles on: every ball tried costs a judged design. Of 23 trials in
    /// designs with more capsules (the T, the fish, Spot and four real meshes) one won, by
    /// 0.02° in a design that misses its goals either way, and the T's three took 14 % of its
    /// build.
    pub fn with_other_balls(&self, starts: &[StartCapsule], outcome: Outcome) -> Outcome {
        let movable = starts.iter().filter(|c| !c.pinned).count();
        if !self.project.ball.is_listed()
            || movable != 1
            || starts.len() != outcome.design.capsules.len()
        {
            return outcome;
        }
        let start: Vec<StartCapsule> = starts.iter().map(|c| self.upright(c)).collect();
        let layout = DesignLayout::for_design(self.project, &outcome.design);
        let x = layout.to_vector(&outcome.design);
        let cut = self.cut(&outcome.design);
        let corrected = self.corrected_bodies(&outcome.design, &cut);
        let own = self.objective_over(&corrected, &layout, &start);
        // Every radius fixed, and the pinned capsules whole.
        let mut bounds = design_bounds(&own, self.meshes);
        for (i, (range, &value)) in bounds.range.iter_mut().zip(&x).enumerate() {
            let capsule = start.get(i / CAPSULE_STRIDE);
            if capsule.is_some_and(|c| c.pinned || i % CAPSULE_STRIDE == R) {
                *range = (value, value);
            }
        }
        let evaluations = outcome.evaluations;
        let kept = Settled {
            solved: Solve {
                x,
                value: outcome.value,
                violation: 0.0,
                evaluations: 0,
                converged: true,
            },
            outcome,
        };
        if kept.outcome.value > HOPELESS_DEGREES.to_radians() {
            return kept.outcome;
        }
        let kept = self.other_balls(&layout, &start, &bounds, kept, &corrected);
        let mut outcome = kept.outcome;
        outcome.evaluations = evaluations + kept.solved.evaluations;
        outcome
    }

    /// `kept`, or the design reached from it with a smaller stock ball in one of its capsules
    /// when the judge prefers that (`better`). For each unpinned capsule, the largest listed
    /// ball whose capsule is at least a bead (the extrusion width) narrower, if not below the
    /// smallest capsule: solved again from `kept` over `corrected` (the bodies corrected at
    /// `kept`) within `bounds` (every radius fixed), and weighed; the trials run side by side
    /// and are compared in capsule order. The judge's material is a stepped function of the
    /// design (layers, beads, regions the slicer fills solid) that the smooth program's
    /// correction, taken at one radius, cannot foresee: the sheared cylinder's part, its capsule
    /// solved for each ball, holds 8 % more plastic with a 22 mm ball than with a 13/16 in
    /// (20.6 mm) one, where the closed-form term expects 1 % less.
    fn other_balls(
        &self,
        layout: &DesignLayout,
        start: &[StartCapsule],
        bounds: &Bounds,
        kept: Settled,
        corrected: &[ComponentBody],
    ) -> Settled {
        let ball = &self.project.ball;
        let x = &kept.solved.x;
        // A ball that narrows the void by less than a bead leaves the layers around it much as
        // they were (the T's and the cylinder's such trials all lost).
        let bead = self.project.print.extrusion_width;
        let trials: Vec<(usize, f64)> = start
            .iter()
            .enumerate()
            .filter(|(_, capsule)| !capsule.pinned)
            .filter_map(|(j, _)| {
                let i = j * CAPSULE_STRIDE + R;
                let current = ball.radius_for(x[i])?;
                ball.smaller(current)
                    .map(|smaller| capsule_radius(ball, smaller, self.scale))
                    .find(|&radius| radius <= x[i] - bead)
                    .filter(|&radius| radius >= self.parameters().min_radius)
                    .map(|radius| (i, radius))
            })
            .collect();
        let budget = self.near_budget(layout);
        let reached = map_each(trials.len(), |t| {
            let (i, radius) = trials[t];
            // Each trial's own objective: an objective is not shared between threads.
            let own = self.objective_over(corrected, layout, start);
            let mut trial = x.clone();
            trial[i] = radius;
            let mut fixed = bounds.clone();
            fixed.range[i] = (radius, radius);
            let again = solve(&own, &trial, &fixed, self.method, budget.clone());
            let evaluations = again.evaluations;
            let weighed = (again.violation <= FEASIBLE)
                .then(|| self.weighed(layout, start, &fixed, again, &own).0);
            (weighed, evaluations)
        });
        let mut kept = kept;
        let mut evaluations = 0;
        for (weighed, spent) in reached {
            evaluations += spent;
            if let Some(reached) = weighed.filter(|reached| better(reached, &kept)) {
                kept = reached;
            }
        }
        kept.solved.evaluations = evaluations;
        kept
    }

    /// The design `solved` reached with `objective` within `bounds`, weighed as the judge weighs
    /// it (as the solution file would hold it, [`Problem::repaired`]), and the objective
    /// corrected at that design itself.
    fn weighed(
        &self,
        layout: &DesignLayout,
        start: &[StartCapsule],
        bounds: &Bounds,
        solved: Solve,
        objective: &Objective,
    ) -> (Settled, Objective) {
        let design = self.design_at(layout, start, &solved.x);
        let feasible = solved.violation <= FEASIBLE;
        let (design, fabrication) =
            self.repaired(layout, start, bounds, objective, design, feasible);
        let cut = self.cut(&design);
        let own = self.objective_over(&self.corrected_bodies(&design, &cut), layout, start);
        let x = layout.to_vector(&design);
        let mut outcome = self.judge(design, fabrication, &cut);
        outcome.value = own.value(&x);
        (Settled { solved, outcome }, own)
    }

    /// `design` (as the solution file holds it, from a solve that ended within the constraints
    /// when `feasible`) with its capsules that the fabrication checks find too close to the
    /// surface moved (solved again with `objective` within `bounds` as if wider) or shrunk, and
    /// the fabrication issues left.
    fn repaired(
        &self,
        layout: &DesignLayout,
        start: &[StartCapsule],
        bounds: &Bounds,
        objective: &Objective,
        mut design: Design,
        feasible: bool,
    ) -> (Design, Vec<CapsuleIssue>) {
        // The grid's interpolant can overestimate the distance to a sharp feature by a fraction
        // of a cell: shrink any capsule that came too close, by the exact deficit, and check
        // again. A stock radius cannot shrink by a fraction of a cell, only to the next smaller
        // ball: first the capsules are moved instead (up to three times), solved again as if
        // wider by their deficit. A deficit past a cell is not the interpolant's but a solve
        // that ended outside the constraints; solving again from there rarely mends it and costs
        // as much as the solve, so such a capsule is only shrunk. Moving and shrinking are
        // decided by the fabrication checks alone: only the design they end at is judged.
        let mut fabrication = self.fabrication(&design);
        let listed = self.project.ball.is_listed();
        let mut widening = vec![0.0; start.len()];
        // Whether moving capsules still mends them: a move that leaves more of them too close,
        // or closer in all, is undone, and they are shrunk from then on. A move that leaves them
        // as close is kept: the checked designs are on the file's grid, where distances to a
        // flat face come in its steps and often tie, and the next move widens the capsule it
        // left too close on top of the first's (three capsules in the T printed on its foot
        // meet every goal only after a third move). A design whose solve ended outside the
        // constraints is not the interpolant's to mend either: it is only shrunk (moving the
        // fish's five capsules cost two full solves, 1 s of its 4, and mended nothing).
        let mut moves_mend = feasible;
        for attempt in 0..4 {
            let move_first = listed && attempt < 3 && moves_mend;
            let mut shrunk = design.clone();
            let (mut changed, mut moving) = (false, false);
            for issue in &fabrication {
                if let CapsuleIssue::TooCloseToSurface {
                    capsule,
                    distance,
                    required,
                    ..
                } = *issue
                {
                    if start.get(capsule).is_none_or(|s| s.pinned) {
                        continue;
                    }
                    let c = &mut shrunk.capsules[capsule];
                    // Past the limit by what rounding a moved capsule's ends onto the file's grid
                    // may take; a narrowed one keeps its ends (on the grid already) and the same
                    // margin, as the smooth constraints keep it.
                    let deficit = (required - distance) * 1.01
                        + 1e-9 * c.radius.abs()
                        + self.rounding_slack();
                    if move_first && required - distance <= self.grid_cell(c.component) {
                        widening[capsule] += deficit;
                        moving = true;
                        continue;
                    }
                    let mut radius = c.radius - deficit;
                    let Some(ball) = self.project.ball.radius_for(radius) else {
                        continue;
                    };
                    if listed {
                        radius = capsule_radius(&self.project.ball, ball, self.scale);
                    }
                    c.radius = radius;
                    c.ball_radius = ball;
                    changed = true;
                }
            }
            if !changed && !moving {
                break;
            }
            // A capsule shrunk beside one moved is shrunk at a later attempt, if still too close
            // where the move left it.
            if moving {
                let moved = self.moved(objective, bounds, layout, &design, &widening);
                let moved = self.written(moved, start);
                let issues = self.fabrication(&moved);
                if issues.len() <= fabrication.len()
                    && surface_deficit(&issues) <= surface_deficit(&fabrication)
                {
                    (design, fabrication) = (moved, issues);
                } else {
                    moves_mend = false;
                }
                continue;
            }
            design = self.written(shrunk, start);
            fabrication = self.fabrication(&design);
        }
        (design, fabrication)
    }

    /// The design the solution file would hold for the design vector `x` laid out as `layout`:
    /// each capsule with the stock ball that fits it, the capsules pinned in `start` as they
    /// are, on the file's grid ([`Problem::written`]).
    fn design_at(&self, layout: &DesignLayout, start: &[StartCapsule], x: &[f64]) -> Design {
        let mut design = layout.to_design(x, &self.project.ball, self.project.infill.value);
        for (capsule, started) in design.capsules.iter_mut().zip(start) {
            if let Some(ball) = self.project.ball.radius_for(capsule.radius) {
                capsule.ball_radius = ball;
            }
            if started.pinned {
                capsule.from = started.from;
                capsule.to = started.to;
                capsule.radius = started.radius;
            }
        }
        self.written(design, start)
    }

    /// The bodies of the smooth objective near `design`: each component's bare material, plus
    /// for one with capsules the difference between its material with `design`'s voids cut
    /// (`cut`, [`Problem::cut`]) and the closed-form capsule term at `design`, as a correction
    /// of its solid part.
    fn corrected_bodies(&self, design: &Design, cut: &[ComponentBody]) -> Vec<ComponentBody<'a>> {
        self.bodies
            .iter()
            .zip(cut)
            .enumerate()
            .map(|(index, (bare, cut))| {
                if !design.capsules.iter().any(|c| c.component == index) {
                    return *bare;
                }
                let truth = component_material(self.project, cut, design, index);
                let surrogate = component_material(self.project, bare, design, index);
                let correction = PrintCorrection::default().plus_difference(&truth, &surrogate);
                match correction.apply(&bare.print) {
                    Some(print) => ComponentBody { print, ..*bare },
                    None => *bare,
                }
            })
            .collect()
    }

    /// `design` as the solution file holds it ([`on_file_grid`]), the capsules pinned in
    /// `start` as they are.
    fn written(&self, design: Design, start: &[StartCapsule]) -> Design {
        let pinned: Vec<bool> = start.iter().map(|c| c.pinned).collect();
        let ranged = self.project.infill.range.is_some();
        on_file_grid(design, &pinned, &self.project.ball, self.scale, ranged)
    }

    /// `design` with its capsules' ends and the infill solved again from where they are, every
    /// radius fixed and each capsule seen by the constraints as `widening` wider than it is (so
    /// that it keeps that much further from the surface); radii and balls stay `design`'s.
    fn moved(
        &self,
        objective: &Objective,
        bounds: &Bounds,
        layout: &DesignLayout,
        design: &Design,
        widening: &[f64],
    ) -> Design {
        let mut x = layout.to_vector(design);
        let mut fixed = bounds.clone();
        for (j, extra) in widening.iter().enumerate() {
            let i = j * CAPSULE_STRIDE + R;
            x[i] += extra;
            fixed.range[i] = (x[i], x[i]);
        }
        let again = solve(objective, &x, &fixed, self.method, self.near_budget(layout));
        let mut moved = layout.to_design(&again.x, &self.project.ball, self.project.infill.value);
        for (capsule, kept) in moved.capsules.iter_mut().zip(&design.capsules) {
            capsule.radius = kept.radius;
            capsule.ball_radius = kept.ball_radius;
        }
        moved
    }

    /// `solved` with the radius of every unpinned capsule snapped to a stock ball plus the
    /// clearance ([`snap`]; the larger ball only when it breaks no constraint the smaller keeps),
    /// then those radii fixed and everything else solved again from there; the snapped point
    /// itself when the second solve ends at a higher objective; with `bounds` with those radii
    /// fixed. `solved` itself, and no bounds, when balls come in any size.
    fn snapped(
        &self,
        objective: &Objective,
        layout: &DesignLayout,
        bounds: &Bounds,
        start: &[StartCapsule],
        solved: Solve,
    ) -> (Solve, Option<Bounds>) {
        let ball = &self.project.ball;
        if !ball.is_listed() || start.iter().all(|c| c.pinned) {
            return (solved, None);
        }
        let mut x = solved.x.clone();
        let mut fixed = bounds.clone();
        for (j, capsule) in start.iter().enumerate() {
            let i = j * CAPSULE_STRIDE + R;
            if capsule.pinned {
                continue;
            }
            let with = |radius: f64| {
                let mut trial = x.clone();
                trial[i] = radius;
                objective.constraint_values(&trial)
            };
            let allowed = |larger: f64| {
                let lower = ball
                    .radius_for(x[i])
                    .map_or(0.0, |b| capsule_radius(ball, b, self.scale));
                larger <= bounds.range[i].1
                    && with(larger)
                        .iter()
                        .zip(with(lower))
                        .all(|(g, kept)| *g >= 0.0 || *g >= kept)
            };
            let Some((radius, _)) = snap(ball, x[i], self.scale, allowed) else {
                continue;
            };
            x[i] = radius;
            fixed.range[i] = (radius, radius);
        }
        // The snapped point itself, evaluated as a solve with nothing free: the second solve
        // prefers a smaller constraint violation to a lower objective, and from a point just
        // outside the constraints it can drift far from the design the first solve found.
        let pinned = Bounds {
            range: x.iter().map(|&v| (v, v)).collect(),
            ..bounds.clone()
        };
        let budget = self.near_budget(layout);
        let at_snap = solve(objective, &x, &pinned, self.method, budget.clone());
        let again = solve(objective, &x, &fixed, self.method, budget);
        let evaluations = solved.evaluations + at_snap.evaluations + again.evaluations;
        let best = if at_snap.value < again.value {
            at_snap
        } else {
            again
        };
        (
            Solve {
                evaluations,
                ..best
            },
            Some(fixed),
        )
    }
}
