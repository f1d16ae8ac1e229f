//! Where the nozzle goes: a move's words, its target within the limits and the filament it
//! feeds.

use nalgebra::Vector3;

use super::words::{Word, Words};
use super::{GcodeError, GcodeErrorKind, MAX_COORDINATE, MAX_FILAMENT};

/// The words of a move that ballast reads, each with its value and its text.
#[derive(Debug, Default)]
pub(super) struct Axes<'a> {
    /// `X`, `Y`, `Z`.
    pub xyz: [Option<(f64, &'a str)>; 3],
    /// `E`.
    pub e: Option<(f64, &'a str)>,
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

/// The nozzle: where it is, the extruder's position and the filament deposited so far.
#[derive(Debug, Default)]
pub(super) struct Motion {
    pub position: Vector3<f64>,
    pub e: f64,
    deposited: f64,
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
}
