//! One pass over a G-code program: its extrusion segments by printed object, its layers and its
//! pauses. [`scan_program`] hands each segment to its caller as it is read and keeps only what
//! is per object, per layer and per pause; [`read_program`] keeps every segment too.

use std::collections::HashMap;

use nalgebra::{Point3, Vector3};

use super::layers::{layer_comment, LayerComment, LayerStart, PendingMarker};
use super::motion::{Axes, Motion};
use super::words::{command, split_line, Pattern};
use super::{GcodeError, GcodeErrorKind, MAX_PAUSES, MAX_TEXT_BYTES};

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
    /// Where each layer of [`Program::layers`] starts (`layers.rs`).
    pub layer_starts: Vec<LayerStart>,
    /// The pauses, in print order.
    pub pauses: Vec<PauseMark>,
}

impl Program {
    /// Thickness of layer `index`: its height less the previous layer's (the first layer's from
    /// the bed at 0); 0 past the last layer.
    pub fn layer_thickness(&self, index: usize) -> f64 {
        layer_thickness(&self.layers, index)
    }
}

/// A G-code program without its segments: what [`scan_program`] keeps.
#[derive(Debug, Clone, PartialEq)]
pub struct Outline {
    /// The printed objects, in the order of [`Program::objects`].
    pub objects: Vec<ObjectOutline>,
    /// As [`Program::layers`].
    pub layers: Vec<f64>,
    /// As [`Program::layer_starts`].
    pub layer_starts: Vec<LayerStart>,
    /// As [`Program::pauses`].
    pub pauses: Vec<PauseMark>,
}

impl Outline {
    /// As [`Program::layer_thickness`].
    pub fn layer_thickness(&self, index: usize) -> f64 {
        layer_thickness(&self.layers, index)
    }
}

fn layer_thickness(layers: &[f64], index: usize) -> f64 {
    match (index.checked_sub(1), layers.get(index)) {
        (_, None) => 0.0,
        (None, Some(z)) => *z,
        (Some(below), Some(z)) => z - layers[below],
    }
}

/// One printed object of an [`Outline`].
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectOutline {
    /// The number [`scan_program`] hands with each of the object's segments: objects are
    /// numbered from 0 in the order the reader first meets them.
    pub id: usize,
    /// As [`PrintedObject::label`].
    pub label: Option<String>,
    /// How many extrusion segments it has.
    pub segments: usize,
}

impl ObjectOutline {
    /// As [`PrintedObject::name`].
    pub fn name(&self) -> Option<&str> {
        self.label.as_deref().map(object_name)
    }
}

/// The extrusions of one printed object.
#[derive(Debug, Clone, PartialEq)]
pub struct PrintedObject {
    /// The object's label as the slicer wrote it (PrusaSlicer: `NAME id:N copy M`; OrcaSlicer:
    /// the unique label id; Cura: the mesh's file); `None` for extrusions outside any label.
    pub label: Option<String>,
    /// Its extrusion segments, in print order.
    pub segments: Vec<Segment>,
}

impl PrintedObject {
    /// The object's name: the label without PrusaSlicer's ` id:N copy M` suffix, and for an
    /// object loaded from an STL file (slicers name it after the file), the file's name without
    /// its folders and `.stl`.
    pub fn name(&self) -> Option<&str> {
        self.label.as_deref().map(object_name)
    }
}

/// `label` without PrusaSlicer's ` id:N copy M` suffix, and without the folders and `.stl` of
/// a label that names an STL file.
fn object_name(label: &str) -> &str {
    let name = label
        .rfind(" id:")
        .filter(|&at| label[at..].contains(" copy "))
        .map_or(label, |at| &label[..at]);
    let stem = name
        .len()
        .checked_sub(4)
        .filter(|&at| name.is_char_boundary(at) && name[at..].eq_ignore_ascii_case(".stl"));
    match stem {
        Some(at) => {
            let file = &name[..at];
            file.rfind(['/', '\\'])
                .map_or(file, |slash| &file[slash + 1..])
        }
        None => name,
    }
}

