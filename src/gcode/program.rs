//! One pass over a G-code program: its extrusion segments by printed object, its layers and its
//! pauses.

use std::collections::HashMap;

use nalgebra::{Point3, Vector3};

use super::GcodeError;

/// What to look for beyond moves.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadOptions {
    /// The command that pauses the print (PrusaSlicer's `pause_print_gcode`, `M601` by
    /// default): a line whose code (the text before any `;`) is this, words compared without
    /// regard to case or spacing, is a pause.
    pub pause_gcode: String,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            pause_gcode: "M601".to_string(),
        }
    }
}

/// A G-code program, read.
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    /// The printed objects, in the order their labels first appear. Without object labels, one object
    /// named `None` holds every extrusion; with labels, extrusions outside any label (a purge
    /// line, a skirt) go to an object named `None`, listed only when there are some.
    pub objects: Vec<PrintedObject>,
    /// The nozzle height of each layer, in print order: a layer begins when a move extrudes at
    /// a height other than the current layer's.
    pub layers: Vec<f64>,
    /// The pauses, in print order.
    pub pauses: Vec<PauseMark>,
}

impl Program {
    /// Thickness of layer `index`: its height less the previous layer's (the first layer's from
    /// the bed at 0); 0 past the last layer.
    pub fn layer_thickness(&self, index: usize) -> f64 {
        match (index.checked_sub(1), self.layers.get(index)) {
            (_, None) => 0.0,
            (None, Some(z)) => *z,
            (Some(below), Some(z)) => z - self.layers[below],
        }
    }
}

/// The extrusions of one printed object.
#[derive(Debug, Clone, PartialEq)]
pub struct PrintedObject {
    /// The object's label as the slicer wrote it (PrusaSlicer: `NAME id:N copy M`; OrcaSlicer:
    /// the unique label id); `None` for extrusions outside any label.
    pub label: Option<String>,
    /// Its extrusion segments, in print order.
    pub segments: Vec<Segment>,
}

impl PrintedObject {
    /// The object's name: the label without PrusaSlicer's ` id:N copy M` suffix.
    pub fn name(&self) -> Option<&str> {
        let label = self.label.as_deref()?;
        let name = label
            .rfind(" id:")
            .filter(|&at| label[at..].contains(" copy "))
            .map_or(label, |at| &label[..at]);
        Some(name)
    }
}

/// One extruding move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Where the nozzle starts, mm.
    pub start: Point3<f64>,
    /// Where it ends, mm.
    pub end: Point3<f64>,
    /// Filament fed along the way, mm.
    pub filament: f64,
    /// Index into [`Program::layers`] of the layer it belongs to.
    pub layer: usize,
    /// 1-based line number of the move.
    pub line: usize,
}

/// A pause of the print.
#[derive(Debug, Clone, PartialEq)]
pub struct PauseMark {
    /// 1-based line number of the pause command.
    pub line: usize,
    /// The text of the last `M117` since the last extrusion before the pause, if any.
    pub message: Option<String>,
    /// Layers that extruded before the pause.
    pub layers_done: usize,
    /// Nozzle height of the last layer printed before the pause; `None` before any.
    pub height: Option<f64>,
    /// Nozzle height of the first layer printed after it; `None` when none is.
    pub resume_height: Option<f64>,
}

/// How far two heights may differ and still be one layer, mm.
const SAME_LAYER: f64 = 1e-6;

/// Reads the G-code `text`.
///
/// Objects are told apart by the comments slicers write around each object's moves:
/// PrusaSlicer's `; printing object NAME` … `; stop printing object NAME` (its
/// `gcode_label_objects` setting) and OrcaSlicer's `; start printing object, unique label id:
/// N` … `; stop printing object, unique label id: N`. A file without such comments may label
/// its objects for the firmware instead: `M486 S<n>` starts object `n` (named by an `A` word on
/// that line or an earlier one for `n`, else labelled `n`), `M486 S-1` ends it.
pub fn read_program(text: &str, options: &ReadOptions) -> Result<Program, GcodeError> {
    let pause = normalise(&options.pause_gcode);
    let firmware_labels = !text.lines().any(|raw| {
        raw.split_once(';')
            .is_some_and(|(_, comment)| label_change(comment).is_some())
    });
    let mut firmware_names: Vec<(i64, String)> = Vec::new();
    let mut state = State::default();
    for (index, raw) in text.lines().enumerate() {
        let line = index + 1;
        let (code, comment) = raw.split_once(';').unwrap_or((raw, ""));
        if let Some(label) = label_change(comment) {
            let object = label.map(|name| state.object(Some(name)));
            state.current = object;
            continue;
        }
        let code = code.trim();
        if code.is_empty() {
            continue;
        }
        if !pause.is_empty() && normalise(code) == pause {
            state.pause(line);
            continue;
        }
        let (command, rest) = code.split_once(char::is_whitespace).unwrap_or((code, ""));
        let command = command.to_ascii_uppercase();
        match command.as_str() {
            "G90" => (state.relative_xyz, state.relative_e) = (false, false),
            "G91" => (state.relative_xyz, state.relative_e) = (true, true),
            "M82" => state.relative_e = false,
            "M83" => state.relative_e = true,
            "M117" => state.message = Some(rest.trim().to_string()),
            "M486" if firmware_labels => {
                if let Some((id, name)) = firmware_label(rest) {
                    if id < 0 {
                        state.current = None;
                    } else {
                        let known = firmware_names.iter().find(|(n, _)| *n == id);
                        let label = match (name, known) {
                            (Some(name), _) => name,
                            (None, Some((_, name))) => name.clone(),
                            (None, None) => id.to_string(),
                        };
                        if known.is_none() {
                            firmware_names.push((id, label.clone()));
                        }
                        state.current = Some(state.object(Some(label)));
                    }
                }
            }
            "G92" => {
                let values = axis_values(rest, line)?;
                for (axis, value) in values.iter().take(3).enumerate() {
                    if let Some(v) = value {
                        state.position[axis] = *v;
                    }
                }
                if let Some(v) = values[3] {
                    state.e = v;
                }
            }
            "G0" | "G1" => {
                let values = axis_values(rest, line)?;
                state.motion(values, line);
            }
            _ => {}
        }
    }
    Ok(state.finish())
}

