//! Where the nozzle goes: a move's words, its target and the filament it feeds.

use nalgebra::Vector3;

use super::words::{Word, Words};
use super::{GcodeError, GcodeErrorKind};

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

/// The value of `word`, a finite number.
fn number(word: &Word, line: usize) -> Result<f64, GcodeError> {
    match word.number.parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        _ => Err(error(line, word.text, GcodeErrorKind::NotANumber)),
    }
}

fn error(line: usize, word: &str, kind: GcodeErrorKind) -> GcodeError {
    GcodeError::new(line, word, kind)
}

/// The nozzle: where it is and the extruder's position.
#[derive(Debug, Default)]
pub(super) struct Motion {
    pub position: Vector3<f64>,
    pub e: f64,
}

impl Motion {
    /// The filament a move with `axes` feeds (negative for a retraction), the extruder moved
    /// on by it.
    pub fn feed(&mut self, axes: &Axes, relative: bool) -> f64 {
        let Some((v, _)) = axes.e else {
            return 0.0;
        };
        let fed = if relative { v } else { v - self.e };
        self.e += fed;
        fed
    }
}
