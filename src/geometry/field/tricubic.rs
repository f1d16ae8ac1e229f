//! Catmull-Rom weights for tricubic interpolation over a 4×4×4 neighbourhood.

/// The four Catmull-Rom weights at fraction `t ∈ [0, 1]` between the two middle nodes, and their
/// derivatives with respect to `t`. The weights sum to 1 and reproduce linear functions; the
/// resulting interpolant passes through the nodes and is C¹ across cells.
pub(super) fn catmull_rom(t: f64) -> ([f64; 4], [f64; 4]) {
    let (t2, t3) = (t * t, t * t * t);
    let weights = [
        (-t3 + 2.0 * t2 - t) / 2.0,
        (3.0 * t3 - 5.0 * t2 + 2.0) / 2.0,
        (-3.0 * t3 + 4.0 * t2 + t) / 2.0,
        (t3 - t2) / 2.0,
    ];
    let derivatives = [
        (-3.0 * t2 + 4.0 * t - 1.0) / 2.0,
        (9.0 * t2 - 10.0 * t) / 2.0,
        (-9.0 * t2 + 8.0 * t + 1.0) / 2.0,
        (3.0 * t2 - 2.0 * t) / 2.0,
    ];
    (weights, derivatives)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_interpolate_and_reproduce_lines() {
        for t in [0.0, 0.25, 0.5, 0.9, 1.0] {
            let (w, d) = catmull_rom(t);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            let line: f64 = w
                .iter()
                .enumerate()
                .map(|(i, w)| w * (i as f64 - 1.0))
                .sum();
            assert!((line - t).abs() < 1e-15);
            assert!(d.iter().sum::<f64>().abs() < 1e-15);
        }
        assert_eq!(catmull_rom(0.0).0, [0.0, 1.0, 0.0, 0.0]);
    }
}
