//! The print plan's pauses put into a sliced G-code file: `ballast pauses`, for slicers that
//! keep no pause in the files ballast writes (Cura, OrcaSlicer, Bambu Studio, SuperSlicer).
//!
//! The whole bed pauses at once, so the pauses put in are the plan's pauses of the bed
//! ([`PrintPlan::plate_pauses`](crate::fabrication::PrintPlan::plate_pauses): every component's
//! pauses after the same layer are one, its message each component's, named on a bed of several
//! parts), in millimetres.
//! Each is put before the first layer printed after it, found by its height: the layer of the
//! file whose extrusions run at the plan's resume height (within a quarter of the plan's layer
//! height), however the slicer numbers its layers. Its lines go right after the slicer's marker
//! of that layer (`;LAYER_CHANGE` and its `;Z:`/`;HEIGHT:`, `; CHANGE_LAYER`, Cura's `;LAYER:n`;
//! `gcode::LayerStart`), or before the layer's first extrusion in a file without markers:
//!
//! ```text
//! ;PAUSE_PRINT
//! ; ballast: after layer 46 (printed to 13.85 mm), resuming with the layer to 14.15 mm
//! M117 Insert one 8 mm steel ball into capsule `keel`
//! M601
//! ```
//!
//! A pause the file already has there (its pause command, after the layer before and before
//! the first extrusion of the layer) is kept and none is added, so a file is never paused twice
//! for one ball, and running `ballast pauses` on its own output changes nothing. The rest of
//! the file is copied byte for byte.
//!
//! Invariant: the output is the input with whole lines added before some of its lines; nothing
//! of the input is changed, moved or left out.

use serde::Serialize;
use thiserror::Error;

mod splice;

use splice::{line_break, splice};

use crate::fabrication::PlatePause;
use crate::gcode::{scan_program, GcodeError, LayerStart, Outline, ReadOptions};

/// The pause commands `--pause-gcode` names for common firmware: Prusa firmware and Marlin's
/// `M601` (pause, park and wait), Marlin's `M0` (wait for the user), Bambu Lab's `M400 U1`,
/// Klipper's `PAUSE` macro.
pub const PAUSE_PRESETS: [&str; 4] = ["M601", "M0", "M400 U1", "PAUSE"];

/// The longest pause command taken, bytes.
pub const MAX_PAUSE_COMMAND_BYTES: usize = 200;

/// A pause command: one line of G-code without a comment, within
/// [`MAX_PAUSE_COMMAND_BYTES`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PauseCommand(String);

impl PauseCommand {
    /// `text` as a pause command, or why it is none.
    pub fn new(text: &str) -> Result<PauseCommand, String> {
        let command = text.trim();
        if command.is_empty() {
            return Err("a pause command cannot be empty".to_string());
        }
        if command.len() > MAX_PAUSE_COMMAND_BYTES {
            return Err(format!(
                "a pause command is one line of at most {MAX_PAUSE_COMMAND_BYTES} bytes"
            ));
        }
        if command.chars().any(char::is_control) {
            return Err("a pause command is one line: no line break or control character".into());
        }
        if command.contains(';') {
            return Err(
                "a pause command holds no `;` (the rest of the line would be a comment)"
                    .to_string(),
            );
        }
        Ok(PauseCommand(command.to_string()))
    }

    /// The command's text.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

/// Where one pause went.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlacedPause {
    /// The plan's pause of the bed, heights in millimetres.
    pub pause: PlatePause,
    /// Index of the file's layer printed right after it (its layers counted from 0, in print
    /// order, as `gcode::Outline::layers`).
    pub layer: usize,
    /// 1-based line of the pause command in the output.
    pub line: usize,
    /// Whether the file had the pause already (then `line` is that pause's, and nothing was
    /// added).
    pub kept: bool,
}

/// The file with the plan's pauses.
#[derive(Debug, Clone, PartialEq)]
pub struct Paused {
    /// The output's bytes.
    pub bytes: Vec<u8>,
    /// One per pause of the plan, lowest first.
    pub pauses: Vec<PlacedPause>,
}

