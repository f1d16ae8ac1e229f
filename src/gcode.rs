//! Reading what a G-code file deposits: the filament extruded, where, and so the mass and
//! centre of mass of the print (`docs/physics.md`, "The mass of a print").
//!
//! Understood: `G0`/`G1` moves (`X`, `Y`, `Z`, `E`), `G90`/`G91` (absolute or relative
//! positions, `E` included, as Marlin does), `M82`/`M83` (absolute or relative `E`), `G92`
//! (setting positions). Everything else (temperatures, fans, comments after `;`) is skipped. A
//! move that extrudes (`E` grows) while it moves in `X`, `Y` or `Z` deposits the filament it
//! feeds at its midpoint; `E` changes without motion are retractions and their undoing.

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

/// A G-code line that cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("G-code line {line}: `{word}` is not a number")]
pub struct GcodeError {
    /// 1-based line number.
    pub line: usize,
    /// The word whose value does not parse.
    pub word: String,
}

/// The deposit of the G-code `text`, with filament of `filament_diameter` mm.
pub fn read_deposit(text: &str, filament_diameter: f64) -> Result<Deposit, GcodeError> {
    let area = std::f64::consts::PI * filament_diameter * filament_diameter / 4.0;
    let mut position = Vector3::zeros();
    let mut e = 0.0;
    let mut relative_xyz = false;
    let mut relative_e = false;
    let mut filament = 0.0;
    let mut moment = Vector3::zeros();
    for (index, raw) in text.lines().enumerate() {
        let code = raw.split(';').next().unwrap_or("").trim();
        let mut words = code.split_whitespace();
        let Some(command) = words.next() else {
            continue;
        };
        let mut values: [Option<f64>; 4] = [None; 4];
        let command = command.to_ascii_uppercase();
        let takes_axes = matches!(command.as_str(), "G0" | "G1" | "G92");
        if takes_axes {
            for word in words {
                let (letter, number) = word.split_at(word.chars().next().map_or(0, char::len_utf8));
                let slot = match letter.to_ascii_uppercase().as_str() {
                    "X" => 0,
                    "Y" => 1,
                    "Z" => 2,
                    "E" => 3,
                    _ => continue,
                };
                let value: f64 = number.parse().map_err(|_| GcodeError {
                    line: index + 1,
                    word: word.to_owned(),
                })?;
                if !value.is_finite() {
                    return Err(GcodeError {
                        line: index + 1,
                        word: word.to_owned(),
                    });
                }
                values[slot] = Some(value);
            }
        }
        match command.as_str() {
            "G90" => (relative_xyz, relative_e) = (false, false),
            "G91" => (relative_xyz, relative_e) = (true, true),
            "M82" => relative_e = false,
            "M83" => relative_e = true,
            "G92" => {
                for axis in 0..3 {
                    if let Some(v) = values[axis] {
                        position[axis] = v;
                    }
                }
                if let Some(v) = values[3] {
                    e = v;
                }
            }
            "G0" | "G1" => {
                let start = position;
                for axis in 0..3 {
                    if let Some(v) = values[axis] {
                        position[axis] = if relative_xyz { position[axis] + v } else { v };
                    }
                }
                let fed = match values[3] {
                    Some(v) if relative_e => v,
                    Some(v) => v - e,
                    None => 0.0,
                };
                e += fed;
                if fed > 0.0 && position != start {
                    filament += fed;
                    moment += (start + position) * (fed / 2.0);
                }
            }
            _ => {}
        }
    }
    let centroid = if filament > 0.0 {
        Point3::from(moment / filament)
    } else {
        Point3::origin()
    };
    Ok(Deposit {
        filament,
        volume: filament * area,
        centroid,
    })
}
