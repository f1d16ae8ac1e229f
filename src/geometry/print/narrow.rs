//! The parts of a solid strip too narrow to fill, grown: PrusaSlicer's widening of the solid
//! that a top or bottom surface adds to a layer next to it, on the raster.

use super::distance::{grown_marked_box, near_marked};

/// Over a box `columns` wide (row by row): the cells of `fill` within `widening` (in cells) of
/// the parts of `strip` (a set of `fill`'s cells) that an opening by `widening` removes, those
/// narrower than twice it (`PrintObject::discover_horizontal_shells`: `too_narrow`, the strip
/// less its opening, grown by the margin within the layer's internal fill); `None` when no part
/// is that narrow.
///
/// Distances run between cell centres, and a set's edge lies half a cell past its outermost
/// centres: each of the three steps (the erosion and the dilation of the opening, the growth)
/// reaches half a cell further than `widening`. Past the box's edge no cell is seen, in the
/// strip or out of it, so the result is exact only beyond three such reaches from the edge.
pub(super) fn widened_narrow(
    strip: &[bool],
    fill: &[bool],
    columns: usize,
    widening: f64,
) -> Option<Vec<bool>> {
    debug_assert_eq!(strip.len(), fill.len());
    if columns == 0 {
        return None;
    }
    let rows = strip.len() / columns;
    let reach = widening + 0.5;
    // Only the cells within three reaches of the strip can change: its box grown by those.
    let (i, j) = grown_marked_box(strip, columns, rows, 3.0 * reach)?;
    let width = i.len();
    let part = |cells: &[bool]| -> Vec<bool> {
        j.clone()
            .flat_map(|y| &cells[y * columns + i.start..y * columns + i.end])
            .copied()
            .collect()
    };
    let grown = widened_in_box(&part(strip), &part(fill), width, reach)?;
    let mut widened = vec![false; strip.len()];
    for (y, row) in j.zip(grown.chunks(width)) {
        widened[y * columns + i.start..][..width].copy_from_slice(row);
    }
    Some(widened)
}

/// [`widened_narrow`] over a box `columns` wide holding every cell it can change, with each
/// step's `reach` (in cells).
fn widened_in_box(strip: &[bool], fill: &[bool], columns: usize, reach: f64) -> Option<Vec<bool>> {
    let rows = strip.len() / columns;
    let limit = reach * reach;
    let near = |marked: &[bool]| near_marked(marked, columns, rows, reach, |d| d <= limit);
    // The opening: the strip's cells farther than the reach from every cell outside it, grown
    // back by the reach within the strip.
    let outside: Vec<bool> = strip.iter().map(|&s| !s).collect();
    let eroded: Vec<bool> = near(&outside)
        .iter()
        .zip(strip)
        .map(|(&n, &s)| s && !n)
        .collect();
    let opened = near(&eroded);
    let narrow: Vec<bool> = strip.iter().zip(&opened).map(|(&s, &o)| s && !o).collect();
    if !narrow.iter().fold(false, |any, &n| any | n) {
        return None;
    }
    let grown = near(&narrow);
    Some(grown.iter().zip(fill).map(|(&g, &f)| g && f).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box `columns` wide with the columns `from..to` of every row marked.
    fn band(columns: usize, rows: usize, from: usize, to: usize) -> Vec<bool> {
        (0..columns * rows)
            .map(|c| (from..to).contains(&(c % columns)))
            .collect()
    }

    #[test]
    fn a_band_narrower_than_twice_the_widening_grows_by_it_within_the_fill() {
        let (columns, rows) = (40, 30);
        let fill = vec![true; columns * rows];
        // Three cells wide, widened by four: the band and four cells on either side.
        let grown = widened_narrow(&band(columns, rows, 18, 21), &fill, columns, 4.0).unwrap();
        assert_eq!(grown, band(columns, rows, 14, 25));
        // Within the fill only.
        let half = band(columns, rows, 0, 20);
        let grown = widened_narrow(&band(columns, rows, 18, 21), &half, columns, 4.0).unwrap();
        assert_eq!(grown, band(columns, rows, 14, 20));
    }

    #[test]
    fn a_band_wider_than_twice_the_widening_is_not_widened() {
        let (columns, rows) = (40, 30);
        let fill = vec![true; columns * rows];
        // Twelve cells wide against a widening of four, away from the box's edges along x: its
        // ends at the box's top and bottom rows see nothing past the edge, and are not narrow.
        let strip = band(columns, rows, 14, 26);
        assert_eq!(widened_narrow(&strip, &fill, columns, 4.0), None);
        // No strip, nothing widened.
        assert_eq!(widened_narrow(&[false; 12], &fill[..12], 4, 4.0), None);
    }
}
