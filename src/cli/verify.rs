//! `ballast verify`: every goal re-measured by a rigid-body simulation, printed beside the
//! computed value.

use std::fmt::Write;
use std::path::Path;

use super::{compile_file, file_name, MessageFormat, EXIT_INVALID, EXIT_MET, EXIT_UNMET};
use crate::compile::{CompileOptions, Workspace};
use crate::verify::{verify, BallEnd, Detail, FinalState, GoalCheck, Verification};

/// Verifies the project at `path`; prints the table, or the verification as JSON when `json`.
pub fn run(path: &Path, json: bool, options: &CompileOptions) -> i32 {
    let Ok(compilation) = compile_file(path, options, &mut Workspace::new(), MessageFormat::Human)
    else {
        return EXIT_INVALID;
    };
    let verification = verify(&compilation);
    if json {
        match serde_json::to_string_pretty(&verification) {
            Ok(text) => println!("{text}"),
            Err(error) => {
                eprintln!("error: cannot encode the verification: {error}");
                return EXIT_INVALID;
            }
        }
    } else {
        let names: Vec<&str> = compilation
            .design
            .capsules
            .iter()
            .map(|capsule| capsule.name.as_str())
            .collect();
        print!("{}", table(&verification, &file_name(path), &names));
    }
    if verification.agrees() {
        EXIT_MET
    } else {
        EXIT_UNMET
    }
}

/// The table: per pose, per goal, computed beside measured, then what the simulation saw.
fn table(verification: &Verification, project_name: &str, capsules: &[&str]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{project_name}: simulated with a rigid-body engine; angles in degrees"
    );
    let (mut total, mut agree) = (0, 0);
    for pose in &verification.poses {
        let _ = writeln!(out, "\npose \"{}\"", pose.pose);
        for goal in &pose.goals {
            total += 1;
            agree += usize::from(goal.agrees);
            goal_lines(&mut out, goal, capsules);
        }
    }
    let _ = writeln!(
        out,
        "\n{agree} of {total} goal{} agree{} with the simulation.",
        if total == 1 { "" } else { "s" },
        if agree == 1 { "s" } else { "" }
    );
    out
}

fn goal_lines(out: &mut String, goal: &GoalCheck, capsules: &[&str]) {
    let (kind, measured) = match &goal.detail {
        Detail::Stand { runs, .. } => (
            "stand",
            match goal.measured {
                Some(value) => format!("{value:.1}"),
                None if runs.is_empty() => "topples when set down".to_string(),
                None => "stands at every tilt tried".to_string(),
            },
        ),
        Detail::Imbalance { topples, .. } => (
            "imbalance",
            match goal.measured {
                Some(value) => format!("{value:.1}"),
                None if *topples => "stands on no slope tried".to_string(),
                None => "stands".to_string(),
            },
        ),
        Detail::Suspend { .. } => ("suspend", angle(goal.measured)),
        Detail::Immerse { .. } => ("immerse", angle(goal.measured)),
    };
    let verdict = match &goal.disagreement {
        None => "agrees".to_string(),
        Some(why) => format!("DISAGREES: {why}"),
    };
    let _ = writeln!(
        out,
        "  {kind:<10} computed {:>6.1}   simulated {measured:<8} {verdict}",
        goal.computed
    );
    match &goal.detail {
        Detail::Stand { runs, .. } => {
            direction_line(out, "toppled at", runs.iter().map(|run| run.topples_at))
        }
        Detail::Imbalance { slopes, .. } => direction_line(
            out,
            "stood from a slope of",
            slopes.iter().map(|run| run.stands_from),
        ),
        Detail::Suspend { states, .. } | Detail::Immerse { states, .. } => {
            for (index, state) in states.iter().enumerate() {
                let _ = writeln!(
                    out,
                    "    {} {}",
                    if index == 0 {
                        "settles at"
                    } else {
                        "also at   "
                    },
                    state_line(state, capsules)
                );
            }
        }
    }
}

fn angle(value: Option<f64>) -> String {
    value.map_or("-".to_string(), |value| format!("{value:.1}"))
}

/// One final state: its angle, where the balls are, and the releases that ended there.
fn state_line(state: &FinalState, capsules: &[&str]) -> String {
    let balls: Vec<String> = state
        .balls
        .iter()
        .zip(capsules)
        .map(|(end, name)| {
            let end = match end {
                BallEnd::From => "`from` end",
                BallEnd::To => "`to` end",
                BallEnd::Between => "between its ends",
            };
            format!("ball `{name}` at its {end}")
        })
        .collect();
    let balls = if balls.is_empty() {
        String::new()
    } else {
        format!(", {}", balls.join(", "))
    };
    format!(
        "{:.1}{balls}; released from: {}",
        state.angle,
        state.releases.join(", ")
    )
}

/// One line of per-direction values, degrees (`-` where a direction gave none), after `what`;
/// nothing when no direction was tried.
fn direction_line(out: &mut String, what: &str, values: impl Iterator<Item = Option<f64>>) {
    let values: Vec<String> = values
        .map(|value| match value {
            Some(value) => format!("{value:.1}"),
            None => "-".to_string(),
        })
        .collect();
    if !values.is_empty() {
        let _ = writeln!(
            out,
            "    {what} (worst direction first, then every 30° around) {}",
            values.join(" ")
        );
    }
}
