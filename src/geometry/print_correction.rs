//! A measured correction to a component's print volumes: what a real slicer deposits beyond
//! (or short of) what the mass model puts there, as a volume and its first moment.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::print::{PrintVolumes, Region};

/// Material to add to a component's solid part: `volume` at full density (cubic units, negative
/// to take material away) with first moment `moment` (volume × position, rest frame).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct PrintCorrection {
    /// Cubic units at full density.
    pub volume: f64,
    /// Σ volume × position, rest frame.
    pub moment: [f64; 3],
}

impl PrintCorrection {
    /// The correction that turns `modelled` (a component's material as the model has it) into
    /// `measured` (as deposited), added to this one.
    pub fn plus_difference(&self, measured: &Region, modelled: &Region) -> PrintCorrection {
        let moment = Vector3::from(self.moment) + measured.centroid.coords * measured.volume
            - modelled.centroid.coords * modelled.volume;
        PrintCorrection {
            volume: self.volume + measured.volume - modelled.volume,
            moment: moment.into(),
        }
    }

    /// `print` with this correction added to its solid part, or `None` when that would leave
    /// the solid part without material (a correction measured on another mesh).
    pub fn apply(&self, print: &PrintVolumes) -> Option<PrintVolumes> {
        let volume = print.solid.volume + self.volume;
        if !volume.is_finite() || volume <= 0.0 {
            return None;
        }
        let moment = print.solid.centroid.coords * print.solid.volume + Vector3::from(self.moment);
        let centroid = nalgebra::Point3::from(moment / volume);
        centroid
            .iter()
            .all(|x| x.is_finite())
            .then_some(PrintVolumes {
                solid: Region { volume, centroid },
                sparse: print.sparse,
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;

    fn region(volume: f64, x: f64) -> Region {
        Region {
            volume,
            centroid: Point3::new(x, 0.0, 0.0),
        }
    }

    #[test]
    fn the_difference_applied_gives_the_measured_material() {
        let print = PrintVolumes {
            solid: region(10.0, 1.0),
            sparse: region(30.0, 3.0),
        };
        // The model's material at infill 0.5: 10 at x = 1 and 15 at x = 3.
        let modelled = region(25.0, (10.0 + 45.0) / 25.0);
        let measured = region(28.0, 2.0);
        let correction = PrintCorrection::default().plus_difference(&measured, &modelled);
        let corrected = correction.apply(&print).unwrap();
        let volume = corrected.solid.volume + 0.5 * corrected.sparse.volume;
        let moment = corrected.solid.centroid.x * corrected.solid.volume
            + 0.5 * corrected.sparse.volume * corrected.sparse.centroid.x;
        assert!((volume - 28.0).abs() < 1e-12);
        assert!((moment / volume - 2.0).abs() < 1e-12);
    }

    #[test]
    fn a_correction_larger_than_the_solid_is_refused() {
        let print = PrintVolumes {
            solid: region(1.0, 0.0),
            sparse: region(30.0, 0.0),
        };
        let correction = PrintCorrection {
            volume: -2.0,
            moment: [0.0; 3],
        };
        assert_eq!(correction.apply(&print), None);
    }
}
