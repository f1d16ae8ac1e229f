//! What changed between two good builds, in a few lines: goals now met or broken, the capsule
//! count, the worst tilt margin.

use crate::balance::GoalOutcome;
use crate::compile::Compilation;

/// The facts of a good build that the watch summary compares.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Every goal of every pose, in project order.
    pub goals: Vec<GoalState>,
    /// Capsules in the design.
    pub capsules: usize,
    /// The smallest tilt margin over the poses with a `stand` goal, degrees; `None` without one.
    pub worst_tilt_margin: Option<f64>,
}

/// One goal's identity and verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct GoalState {
    /// The pose's name.
    pub pose: String,
    /// The goal's index within its pose.
    pub index: usize,
    /// The goal's node name: `stand`, `imbalance`, `suspend` or `immerse`.
    pub kind: &'static str,
    /// Whether it holds.
    pub met: bool,
}

impl Snapshot {
    /// The facts of `compilation`.
    pub fn new(compilation: &Compilation) -> Snapshot {
        let mut goals = Vec::new();
        let mut worst: Option<f64> = None;
        for pose in &compilation.poses {
            for (index, goal) in pose.goals.iter().enumerate() {
                goals.push(GoalState {
                    pose: pose.pose.clone(),
                    index,
                    kind: kind(&goal.outcome),
                    met: goal.met,
                });
                if let GoalOutcome::Stand { tilt_margin, .. } = goal.outcome {
                    worst = Some(worst.map_or(tilt_margin, |w| w.min(tilt_margin)));
                }
            }
        }
        Snapshot {
            goals,
            capsules: compilation.design.capsules.len(),
            worst_tilt_margin: worst,
        }
    }

    /// How many goals hold, and how many there are.
    pub fn goals_met(&self) -> (usize, usize) {
        (
            self.goals.iter().filter(|goal| goal.met).count(),
            self.goals.len(),
        )
    }
}

fn kind(outcome: &GoalOutcome) -> &'static str {
    match outcome {
        GoalOutcome::Stand { .. } => "stand",
        GoalOutcome::Imbalance { .. } => "imbalance",
        GoalOutcome::Suspend { .. } => "suspend",
        GoalOutcome::Immerse { .. } => "immerse",
    }
}

/// One line per difference from `before` to `after`: goals now met, goals now broken, goals new
/// to the project (or gone from it), the capsule count, the worst tilt margin (when it moved by
/// 0.05° or more). Empty when nothing shown changed. A goal is the same goal when its pose, its
/// index in the pose and its kind are.
pub fn differences(before: &Snapshot, after: &Snapshot) -> Vec<String> {
    let mut lines = Vec::new();
    let same =
        |a: &GoalState, b: &GoalState| a.pose == b.pose && a.index == b.index && a.kind == b.kind;
    for goal in &after.goals {
        let name = format!("`{}` in pose \"{}\"", goal.kind, goal.pose);
        match before.goals.iter().find(|old| same(old, goal)) {
            Some(old) if old.met == goal.met => {}
            Some(_) if goal.met => lines.push(format!("now met: {name}")),
            Some(_) => lines.push(format!("now broken: {name}")),
            None => lines.push(format!(
                "new goal: {name}, {}",
                if goal.met { "met" } else { "not met" }
            )),
        }
    }
    for old in &before.goals {
        if !after.goals.iter().any(|goal| same(old, goal)) {
            lines.push(format!(
                "goal gone: `{}` in pose \"{}\"",
                old.kind, old.pose
            ));
        }
    }
    if before.capsules != after.capsules {
        lines.push(format!(
            "capsules: {} -> {}",
            before.capsules, after.capsules
        ));
    }
    match (before.worst_tilt_margin, after.worst_tilt_margin) {
        (Some(a), Some(b)) if (a - b).abs() >= 0.05 => lines.push(format!(
            "worst tilt margin: {a:.1} -> {b:.1} ({:+.1})",
            b - a
        )),
        (None, Some(b)) => lines.push(format!("worst tilt margin: {b:.1}")),
        (Some(a), None) => lines.push(format!("worst tilt margin: {a:.1} -> none (no stand goal)")),
        _ => {}
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    fn goal(pose: &str, index: usize, met: bool) -> GoalState {
        GoalState {
            pose: pose.to_string(),
            index,
            kind: "stand",
            met,
        }
    }

    fn snapshot(goals: Vec<GoalState>, capsules: usize, tilt: Option<f64>) -> Snapshot {
        Snapshot {
            goals,
            capsules,
            worst_tilt_margin: tilt,
        }
    }

    #[test]
    fn nothing_changed_gives_no_lines() {
        let a = snapshot(vec![goal("up", 0, true)], 1, Some(10.0));
        assert!(differences(&a, &a.clone()).is_empty());
        let nudged = snapshot(vec![goal("up", 0, true)], 1, Some(10.01));
        assert!(differences(&a, &nudged).is_empty());
    }

    #[test]
    fn goals_met_broken_new_and_gone_are_named() {
        let before = snapshot(
            vec![
                goal("up", 0, true),
                goal("side", 0, false),
                goal("old", 0, true),
            ],
            2,
            Some(5.0),
        );
        let after = snapshot(
            vec![
                goal("up", 0, false),
                goal("side", 0, true),
                goal("new", 0, true),
            ],
            1,
            Some(-3.0),
        );
        assert_eq!(
            differences(&before, &after),
            vec![
                "now broken: `stand` in pose \"up\"",
                "now met: `stand` in pose \"side\"",
                "new goal: `stand` in pose \"new\", met",
                "goal gone: `stand` in pose \"old\"",
                "capsules: 2 -> 1",
                "worst tilt margin: 5.0 -> -3.0 (-8.0)",
            ]
        );
    }

    #[test]
    fn counts_goals_met() {
        let s = snapshot(vec![goal("a", 0, true), goal("a", 1, false)], 0, None);
        assert_eq!(s.goals_met(), (1, 2));
    }
}
