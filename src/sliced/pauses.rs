//! The planned pauses against the file's.
//!
//! The whole bed pauses at once, so the plan's pauses of every component after the same layer
//! are one pause of the file. Such a pause is as planned when it comes right after the planned
//! layer (as many layers printed before it, the last at the planned height) and its message is
//! the planned one (or, for pauses of several components merged, holds each planned message).
//! A pause of the file that no plan asks for is a failure too.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::fabrication::PrintPlan;
use crate::gcode::{Outline, PauseMark};

/// A pause as the plan has it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlannedPause {
    /// Layers printed before it.
    pub layers_done: usize,
    /// Top of the last layer printed before it, project units.
    pub height: f64,
    /// Top of the first layer printed after it, project units.
    pub resume_height: f64,
    /// The messages of the plan's pauses at this layer, one per component pausing there.
    pub messages: Vec<String>,
}

/// A pause as the file has it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FoundPause {
    /// Line of the pause command.
    pub line: usize,
    /// Layers printed before it.
    pub layers_done: usize,
    /// Nozzle height of the last layer printed before it, project units; `None` before any.
    pub height: Option<f64>,
    /// Nozzle height of the first layer printed after it, project units; `None` when none is.
    pub resume_height: Option<f64>,
    /// The `M117` message shown with it, if any.
    pub message: Option<String>,
}

/// One pause: planned, found, or both, and what is wrong with it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PauseCheck {
    /// The plan's pause; `None` for a pause the plan does not have.
    pub planned: Option<PlannedPause>,
    /// The file's pause after the planned layer; `None` when there is none.
    pub found: Option<FoundPause>,
    /// What is wrong, in words; `None` when the pause is as planned.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub problem: Option<String>,
}

/// Every planned pause of `plan` against the pauses of `program` (heights `mm` project units
/// per mm); two heights are one when they differ by less than a quarter of the plan's layer
/// height.
pub(super) fn check(plan: &PrintPlan, program: &Outline, mm: f64) -> Vec<PauseCheck> {
    let layer_height = plan.layer_height;
    let mut planned: BTreeMap<usize, PlannedPause> = BTreeMap::new();
    for pause in plan.components.iter().flat_map(|c| &c.pauses) {
        planned
            .entry(pause.layers_done)
            .or_insert_with(|| PlannedPause {
                layers_done: pause.layers_done,
                height: pause.height,
                resume_height: pause.resume_height,
                messages: Vec::new(),
            })
            .messages
            .push(pause.message.clone());
    }
    let found: Vec<FoundPause> = program
        .pauses
        .iter()
        .map(|mark: &PauseMark| FoundPause {
            line: mark.line,
            layers_done: mark.layers_done,
            height: mark.height.map(|z| z * mm),
            resume_height: mark.resume_height.map(|z| z * mm),
            message: mark.message.clone(),
        })
        .collect();
    let mut used = vec![false; found.len()];
    let mut checks = Vec::new();
    for pause in planned.into_values() {
        let at = (0..found.len()).find(|&i| !used[i] && found[i].layers_done == pause.layers_done);
        let problem = match at {
            None => Some(missing(&pause, &found)),
            Some(i) => {
                used[i] = true;
                mismatch(&pause, &found[i], layer_height)
            }
        };
        checks.push(PauseCheck {
            found: at.map(|i| found[i].clone()),
            planned: Some(pause),
            problem,
        });
    }
    for (pause, _) in found.into_iter().zip(used).filter(|(_, used)| !used) {
        let problem = format!(
            "the file pauses after layer {} ({}, line {}), which the plan does not",
            pause.layers_done,
            height_words(pause.height),
            pause.line
        );
        checks.push(PauseCheck {
            planned: None,
            found: Some(pause),
            problem: Some(problem),
        });
    }
    checks
}

/// The planned `pause` is not in the file (whose pauses are `found`).
fn missing(pause: &PlannedPause, found: &[FoundPause]) -> String {
    let nearest = found
        .iter()
        .min_by_key(|f| f.layers_done.abs_diff(pause.layers_done))
        .map_or(String::new(), |f| {
            format!(
                "; the nearest pause in the file is after layer {}",
                f.layers_done
            )
        });
    format!(
        "no pause after layer {} (height {:.2}) for \"{}\"{nearest}",
        pause.layers_done,
        pause.height,
        pause.messages.join("\", \"")
    )
}

/// What differs between the planned `pause` and the `found` one after the same layer.
fn mismatch(pause: &PlannedPause, found: &FoundPause, layer_height: f64) -> Option<String> {
    let mut problems = Vec::new();
    if found
        .height
        .is_none_or(|h| (h - pause.height).abs() > layer_height / 4.0)
    {
        problems.push(format!(
            "the last layer before it is at {}, planned at {:.2} (the file's layers are not the \
             plan's)",
            height_words(found.height),
            pause.height
        ));
    }
    if found
        .resume_height
        .is_some_and(|h| (h - pause.resume_height).abs() > layer_height / 4.0)
    {
        problems.push(format!(
            "the first layer after it is at {}, planned at {:.2}",
            height_words(found.resume_height),
            pause.resume_height
        ));
    }
    let message = found.message.as_deref().unwrap_or("");
    let shown = match pause.messages.as_slice() {
        // On a bed of several parts the 3MF names the part before its message.
        [one] => message == one || message.ends_with(&format!(": {one}")),
        many => many.iter().all(|m| message.contains(m.as_str())),
    };
    if !shown {
        problems.push(format!(
            "it shows \"{message}\", planned \"{}\"",
            pause.messages.join("\", \"")
        ));
    }
    (!problems.is_empty()).then(|| {
        format!(
            "the pause after layer {} (line {}): {}",
            pause.layers_done,
            found.line,
            problems.join("; ")
        )
    })
}

fn height_words(height: Option<f64>) -> String {
    height.map_or("before any layer".to_string(), |h| format!("height {h:.2}"))
}
