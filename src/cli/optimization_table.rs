//! What the optimizer did, as `ballast build` prints it before the summary: every capsule count
//! tried, the choice, the random-start ranking, the conflicting goals and the stage times.

use std::fmt::Write;

use super::table::plural;
use crate::compile::{Compilation, Optimization, Starts};

/// What the optimizer did: every capsule count tried (the chosen one marked), the stage times
/// (with the meshes whose precomputation was read `from_disk`), the random-start ranking when
/// asked for, and the conflicting goals when some goal is missed.
pub fn optimization(
    optimization: &Optimization,
    compilation: &Compilation,
    from_disk: usize,
) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "optimized from {}; {} capsule count{} tried",
        started_from(&optimization.starts),
        optimization.candidates.len(),
        plural(optimization.candidates.len()),
    );
    let _ = writeln!(out, "  capsules  objective  worst tilt  goals        time");
    let mut marked = false;
    for candidate in &optimization.candidates {
        let chosen = !marked && candidate.capsules == optimization.chosen;
        marked |= chosen;
        let tilt = candidate
            .worst_tilt_margin
            .map_or("-".to_string(), |t| format!("{t:.2}"));
        let _ = writeln!(
            out,
            "{} {:>7}  {:>9.3}  {:>10}  {:<11} {:>6.2} s",
            if chosen { "*" } else { " " },
            candidate.capsules,
            candidate.objective,
            tilt,
            if candidate.meets_goals {
                "all met"
            } else if !candidate.printable {
                "unprintable"
            } else {
                "not all"
            },
            candidate.seconds,
        );
    }
    let rule = chosen_rule(optimization);
    let _ = writeln!(out, "  * chosen: {rule}");
    if optimization.rescue_starts > 0 {
        let _ = writeln!(
            out,
            "  no count met every goal from the seeds: {} random start{} tried, kept only where one met them all",
            optimization.rescue_starts,
            plural(optimization.rescue_starts),
        );
    }
    for ranking in &optimization.exhaustive {
        let _ = writeln!(
            out,
            "  {} capsule{}: the heuristic ranks {} of {} random starts (best random objective {:.3}, heuristic {:.3}; {} met every goal)",
            ranking.capsules,
            plural(ranking.capsules),
            ranking.rank,
            ranking.starts + 1,
            ranking.best_objective,
            ranking.heuristic_objective,
            ranking.meeting_goals,
        );
    }
    if optimization.conflicts_cut_short {
        let _ = writeln!(
            out,
            "  the explanation of the goals not met was cut short: {} found before it stopped{}",
            optimization.conflicts.len(),
            if optimization.conflicts.is_empty() {
                ""
            } else {
                ", listed below"
            }
        );
    }
    if !optimization.conflicts.is_empty() {
        let _ = writeln!(out, "  no design met every goal:");
        for conflict in &optimization.conflicts {
            let goals: Vec<String> = conflict
                .goals
                .iter()
                .map(|g| format!("`{}` in pose \"{}\"", g.kind, g.pose))
                .collect();
            let what = if goals.len() == 1 {
                format!("{} cannot be met even alone", goals[0])
            } else {
                format!("{} conflict", goals.join(" and "))
            };
            let _ = writeln!(
                out,
                "    {what}: the best design for {} falls short by about {:.2}°",
                if goals.len() == 1 { "it" } else { "both" },
                conflict.shortfall.max(0.0),
            );
        }
    }
    let timings = &optimization.timings;
    // Looking for conflicts runs whenever no design meets every goal, and can take longer than
    // the search: its time is shown even when it names none.
    let explained = !optimization.meets_goals && optimization.interrupted.is_none();
    let _ = writeln!(
        out,
        "  time: precompute {:.2} s{}, heuristic {:.2} s{}{}",
        timings.precompute,
        if from_disk == 0 {
            String::new()
        } else {
            format!(
                " ({from_disk} mesh{} from the disk cache)",
                if from_disk == 1 { "" } else { "es" }
            )
        },
        timings.heuristic,
        if optimization.exhaustive.is_empty() {
            String::new()
        } else {
            format!(", exhaustive {:.2} s", timings.exhaustive)
        },
        if !explained && optimization.conflicts.is_empty() && !optimization.conflicts_cut_short {
            String::new()
        } else {
            format!(", conflicts {:.2} s", timings.conflicts)
        },
    );
    let _ = compilation;
    out.push('\n');
    out
}