/// One extruding move, or one chord of an extruding arc.
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

/// Reads the G-code `text`, keeping every segment.
///
/// Objects are told apart by the comments slicers write around each object's moves:
/// PrusaSlicer's `; printing object NAME` … `; stop printing object NAME` (its
/// `gcode_label_objects` setting), OrcaSlicer's `; start printing object, unique label id:
/// N` … `; stop printing object, unique label id: N`, and Cura's `;MESH:NAME` before each
/// object's moves (`;MESH:NONMESH` before moves of no object). A file without such comments
/// may label its objects for the firmware instead: `M486 S<n>` starts object `n` (named by an
/// `A` word on that line or an earlier one for `n`, else labelled `n`), `M486 S-1` ends it.
pub fn read_program(text: &str, options: &ReadOptions) -> Result<Program, GcodeError> {
    let mut segments: Vec<Vec<Segment>> = Vec::new();
    let outline = scan_program(text, options, |id, segment| {
        if segments.len() <= id {
            segments.resize_with(id + 1, Vec::new);
        }
        segments[id].push(*segment);
    })?;
    let objects = outline
        .objects
        .into_iter()
        .map(|object| PrintedObject {
            label: object.label,
            segments: segments
                .get_mut(object.id)
                .map(std::mem::take)
                .unwrap_or_default(),
        })
        .collect();
    Ok(Program {
        objects,
        layers: outline.layers,
        layer_starts: outline.layer_starts,
        pauses: outline.pauses,
    })
}

/// Reads the G-code `text` as [`read_program`] does, handing each segment to `segment` with
/// its object's [`ObjectOutline::id`] as it is read, in print order, and keeping none: memory
/// grows with the objects, layers and pauses, not with the moves.
pub fn scan_program(
    text: &str,
    options: &ReadOptions,
    mut segment: impl FnMut(usize, &Segment),
) -> Result<Outline, GcodeError> {
    let pause = Pattern::new(&options.pause_gcode);
    let firmware_labels = !text.lines().any(|raw| {
        raw.split_once(';')
            .is_some_and(|(_, comment)| label_change(comment).is_some())
    });
    let mut state = State::default();
    for (index, raw) in text.lines().enumerate() {
        let line = index + 1;
        let (code, comment) = split_line(raw);
        if let Some(label) = label_change(comment) {
            if let Some(name) = label {
                checked_text(name, line)?;
            }
            state.current = label.map(|name| state.object(Some(name)));
            continue;
        }
        let code = code.trim();
        if code.is_empty() {
            if let Some(layer) = layer_comment(comment) {
                state.layer_comment(line, layer);
            }
            continue;
        }
        if !pause.is_empty() && pause.matches(code) {
            state.pause(line)?;
            continue;
        }
        let Some((command, words)) = command(code) else {
            continue;
        };
        if command.subcode.is_some() {
            continue;
        }
        match (command.letter, command.code) {
            (b'G', 90) => (state.relative_xyz, state.relative_e) = (false, false),
            (b'G', 91) => (state.relative_xyz, state.relative_e) = (true, true),
            (b'M', 82) => state.relative_e = false,
            (b'M', 83) => state.relative_e = true,
            (b'G', 17) => state.motion.plane_xy = true,
            (b'G', 18 | 19) => state.motion.plane_xy = false,
            (b'M', 117) => {
                state.message = Some(checked_text(words.rest().trim(), line)?.to_string());
            }
            (b'M', 486) if firmware_labels => {
                state.firmware_label(checked_text(words.rest(), line)?)
            }
            (b'G', 92) => state.set_position(&Axes::read(words, line)?, line)?,
            (b'G', code @ 0..=3) => {
                let axes = Axes::read(words, line)?;
                state.motion(code, &axes, line, &mut segment)?;
            }
            _ => {}
        }
    }
    Ok(state.finish())
}

