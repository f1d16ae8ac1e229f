//! The steel ball sizes one can buy: the default of `ball { diameters ... }`.
//!
//! Loose chrome-steel bearing balls (ISO 3290 / ABMA grades, G10 to G1000) are sold in metric
//! sizes and in fractions of an inch; both series are listed here, the commonly stocked sizes only
//! (every 0.5 mm from 1 to 8 mm, every millimetre to 16 mm, then the usual larger sizes; 1/16",
//! 3/32", every 1/32" from 1/8" to 11/32", every 1/16" from 3/8" to 1", then the usual larger
//! ones). `docs/format.md` lists them.

/// Metric ball diameters, millimetres.
const METRIC_MM: &[f64] = &[
    1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5, 6.0, 6.5, 7.0, 7.5, 8.0, 9.0, 10.0, 11.0,
    12.0, 13.0, 14.0, 15.0, 16.0, 18.0, 20.0, 22.0, 25.0, 30.0, 35.0, 40.0, 50.0,
];

/// Inch ball diameters as (numerator, denominator) of an inch.
const INCH_FRACTIONS: &[(u32, u32)] = &[
    (1, 16),
    (3, 32),
    (1, 8),
    (5, 32),
    (3, 16),
    (7, 32),
    (1, 4),
    (9, 32),
    (5, 16),
    (11, 32),
    (3, 8),
    (7, 16),
    (1, 2),
    (9, 16),
    (5, 8),
    (11, 16),
    (3, 4),
    (13, 16),
    (7, 8),
    (15, 16),
    (1, 1),
    (9, 8),
    (5, 4),
    (3, 2),
    (7, 4),
    (2, 1),
];

/// Every stock diameter in millimetres, metric and inch sizes together, smallest first.
pub fn stock_diameters_mm() -> Vec<f64> {
    let mut all: Vec<f64> = METRIC_MM
        .iter()
        .copied()
        .chain(
            INCH_FRACTIONS
                .iter()
                .map(|&(n, d)| f64::from(n) * 25.4 / f64::from(d)),
        )
        .collect();
    all.sort_by(f64::total_cmp);
    all.dedup();
    all
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_list_holds_both_series_in_order() {
        let all = stock_diameters_mm();
        assert_eq!(all.len(), METRIC_MM.len() + INCH_FRACTIONS.len());
        assert!(all.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(all[0], 1.0);
        assert_eq!(all[all.len() - 1], 2.0 * 25.4);
        assert!(all.contains(&6.35) && all.contains(&12.7) && all.contains(&8.0));
    }
}