/// Why the pauses cannot be put into a file.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PausesError {
    /// A line does not read.
    #[error(transparent)]
    Gcode(#[from] GcodeError),
    /// Nothing is extruded.
    #[error("the G-code extrudes nothing")]
    Empty,
    /// No layer of the file is printed at a planned resume height.
    #[error(
        "the file has no layer at {resume_height:.3} mm, the top of the first layer after the \
         pause planned after layer {layers_done} (\"{message}\"); its nearest layers are at \
         {nearest}: the file's layers are not the plan's"
    )]
    NoLayer {
        /// Layers the plan prints before the pause.
        layers_done: usize,
        /// The planned resume height, mm.
        resume_height: f64,
        /// The pause's message.
        message: String,
        /// The nearest layer heights of the file, mm, in words.
        nearest: String,
    },
    /// The file prints at a planned resume height more than once (objects printed one at a
    /// time), so where the whole bed pauses is not one place.
    #[error(
        "the file prints layers at {resume_height:.3} mm {count} times (from lines {lines}): \
         printed one object at a time, the bed cannot pause there once for every part; slice \
         the parts together, layer by layer"
    )]
    RepeatedHeight {
        /// The planned resume height, mm.
        resume_height: f64,
        /// How many layers of the file are at it.
        count: usize,
        /// The lines those layers start at, in words.
        lines: String,
    },
    /// The planned resume height is the file's first layer: nothing is printed before it.
    #[error(
        "the pause planned after layer {layers_done} resumes at {resume_height:.3} mm, the \
         height of the file's first layer: the file's layers are not the plan's"
    )]
    FirstLayer {
        /// Layers the plan prints before the pause.
        layers_done: usize,
        /// The planned resume height, mm.
        resume_height: f64,
    },
}

/// The G-code `bytes` (read as text with any byte that is not UTF-8 replaced, copied as they
/// are) with `pauses` (the plan's pauses of the bed, heights in mm) put in, each running
/// `command`; `layer_height` (mm) is the plan's, a quarter of which two heights may differ by and
/// be one layer.
pub fn insert_pauses(
    bytes: &[u8],
    pauses: &[PlatePause],
    layer_height: f64,
    command: &PauseCommand,
) -> Result<Paused, PausesError> {
    let text = String::from_utf8_lossy(bytes);
    let read = ReadOptions {
        pause_gcode: command.as_str().to_string(),
    };
    let outline = scan_program(&text, &read, |_, _| {})?;
    if outline.layers.is_empty() {
        return Err(PausesError::Empty);
    }
    let line_break = line_break(bytes);
    // Per pause: its layer, and the line its lines go before (none when it is kept).
    let mut placed = Vec::with_capacity(pauses.len());
    for pause in pauses {
        let layer = resume_layer(&outline, pause, layer_height)?;
        let kept = outline
            .pauses
            .iter()
            .find(|mark| mark.layers_done == layer)
            .map(|mark| mark.line);
        placed.push((pause, layer, kept));
    }
    let mut additions: Vec<(usize, Vec<u8>)> = placed
        .iter()
        .filter(|(_, _, kept)| kept.is_none())
        .map(|(pause, layer, _)| {
            let start: &LayerStart = &outline.layer_starts[*layer];
            (start.insert_before, pause_lines(pause, command, line_break))
        })
        .collect();
    additions.sort_by_key(|(line, _)| *line);
    let (output, line_shift) = splice(bytes, &additions);
    let pauses = placed
        .into_iter()
        .map(|(pause, layer, kept)| {
            let (line, kept) = match kept {
                Some(line) => (line_shift(line), true),
                // The pause command is the last of the lines put before the layer's start.
                None => (
                    line_shift(outline.layer_starts[layer].insert_before) - 1,
                    false,
                ),
            };
            PlacedPause {
                pause: pause.clone(),
                layer,
                line,
                kept,
            }
        })
        .collect();
    Ok(Paused {
        bytes: output,
        pauses,
    })
}

/// The index of the layer of `outline` printed at `pause`'s resume height.
fn resume_layer(
    outline: &Outline,
    pause: &PlatePause,
    layer_height: f64,
) -> Result<usize, PausesError> {
    let tolerance = layer_height / 4.0;
    let at: Vec<usize> = (0..outline.layers.len())
        .filter(|&k| (outline.layers[k] - pause.resume_height).abs() <= tolerance)
        .collect();
    match at.as_slice() {
        [] => Err(PausesError::NoLayer {
            layers_done: pause.layers_done,
            resume_height: pause.resume_height,
            message: pause.message.clone(),
            nearest: nearest_layers(&outline.layers, pause.resume_height),
        }),
        [0] => Err(PausesError::FirstLayer {
            layers_done: pause.layers_done,
            resume_height: pause.resume_height,
        }),
        [layer] => Ok(*layer),
        many => Err(PausesError::RepeatedHeight {
            resume_height: pause.resume_height,
            count: many.len(),
            lines: many
                .iter()
                .map(|&k| outline.layer_starts[k].insert_before.to_string())
                .collect::<Vec<_>>()
                .join(", "),
        }),
    }
}