/// `text` (a label or message of line `line`) when it is within [`MAX_TEXT_BYTES`].
fn checked_text(text: &str, line: usize) -> Result<&str, GcodeError> {
    if text.len() <= MAX_TEXT_BYTES {
        Ok(text)
    } else {
        Err(GcodeError::new(line, text, GcodeErrorKind::TooLong))
    }
}

/// `Some(Some(label))` when `comment` starts an object, `Some(None)` when it ends one.
fn label_change(comment: &str) -> Option<Option<&str>> {
    let comment = comment.trim();
    if let Some(mesh) = comment.strip_prefix("MESH:") {
        let mesh = mesh.trim();
        return Some((mesh != "NONMESH").then_some(mesh));
    }
    if let Some(id) = comment.strip_prefix("start printing object, unique label id:") {
        return Some(Some(id.trim()));
    }
    if comment.starts_with("stop printing object") {
        return Some(None);
    }
    comment
        .strip_prefix("printing object ")
        .map(|label| Some(label.trim()))
}

/// The object index of an `M486 S<n>` and the name its `A` word gives, if any (quotes
/// dropped); `None` for the other `M486` forms (`T`, `P`, `U`, `C`).
fn firmware_label(words: &str) -> Option<(i64, Option<&str>)> {
    let (index, name) = match words.find(['A', 'a']) {
        Some(at) => (&words[..at], Some(words[at + 1..].trim().trim_matches('"'))),
        None => (words, None),
    };
    let mut index = index.split_whitespace();
    let id = index.next()?.strip_prefix(['S', 's'])?.parse().ok()?;
    Some((id, name.filter(|n| !n.is_empty())))
}

/// The reader's state between lines.
#[derive(Debug, Default)]
struct State {
    motion: Motion,
    relative_xyz: bool,
    relative_e: bool,
    objects: Vec<ObjectOutline>,
    /// Index into `objects` of each label seen, so a file of many objects is read in time
    /// linear in its length.
    labelled: HashMap<String, usize>,
    /// Index into `objects` of the unlabelled extrusions, once there are some.
    unlabelled: Option<usize>,
    /// The names `M486 A` gave each firmware object index.
    firmware_names: HashMap<i64, String>,
    /// Index into `objects` of the labelled object printing now.
    current: Option<usize>,
    layers: Vec<f64>,
    layer_starts: Vec<LayerStart>,
    /// The layer marker read since the last extrusion, if any.
    marker: Option<PendingMarker>,
    pauses: Vec<PauseMark>,
    message: Option<String>,
}

impl State {
    /// Index of the object labelled `label`, added when new.
    fn object(&mut self, label: Option<&str>) -> usize {
        let known = match label {
            Some(label) => self.labelled.get(label).copied(),
            None => self.unlabelled,
        };
        if let Some(index) = known {
            return index;
        }
        let index = self.objects.len();
        match label {
            Some(label) => {
                self.labelled.insert(label.to_string(), index);
            }
            None => self.unlabelled = Some(index),
        }
        self.objects.push(ObjectOutline {
            id: index,
            label: label.map(str::to_string),
            segments: 0,
        });
        index
    }

    /// An `M486` with these words.
    fn firmware_label(&mut self, words: &str) {
        let Some((id, name)) = firmware_label(words) else {
            return;
        };
        if id < 0 {
            self.current = None;
            return;
        }
        let label = match (name, self.firmware_names.get(&id)) {
            (Some(name), _) => name.to_string(),
            (None, Some(name)) => name.clone(),
            (None, None) => id.to_string(),
        };
        self.firmware_names
            .entry(id)
            .or_insert_with(|| label.clone());
        self.current = Some(self.object(Some(&label)));
    }

    /// A comment line `line` that says `comment` about layers.
    fn layer_comment(&mut self, line: usize, comment: LayerComment) {
        match comment {
            LayerComment::Start(dialect, number) => {
                self.marker = Some(PendingMarker::new(line, dialect, number));
            }
            LayerComment::Height(_) | LayerComment::Thickness(_) => {
                if let Some(marker) = &mut self.marker {
                    marker.follow(line, comment);
                }
            }
        }
    }

