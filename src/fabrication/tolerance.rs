//! The one comparison every fabrication check uses.

/// Relative slack on every "at least" limit: a value short of its limit by less than this
/// fraction of the limit passes. It absorbs rounding in values that were meant to sit exactly on
/// the limit (a ball radius computed as capsule radius minus clearance, a capsule placed exactly
/// one wall away from a face), and matches the slack the project model allows when it picks an
/// off-the-shelf ball.
const RELATIVE_SLACK: f64 = 1e-9;

/// Whether `value` falls short of the lower limit `limit` by more than the rounding slack.
pub(super) fn falls_short(value: f64, limit: f64) -> bool {
    value < limit - RELATIVE_SLACK * limit.abs()
}

#[cfg(test)]
mod tests {
    use super::falls_short;

    #[test]
    fn rounding_passes_and_real_shortfalls_do_not() {
        assert!(!falls_short(3.0, 3.0));
        assert!(!falls_short(3.2 - 0.2, 3.0));
        assert!(!falls_short(3.0 * (1.0 - 1e-12), 3.0));
        assert!(falls_short(2.999, 3.0));
        assert!(falls_short(-1e-3, 0.0));
        assert!(!falls_short(0.0, 0.0));
    }
}