/// The heights of `layers` just below and just above `height`, mm, in words.
fn nearest_layers(layers: &[f64], height: f64) -> String {
    let below = layers
        .iter()
        .copied()
        .filter(|&z| z < height)
        .reduce(f64::max);
    let above = layers
        .iter()
        .copied()
        .filter(|&z| z > height)
        .reduce(f64::min);
    match (below, above) {
        (Some(b), Some(a)) => format!("{b:.3} and {a:.3} mm"),
        (Some(z), None) | (None, Some(z)) => format!("{z:.3} mm"),
        (None, None) => "nowhere".to_string(),
    }
}

/// The lines of one pause, each ended by `line_break`.
fn pause_lines(pause: &PlatePause, command: &PauseCommand, line_break: &[u8]) -> Vec<u8> {
    let lines = [
        ";PAUSE_PRINT".to_string(),
        format!(
            "; ballast: after layer {} (printed to {:.3} mm), resuming with the layer to {:.3} mm",
            pause.layers_done, pause.height, pause.resume_height
        ),
        format!("M117 {}", printer_text(&pause.message)),
        command.as_str().to_string(),
    ];
    let mut bytes = Vec::new();
    for line in lines {
        bytes.extend_from_slice(line.as_bytes());
        bytes.extend_from_slice(line_break);
    }
    bytes
}