    fn pause(&mut self, line: usize) -> Result<(), GcodeError> {
        if self.pauses.len() >= MAX_PAUSES {
            return Err(GcodeError::new(line, "", GcodeErrorKind::TooManyPauses));
        }
        self.pauses.push(PauseMark {
            line,
            message: self.message.take(),
            layers_done: self.layers.len(),
            height: self.layers.last().copied(),
            resume_height: None,
        });
        Ok(())
    }

    /// A `G92` with these axis values.
    fn set_position(&mut self, axes: &Axes, line: usize) -> Result<(), GcodeError> {
        let position = self.motion.position;
        let mut target = position;
        for (axis, value) in axes.xyz.iter().enumerate() {
            if let Some((v, _)) = value {
                target[axis] = *v;
            }
        }
        self.motion.position = self.motion.checked(target, axes, line)?;
        if let Some((v, word)) = axes.e {
            self.motion.e = super::motion::checked_filament(v, word, line)?;
        }
        Ok(())
    }

    /// A `G0`/`G1` (`code` 0 or 1) or an arc (`G2` clockwise, `G3` counter-clockwise) with
    /// these axis values: each extruding piece goes to `emit`.
    fn motion(
        &mut self,
        code: u32,
        axes: &Axes,
        line: usize,
        emit: &mut impl FnMut(usize, &Segment),
    ) -> Result<(), GcodeError> {
        let start = self.motion.position;
        let mut end = start;
        for (axis, value) in axes.xyz.iter().enumerate() {
            if let Some((v, _)) = *value {
                end[axis] = if self.relative_xyz { end[axis] + v } else { v };
            }
        }
        let end = self.motion.checked(end, axes, line)?;
        let fed = self.motion.feed(axes, self.relative_e, line)?;
        let path = match code {
            2 | 3 => self.motion.arc(code == 2, start, end, axes, line)?,
            _ => None,
        };
        self.motion.position = end;
        let moved = path.as_ref().map_or(end != start, |arc| arc.moves());
        if fed <= 0.0 || !moved {
            return Ok(());
        }
        self.motion.deposit(fed, axes, line)?;
        let z = end.z;
        if self
            .layers
            .last()
            .is_none_or(|last| (last - z).abs() > SAME_LAYER)
        {
            self.layers.push(z);
            self.layer_starts.push(self.marker.take().map_or(
                LayerStart {
                    insert_before: line,
                    marker: None,
                },
                PendingMarker::start,
            ));
            for pause in self.pauses.iter_mut().rev() {
                if pause.resume_height.is_some() {
                    break;
                }
                pause.resume_height = Some(z);
            }
        }
        self.message = None;
        // A marker followed by extrusions at the layer's own height starts no layer.
        self.marker = None;
        let object = match self.current {
            Some(index) => index,
            None => self.object(None),
        };
        let layer = self.layers.len() - 1;
        let mut piece = |start: Vector3<f64>, end: Vector3<f64>, filament: f64| {
            self.objects[object].segments += 1;
            emit(
                object,
                &Segment {
                    start: Point3::from(start),
                    end: Point3::from(end),
                    filament,
                    layer,
                    line,
                },
            );
        };
        match path {
            None => piece(start, end, fed),
            Some(arc) => arc.chords(fed, &mut piece),
        }
        Ok(())
    }

    fn finish(mut self) -> Outline {
        // Unlabelled extrusions come last when the file labels its objects.
        if !self.labelled.is_empty() {
            if let Some(at) = self.unlabelled {
                let unlabelled = self.objects.remove(at);
                self.objects.push(unlabelled);
            }
        }
        Outline {
            objects: self.objects,
            layers: self.layers,
            layer_starts: self.layer_starts,
            pauses: self.pauses,
        }
    }
}