/// A line's code with its words upper-cased and single-spaced.
fn normalise(code: &str) -> String {
    code.split_whitespace()
        .map(str::to_ascii_uppercase)
        .collect::<Vec<_>>()
        .join(" ")
}

/// `Some(Some(label))` when `comment` starts an object, `Some(None)` when it ends one.
fn label_change(comment: &str) -> Option<Option<String>> {
    let comment = comment.trim();
    if let Some(id) = comment.strip_prefix("start printing object, unique label id:") {
        return Some(Some(id.trim().to_string()));
    }
    if comment.starts_with("stop printing object") {
        return Some(None);
    }
    comment
        .strip_prefix("printing object ")
        .map(|label| Some(label.trim().to_string()))
}

/// The object index of an `M486 S<n>` and the name its `A` word gives, if any (quotes
/// dropped); `None` for the other `M486` forms (`T`, `P`, `U`, `C`).
fn firmware_label(words: &str) -> Option<(i64, Option<String>)> {
    let (index, name) = match words.find(['A', 'a']) {
        Some(at) => (&words[..at], Some(words[at + 1..].trim().trim_matches('"'))),
        None => (words, None),
    };
    let mut index = index.split_whitespace();
    let id = index.next()?.strip_prefix(['S', 's'])?.parse().ok()?;
    Some((id, name.filter(|n| !n.is_empty()).map(str::to_string)))
}

/// The `X`, `Y`, `Z` and `E` values of a move's words.
fn axis_values(words: &str, line: usize) -> Result<[Option<f64>; 4], GcodeError> {
    let mut values = [None; 4];
    for word in words.split_whitespace() {
        let (letter, number) = word.split_at(word.chars().next().map_or(0, char::len_utf8));
        let slot = match letter.to_ascii_uppercase().as_str() {
            "X" => 0,
            "Y" => 1,
            "Z" => 2,
            "E" => 3,
            _ => continue,
        };
        let bad = || GcodeError {
            line,
            word: word.to_owned(),
        };
        let value: f64 = number.parse().map_err(|_| bad())?;
        if !value.is_finite() {
            return Err(bad());
        }
        values[slot] = Some(value);
    }
    Ok(values)
}

/// The reader's state between lines.
#[derive(Debug, Default)]
struct State {
    position: Vector3<f64>,
    e: f64,
    relative_xyz: bool,
    relative_e: bool,
    objects: Vec<PrintedObject>,
    /// Index into `objects` of each label seen (`None`: the unlabelled extrusions), so a file
    /// of many objects is read in time linear in its length.
    indices: HashMap<Option<String>, usize>,
    /// Index into `objects` of the labelled object printing now.
    current: Option<usize>,
    /// Whether any label was seen.
    labelled: bool,
    layers: Vec<f64>,
    pauses: Vec<PauseMark>,
    message: Option<String>,
}

impl State {
    /// Index of the object labelled `label`, added when new.
    fn object(&mut self, label: Option<String>) -> usize {
        self.labelled |= label.is_some();
        if let Some(&index) = self.indices.get(&label) {
            return index;
        }
        self.indices.insert(label.clone(), self.objects.len());
        self.objects.push(PrintedObject {
            label,
            segments: Vec::new(),
        });
        self.objects.len() - 1
    }

    fn pause(&mut self, line: usize) {
        self.pauses.push(PauseMark {
            line,
            message: self.message.take(),
            layers_done: self.layers.len(),
            height: self.layers.last().copied(),
            resume_height: None,
        });
    }

    /// A `G0`/`G1` with these axis values.
    fn motion(&mut self, values: [Option<f64>; 4], line: usize) {
        let start = self.position;
        for (axis, value) in values.iter().take(3).enumerate() {
            if let Some(v) = *value {
                self.position[axis] = if self.relative_xyz {
                    self.position[axis] + v
                } else {
                    v
                };
            }
        }
        let fed = match values[3] {
            Some(v) if self.relative_e => v,
            Some(v) => v - self.e,
            None => 0.0,
        };
        self.e += fed;
        if fed <= 0.0 || self.position == start {
            return;
        }
        let z = self.position.z;
        if self
            .layers
            .last()
            .is_none_or(|last| (last - z).abs() > SAME_LAYER)
        {
            self.layers.push(z);
            for pause in self.pauses.iter_mut().rev() {
                if pause.resume_height.is_some() {
                    break;
                }
                pause.resume_height = Some(z);
            }
        }
        self.message = None;
        let object = match self.current {
            Some(index) => index,
            None => self.object(None),
        };
        self.objects[object].segments.push(Segment {
            start: Point3::from(start),
            end: Point3::from(self.position),
            filament: fed,
            layer: self.layers.len() - 1,
            line,
        });
    }

    fn finish(mut self) -> Program {
        // Unlabelled extrusions come last when the file labels its objects.
        if self.labelled {
            if let Some(at) = self.objects.iter().position(|o| o.label.is_none()) {
                let unlabelled = self.objects.remove(at);
                self.objects.push(unlabelled);
            }
        }
        Program {
            objects: self.objects,
            layers: self.layers,
            pauses: self.pauses,
        }
    }
}
