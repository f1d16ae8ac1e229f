//! Where the nozzle goes: a move's words, its target within the limits, the filament it feeds,
//! and arcs (`G2`/`G3`) as the firmware draws them, split into chords.

use std::f64::consts::TAU;

use nalgebra::Vector3;

use super::words::{Word, Words};
use super::{GcodeError, GcodeErrorKind, ARC_CHORDS_PER_TURN, MAX_COORDINATE, MAX_FILAMENT};

/// The words of a move that ballast reads, each with its value and its text.
#[derive(Debug, Default)]
pub(super) struct Axes<'a> {
    /// `X`, `Y`, `Z`.
    pub xyz: [Option<(f64, &'a str)>; 3],
    /// `E`.
    pub e: Option<(f64, &'a str)>,
    /// An arc's centre offset in x from its start, `I`.
    pub i: Option<(f64, &'a str)>,
    /// An arc's centre offset in y, `J`.
    pub j: Option<(f64, &'a str)>,
    /// An arc's radius, `R`.
    pub r: Option<(f64, &'a str)>,
    /// An arc's whole extra turns, `P`.
    pub p: Option<(f64, &'a str)>,
}

impl<'a> Axes<'a> {
    /// The axis words among `words`, of line `line`: a word given twice, or whose number does
    /// not read, is an error. Other letters are left alone.
    pub fn read(words: Words<'a>, line: usize) -> Result<Axes<'a>, GcodeError> {
        let mut axes = Axes::default();
        for word in words {
            let slot = match word.letter {
                b'X' => &mut axes.xyz[0],
                b'Y' => &mut axes.xyz[1],
                b'Z' => &mut axes.xyz[2],
                b'E' => &mut axes.e,
                b'I' => &mut axes.i,
                b'J' => &mut axes.j,
                b'R' => &mut axes.r,
                b'P' => &mut axes.p,
                _ => continue,
            };
            if slot.is_some() {
                return Err(error(line, word.text, GcodeErrorKind::Repeated));
            }
            *slot = Some((number(&word, line)?, word.text));
        }
        Ok(axes)
    }
}

/// The value of `word`; a number too large for a 64-bit float is out of range.
fn number(word: &Word, line: usize) -> Result<f64, GcodeError> {
    let value: f64 = word
        .number
        .parse()
        .map_err(|_| error(line, word.text, GcodeErrorKind::NotANumber))?;
    if value.is_finite() {
        Ok(value)
    } else if word.letter == b'E' {
        Err(error(line, word.text, GcodeErrorKind::TooMuchFilament))
    } else {
        Err(error(line, word.text, GcodeErrorKind::OutOfRange))
    }
}

fn error(line: usize, word: &str, kind: GcodeErrorKind) -> GcodeError {
    GcodeError::new(line, word, kind)
}

/// Whether `value` is at most `limit` in magnitude (never NaN).
fn within(value: f64, limit: f64) -> bool {
    value.abs() <= limit
}

/// `value` when it is a filament length within [`MAX_FILAMENT`].
pub(super) fn checked_filament(value: f64, word: &str, line: usize) -> Result<f64, GcodeError> {
    if within(value, MAX_FILAMENT) {
        Ok(value)
    } else {
        Err(error(line, word, GcodeErrorKind::TooMuchFilament))
    }
}

/// The nozzle: where it is, the extruder's position, the plane arcs are drawn in, and the
/// filament deposited so far.
#[derive(Debug)]
pub(super) struct Motion {
    /// Where the nozzle is, mm.
    pub position: Vector3<f64>,
    /// The extruder's position, mm of filament.
    pub e: f64,
    /// Whether arcs are in the XY plane (`G17`, the default) rather than `G18`'s or `G19`'s.
    pub plane_xy: bool,
    deposited: f64,
}

impl Default for Motion {
    fn default() -> Self {
        Motion {
            position: Vector3::zeros(),
            e: 0.0,
            plane_xy: true,
            deposited: 0.0,
        }
    }
}

impl Motion {
    /// `target` when each coordinate is within [`MAX_COORDINATE`]; an error at the word of
    /// `axes` that took it further otherwise.
    pub fn checked(
        &self,
        target: Vector3<f64>,
        axes: &Axes,
        line: usize,
    ) -> Result<Vector3<f64>, GcodeError> {
        for axis in 0..3 {
            if !within(target[axis], MAX_COORDINATE) {
                let word = axes.xyz[axis].map_or("", |(_, text)| text);
                return Err(error(line, word, GcodeErrorKind::OutOfRange));
            }
        }
        Ok(target)
    }

    /// The filament a move with `axes` feeds (negative for a retraction), the extruder moved
    /// on by it.
    pub fn feed(&mut self, axes: &Axes, relative: bool, line: usize) -> Result<f64, GcodeError> {
        let Some((v, word)) = axes.e else {
            return Ok(0.0);
        };
        let fed = if relative { v } else { v - self.e };
        self.e = checked_filament(self.e + fed, word, line)?;
        Ok(fed)
    }

    /// Counts `fed` mm of filament deposited; an error once the total passes [`MAX_FILAMENT`].
    pub fn deposit(&mut self, fed: f64, axes: &Axes, line: usize) -> Result<(), GcodeError> {
        self.deposited += fed;
        let word = axes.e.map_or("", |(_, text)| text);
        checked_filament(self.deposited, word, line).map(|_| ())
    }

    /// The arc from `start` to `end` that `G2` (`clockwise`) or `G3` draws with `axes`, as
    /// Marlin draws it: the centre at `I`, `J` from the start, or on the side `R` says (a
    /// negative `R` for the longer way round); a full circle when it ends where it starts; the
    /// full turns `P` asks for before it (0 to 100) left out, as they neither move the nozzle
    /// on nor extrude.
    /// `None` when it is a straight line (the end on the ray from the centre to the start).
    pub fn arc(
        &self,
        clockwise: bool,
        start: Vector3<f64>,
        end: Vector3<f64>,
        axes: &Axes,
        line: usize,
    ) -> Result<Option<Arc>, GcodeError> {
        let command = if clockwise { "G2" } else { "G3" };
        let not_an_arc = |why| error(line, command, GcodeErrorKind::NotAnArc(why));
        if !self.plane_xy {
            return Err(not_an_arc("arcs are read in the XY plane (`G17`) only"));
        }
        // Marlin's `P`: whole circles drawn where the arc starts, before it, neither moving on
        // nor feeding filament, so they change nothing read here.
        if axes
            .p
            .is_some_and(|(p, _)| p.fract() != 0.0 || !(0.0..=100.0).contains(&p))
        {
            return Err(not_an_arc(
                "its full turns (`P`) are not a whole number from 0 to 100",
            ));
        }
        for (value, word) in [axes.i, axes.j, axes.r].into_iter().flatten() {
            if !within(value, MAX_COORDINATE) {
                return Err(error(line, word, GcodeErrorKind::OutOfRange));
            }
        }
        let same_end = start.x == end.x && start.y == end.y;
        let offset = if let Some((r, _)) = axes.r {
            if same_end {
                return Err(not_an_arc(
                    "an arc given by `R` must end elsewhere than it starts",
                ));
            }
            let half = (end.xy() - start.xy()) / 2.0;
            let sign = if clockwise ^ (r < 0.0) { -1.0 } else { 1.0 };
            let length = half.norm();
            let h2 = (r - length) * (r + length);
            let h = if h2 >= 0.0 { h2.sqrt() } else { 0.0 };
            let across = nalgebra::Vector2::new(-half.y, half.x);
            half + across / length * sign * h
        } else if axes.i.is_some() || axes.j.is_some() {
            let value = |axis: Option<(f64, &str)>| axis.map_or(0.0, |(v, _)| v);
            nalgebra::Vector2::new(value(axes.i), value(axes.j))
        } else {
            return Err(not_an_arc(
                "it has neither a centre (`I`, `J`) nor a radius (`R`)",
            ));
        };
        if offset.x == 0.0 && offset.y == 0.0 {
            return Err(not_an_arc("its centre is its start"));
        }
        let centre = start.xy() + offset;
        let from = start.xy() - centre;
        let to = end.xy() - centre;
        let angle = if same_end {
            if clockwise {
                -TAU
            } else {
                TAU
            }
        } else {
            let angle = (from.x * to.y - from.y * to.x).atan2(from.x * to.x + from.y * to.y);
            if angle == 0.0 {
                return Ok(None);
            }
            match (angle > 0.0, clockwise) {
                (true, true) => angle - TAU,
                (false, false) => angle + TAU,
                _ => angle,
            }
        };
        let turns = angle.abs() / TAU;
        let chords =
            ((turns * ARC_CHORDS_PER_TURN as f64).ceil() as usize).clamp(1, ARC_CHORDS_PER_TURN);
        Ok(Some(Arc {
            start,
            end,
            centre: Vector3::new(centre.x, centre.y, 0.0),
            from: Vector3::new(from.x, from.y, 0.0),
            angle,
            chords,
        }))
    }
}

/// An arc of a circle in a plane of constant z, or a helix when z changes along it.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Arc {
    start: Vector3<f64>,
    end: Vector3<f64>,
    centre: Vector3<f64>,
    /// From the centre to the start.
    from: Vector3<f64>,
    /// Radians, counter-clockwise positive.
    angle: f64,
    chords: usize,
}

impl Arc {
    /// Whether the nozzle moves along it.
    pub fn moves(&self) -> bool {
        self.angle != 0.0
    }

    /// Hands each chord to `piece` (start, end, its share of the `fed` filament) from start to
    /// end: equal angles, so equal shares; the last chord ends exactly at the arc's end.
    pub fn chords(&self, fed: f64, piece: &mut impl FnMut(Vector3<f64>, Vector3<f64>, f64)) {
        let filament = fed / self.chords as f64;
        let mut previous = self.start;
        for k in 1..=self.chords {
            let next = if k == self.chords {
                self.end
            } else {
                let t = k as f64 / self.chords as f64;
                let (sin, cos) = (self.angle * t).sin_cos();
                Vector3::new(
                    self.centre.x + self.from.x * cos - self.from.y * sin,
                    self.centre.y + self.from.x * sin + self.from.y * cos,
                    self.start.z + (self.end.z - self.start.z) * t,
                )
            };
            piece(previous, next, filament);
            previous = next;
        }
    }
}