/// `message` as one line of `M117` text: a line break or other control character becomes a
/// space and `;` (which would start a comment) a `,`.
fn printer_text(message: &str) -> String {
    message
        .chars()
        .map(|c| match c {
            ';' => ',',
            c if c.is_control() => ' ',
            c => c,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pause(layers_done: usize, height: f64, resume_height: f64) -> PlatePause {
        PlatePause {
            layers_done,
            height,
            resume_height,
            message: format!("Insert one ball after layer {layers_done}"),
        }
    }

    /// Three layers as PrusaSlicer marks them.
    const PRUSA: &str = "\
M83
;LAYER_CHANGE
;Z:0.35
;HEIGHT:0.35
G1 Z.35
G1 X10 E1
;LAYER_CHANGE
;Z:0.65
;HEIGHT:0.3
G1 Z.65
G1 X0 E1
;LAYER_CHANGE
;Z:0.95
;HEIGHT:0.3
G1 Z.95
G1 X10 E1
";

    #[test]
    fn a_pause_goes_after_the_marker_of_the_layer_at_its_resume_height() {
        let command = PauseCommand::new("M601").unwrap();
        let paused =
            insert_pauses(PRUSA.as_bytes(), &[pause(2, 0.65, 0.95)], 0.3, &command).unwrap();
        let text = String::from_utf8(paused.bytes).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(&lines[11..14], [";LAYER_CHANGE", ";Z:0.95", ";HEIGHT:0.3"]);
        assert_eq!(
            &lines[14..18],
            [
                ";PAUSE_PRINT",
                "; ballast: after layer 2 (printed to 0.650 mm), resuming with the layer to 0.950 mm",
                "M117 Insert one ball after layer 2",
                "M601"
            ]
        );
        assert_eq!(lines[18], "G1 Z.95");
        assert_eq!(lines.len(), 16 + 4);
        let placed = &paused.pauses[0];
        assert_eq!((placed.layer, placed.line, placed.kept), (2, 18, false));
        // Read back, the pause is after two layers, with its message.
        let outline = scan_program(&text, &ReadOptions::default(), |_, _| {}).unwrap();
        assert_eq!(outline.pauses.len(), 1);
        assert_eq!(outline.pauses[0].line, 18);
        assert_eq!(outline.pauses[0].layers_done, 2);
        assert_eq!(
            outline.pauses[0].message.as_deref(),
            Some("Insert one ball after layer 2")
        );
    }

    #[test]
    fn a_pause_already_there_is_kept_and_the_output_is_the_input() {
        let command = PauseCommand::new("M0").unwrap();
        let once = insert_pauses(PRUSA.as_bytes(), &[pause(1, 0.35, 0.65)], 0.3, &command).unwrap();
        assert!(!once.pauses[0].kept);
        let twice = insert_pauses(&once.bytes, &[pause(1, 0.35, 0.65)], 0.3, &command).unwrap();
        assert_eq!(twice.bytes, once.bytes);
        assert!(twice.pauses[0].kept);
        assert_eq!(twice.pauses[0].line, once.pauses[0].line);
        // Another command is not a pause of this one's: it is added.
        let other = PauseCommand::new("M601").unwrap();
        let both = insert_pauses(&once.bytes, &[pause(1, 0.35, 0.65)], 0.3, &other).unwrap();
        assert!(!both.pauses[0].kept);
    }

    #[test]
    fn cura_layers_crlf_and_bytes_that_are_not_utf8_are_kept() {
        let mut input =
            b";LAYER_COUNT:2\r\n;LAYER:0\r\nG0 Z0.3\r\n;MESH:b\xffox.stl\r\nG1 X1 E1\r\n".to_vec();
        input.extend_from_slice(b"G0 Z0.6\r\n;LAYER:1\r\nG1 X2 E2\r\n");
        let command = PauseCommand::new("PAUSE").unwrap();
        let paused = insert_pauses(&input, &[pause(1, 0.3, 0.6)], 0.3, &command).unwrap();
        let expected_head = &input[..input.len() - b"G1 X2 E2\r\n".len()];
        assert!(paused.bytes.starts_with(expected_head));
        assert!(paused
            .bytes
            .ends_with(b"M117 Insert one ball after layer 1\r\nPAUSE\r\nG1 X2 E2\r\n"));
        assert_eq!(paused.pauses[0].line, 11);
    }

    #[test]
    fn several_pauses_in_one_file_each_after_its_layer() {
        let command = PauseCommand::new("M601").unwrap();
        let pauses = [pause(1, 0.35, 0.65), pause(2, 0.65, 0.95)];
        let paused = insert_pauses(PRUSA.as_bytes(), &pauses, 0.3, &command).unwrap();
        let text = String::from_utf8(paused.bytes).unwrap();
        let outline = scan_program(&text, &ReadOptions::default(), |_, _| {}).unwrap();
        let found: Vec<(usize, usize)> = outline
            .pauses
            .iter()
            .map(|p| (p.layers_done, p.line))
            .collect();
        let placed: Vec<(usize, usize)> = paused.pauses.iter().map(|p| (p.layer, p.line)).collect();
        assert_eq!(found, [(1, 13), (2, 22)]);
        assert_eq!(placed, found);
    }

    #[test]
    fn heights_the_file_does_not_print_once_are_refused() {
        let command = PauseCommand::new("M601").unwrap();
        let missing = insert_pauses(PRUSA.as_bytes(), &[pause(4, 1.25, 1.55)], 0.3, &command);
        match missing {
            Err(PausesError::NoLayer { nearest, .. }) => assert_eq!(nearest, "0.950 mm"),
            other => panic!("{other:?}"),
        }
        let first = insert_pauses(PRUSA.as_bytes(), &[pause(0, 0.0, 0.35)], 0.3, &command);
        assert!(matches!(first, Err(PausesError::FirstLayer { .. })));
        let twice = format!("{PRUSA}G1 Z0.65\nG1 X5 E1\n");
        let repeated = insert_pauses(twice.as_bytes(), &[pause(1, 0.35, 0.65)], 0.3, &command);
        assert!(matches!(
            repeated,
            Err(PausesError::RepeatedHeight { count: 2, .. })
        ));
        let empty = insert_pauses(b"G28\n", &[], 0.3, &command);
        assert_eq!(empty, Err(PausesError::Empty));
    }

    #[test]
    fn pause_commands_are_one_line_without_a_comment() {
        for preset in PAUSE_PRESETS {
            assert_eq!(PauseCommand::new(preset).unwrap().as_str(), preset);
        }
        assert_eq!(PauseCommand::new("  M25 ").unwrap().as_str(), "M25");
        for bad in ["", "  ", "M0\nG28", "M0 ; wait", "M0\rG28"] {
            assert!(PauseCommand::new(bad).is_err(), "{bad:?}");
        }
        assert!(PauseCommand::new(&"M".repeat(MAX_PAUSE_COMMAND_BYTES + 1)).is_err());
    }

    #[test]
    fn messages_are_one_line_of_printer_text() {
        assert_eq!(printer_text("a; b\nc"), "a, b c");
    }
}
