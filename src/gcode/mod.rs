//! Reading a G-code program: what it deposits, where, object by object and layer by layer, and
//! where it pauses (`docs/physics.md`, "The mass of a print"; `docs/fabrication.md`, "Checking
//! the sliced file").
//!
//! Understood: `G0`/`G1` moves (`X`, `Y`, `Z`, `E`), `G2`/`G3` arcs (centre by `I`/`J` or radius
//! `R`, in the XY plane, split into chords), `G90`/`G91` (absolute or relative positions, `E`
//! included, as Marlin does), `M82`/`M83` (absolute or relative `E`), `G92` (setting positions),
//! `M117` (a message on the printer's screen), the pause command (`M601` unless told otherwise)
//! the comments slicers label objects with (see [`read_program`]) and those they start each layer
//! with (`layers.rs`). Words are read as the
//! firmware reads them (`words.rs`): with or without spaces, either case, a line number `N` and
//! checksum `*` dropped. Everything else (temperatures, fans, other comments) is skipped. A move
//! that extrudes (`E` grows) while it moves in `X`, `Y` or `Z` deposits the filament it feeds
//! along its path; `E` changes without motion are retractions and their undoing.
//!
//! Every number read is bounded: coordinates within [`MAX_COORDINATE`], filament within
//! [`MAX_FILAMENT`], so no sum of them overflows; a line costs time linear in its length and at
//! most one copy of its text (a label or a message).
//!
//! The module knows G-code and nothing of ballast: positions are the printer's, in mm.

mod layers;
mod motion;
mod program;
mod words;

pub use layers::{LayerDialect, LayerMarker, LayerStart};
pub use program::{
    read_program, scan_program, ObjectOutline, Outline, PauseMark, PrintedObject, Program,
    ReadOptions, Segment,
};

use nalgebra::{Point3, Vector3};
use thiserror::Error;

/// What a G-code program deposits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deposit {
    /// Filament fed by depositing moves, mm.
    pub filament: f64,
    /// Volume of that filament, mm³.
    pub volume: f64,
    /// The filament's centroid, printer coordinates (mm); the origin when nothing is deposited.
    pub centroid: Point3<f64>,
}

impl Deposit {
    /// Grams of material of `density` g/cm³.
    pub fn mass(&self, density: f64) -> f64 {
        self.volume * density / 1000.0
    }
}

/// The largest coordinate read, mm (1 km, past any printer): a move, `G92` or arc word that
/// goes further is an error.
pub const MAX_COORDINATE: f64 = 1e6;
/// The largest filament length read, mm (1000 km): an `E` position, or the total a program
/// deposits, past it is an error.
pub const MAX_FILAMENT: f64 = 1e9;
/// The most pauses a program may have.
pub const MAX_PAUSES: usize = 10_000;
/// The longest object label or `M117` message read, bytes (64 KiB; a printer's screen shows a
/// few dozen characters).
pub const MAX_TEXT_BYTES: usize = 64 << 10;
/// The most of a word at fault an error repeats, characters; a longer one ends in `…`.
const MAX_WORD_SHOWN: usize = 40;
/// Chords an arc is split into per full turn (an arc of any angle into at most this many): each
/// chord spans at most 5.625°, so it lies within 0.12% of the radius of its arc.
pub const ARC_CHORDS_PER_TURN: usize = 64;

/// A G-code line that cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("G-code line {line}: {}", self.kind.describe(&self.word))]
pub struct GcodeError {
    /// 1-based line number.
    pub line: usize,
    /// The word at fault, as written (may be empty, for a line at fault as a whole), cut to its
    /// first 40 characters and `…` when longer.
    pub word: String,
    /// What is wrong with it.
    pub kind: GcodeErrorKind,
}

/// What is wrong with a G-code line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GcodeErrorKind {
    /// A word whose value does not parse.
    NotANumber,
    /// A move gives one axis twice (G-code numbers have no exponent: `E1e3` is `E1`, `e3`).
    Repeated,
    /// A coordinate past [`MAX_COORDINATE`].
    OutOfRange,
    /// An `E` position, or the filament deposited, past [`MAX_FILAMENT`].
    TooMuchFilament,
    /// A `G2`/`G3` that is no arc ballast reads, and why.
    NotAnArc(&'static str),
    /// More than [`MAX_PAUSES`] pauses.
    TooManyPauses,
    /// An object label or `M117` message longer than [`MAX_TEXT_BYTES`].
    TooLong,
}

impl GcodeError {
    /// The error of kind `kind` at `word` of line `line`.
    fn new(line: usize, word: &str, kind: GcodeErrorKind) -> GcodeError {
        let word = match word.char_indices().nth(MAX_WORD_SHOWN) {
            Some((at, _)) => format!("{}…", &word[..at]),
            None => word.to_string(),
        };
        GcodeError { line, word, kind }
    }
}

impl GcodeErrorKind {
    fn describe(self, word: &str) -> String {
        match self {
            GcodeErrorKind::NotANumber => format!("`{word}` is not a number"),
            GcodeErrorKind::Repeated => format!(
                "`{word}` gives an axis a second value in one move (G-code numbers have no \
                 exponent: `E1e3` is `E1` then `e3`)"
            ),
            GcodeErrorKind::OutOfRange => format!(
                "`{word}` takes a coordinate past {MAX_COORDINATE:e} mm, beyond any printer"
            ),
            GcodeErrorKind::TooMuchFilament => {
                format!("`{word}` takes the filament past {MAX_FILAMENT:e} mm, beyond any print")
            }
            GcodeErrorKind::NotAnArc(why) => format!("`{word}` is not an arc ballast reads: {why}"),
            GcodeErrorKind::TooManyPauses => {
                format!("more than {MAX_PAUSES} pauses, beyond any print")
            }
            GcodeErrorKind::TooLong => format!(
                "`{word}` is an object label or message longer than {} KiB, beyond any print",
                MAX_TEXT_BYTES >> 10
            ),
        }
    }
}

/// The deposit of the G-code `text`, every object together, with filament of
/// `filament_diameter` mm. Each move's filament counts at the move's midpoint, at the nozzle's
/// height.
pub fn read_deposit(text: &str, filament_diameter: f64) -> Result<Deposit, GcodeError> {
    let program = read_program(text, &ReadOptions::default())?;
    Ok(deposit_of(
        program.objects.iter().flat_map(|object| &object.segments),
        filament_diameter,
    ))
}

/// The deposit of `segments`, with filament of `filament_diameter` mm.
pub fn deposit_of<'a>(
    segments: impl IntoIterator<Item = &'a Segment>,
    filament_diameter: f64,
) -> Deposit {
    let area = filament_area(filament_diameter);
    let mut filament = 0.0;
    let mut moment = Vector3::zeros();
    for segment in segments {
        filament += segment.filament;
        moment += (segment.start.coords + segment.end.coords) * (segment.filament / 2.0);
    }
    let centroid = if filament > 0.0 {
        Point3::from(moment / filament)
    } else {
        Point3::origin()
    };
    Deposit {
        filament,
        volume: filament * area,
        centroid,
    }
}

/// Cross-section of filament of `diameter` mm, mm².
pub fn filament_area(diameter: f64) -> f64 {
    std::f64::consts::PI * diameter * diameter / 4.0
}
