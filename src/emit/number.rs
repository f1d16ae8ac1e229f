//! Numbers as text for the files the back end writes.

/// `value` with at most `decimals` digits after the point, trailing zeros (and a bare point)
/// removed, and no negative zero: deterministic text that slicers and KDL readers parse alike.
pub(crate) fn number(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    };
    if text == "-0" {
        "0".to_string()
    } else {
        text
    }
}