/// Where the capsules the search started from came from, e.g. "3 written seeds and 1 pinned
/// capsule".
fn started_from(starts: &Starts) -> String {
    let count = |n: usize, what: &str| format!("{n} {what}{}", plural(n));
    let mut parts = Vec::new();
    if starts.written > 0 {
        parts.push(count(starts.written, "written seed"));
    }
    if starts.skeleton > 0 {
        parts.push(count(starts.skeleton, "skeleton seed"));
    }
    if starts.earlier > 0 {
        parts.push(format!(
            "the previous build's {}",
            count(starts.earlier, "capsule")
        ));
    }
    if starts.pinned > 0 {
        parts.push(count(starts.pinned, "pinned capsule"));
    }
    match parts.split_last() {
        None => "no capsule (no skeleton segment lies deep enough, in a part with room for the smallest capsule that holds a ball, to seed one)".to_string(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
    }
}

/// Why the chosen capsule count was chosen, saying plainly when it misses some goal.
fn chosen_rule(optimization: &Optimization) -> String {
    match (optimization.requested, optimization.meets_goals) {
        (Some(n), true) => format!("{n} capsule{} as asked", plural(n)),
        (Some(n), false) => format!(
            "{n} capsule{} as asked; it does not meet every goal",
            plural(n)
        ),
        (None, true) => format!(
            "the design meeting every goal with the lowest objective plus {}° per capsule \
             (`optimize tolerance=`): each capsule must gain that much",
            optimization.tolerance
        ),
        (None, false) => {
            "no design meets every goal, so the one with the lowest objective".to_string()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compile::Timings;

    fn optimization(requested: Option<usize>, meets_goals: bool) -> Optimization {
        Optimization {
            requested,
            chosen: 2,
            meets_goals,
            tolerance: 1.0,
            warm_started: false,
            candidates: Vec::new(),
            seeds: Vec::new(),
            starts: Starts::default(),
            exhaustive: Vec::new(),
            conflicts: Vec::new(),
            conflicts_cut_short: false,
            rescue_starts: 0,
            timings: Timings::default(),
            interrupted: None,
            origins: Vec::new(),
            warnings: Vec::new(),
        }
    }

    #[test]
    fn the_first_line_says_where_the_start_capsules_came_from() {
        let starts = |pinned, written, skeleton, earlier| {
            started_from(&Starts {
                pinned,
                written,
                skeleton,
                earlier,
            })
        };
        assert_eq!(starts(0, 0, 5, 0), "5 skeleton seeds");
        assert_eq!(starts(1, 2, 0, 0), "2 written seeds and 1 pinned capsule");
        assert_eq!(
            starts(2, 0, 0, 1),
            "the previous build's 1 capsule and 2 pinned capsules"
        );
        assert_eq!(starts(1, 0, 3, 0), "3 skeleton seeds and 1 pinned capsule");
        assert!(starts(0, 0, 0, 0).starts_with("no capsule"));
    }

    #[test]
    fn the_chosen_rule_says_when_no_design_meets_every_goal() {
        assert_eq!(
            chosen_rule(&optimization(None, true)),
            "the design meeting every goal with the lowest objective plus 1° per capsule \
             (`optimize tolerance=`): each capsule must gain that much"
        );
        let missed = chosen_rule(&optimization(None, false));
        assert_eq!(
            missed,
            "no design meets every goal, so the one with the lowest objective"
        );
        assert!(!missed.contains("that meets every goal"));
        assert_eq!(
            chosen_rule(&optimization(Some(2), true)),
            "2 capsules as asked"
        );
        assert_eq!(
            chosen_rule(&optimization(Some(2), false)),
            "2 capsules as asked; it does not meet every goal"
        );
    }
}
