//! The cells within a distance of a raster's marked cells, exactly: a dilation by the disk of
//! integer offsets, row by row.

use std::ops::Range;

/// The cells of a raster (`columns` × `rows`, row by row) near a marked cell: those whose
/// squared distance `d` (in cells, between cell centres) to the nearest marked cell passes
/// `within(d)`, among the box of the marked cells grown by `reach` and a cell; none without a
/// marked cell. `within` must be monotone (true for every smaller squared distance when true for
/// one); it may not hold within `reach`, but it must not hold past it.
///
/// Squared distances between cell centres are integers, exact in `f64`: the cells near a
/// marked one are those at the offsets (dx, dy) with `within(dx² + dy²)`, for each `dy` a run
/// of `dx` around 0. So each row is dilated by the run of each row offset, from the distance
/// along the row to its nearest marked cell, and the rows are joined: the same cells as the
/// exact Euclidean distance transform of the grown box, tested with `within`.
pub(super) fn near_marked(
    marked: &[bool],
    columns: usize,
    rows: usize,
    reach: f64,
    within: impl Fn(f64) -> bool,
) -> Vec<bool> {
    let mut near = vec![false; marked.len()];
    let Some((i, j)) = grown_marked_box(marked, columns, rows, reach) else {
        return near;
    };
    let width = i.len();
    let runs = half_widths(&within, width, j.len());
    if runs.is_empty() {
        return near;
    }
    // Per row of the box, each cell's distance along the row to its nearest marked cell; `None`
    // for a row without one.
    let gaps: Vec<Option<Vec<u32>>> = j
        .clone()
        .map(|row| row_gaps(&marked[row * columns + i.start..row * columns + i.end]))
        .collect();
    for (y, row) in j.clone().enumerate() {
        let out = &mut near[row * columns + i.start..row * columns + i.end];
        let (low, high) = (y.saturating_sub(runs.len() - 1), y + runs.len());
        for (source, gaps) in gaps.iter().enumerate().take(high).skip(low) {
            let Some(gaps) = gaps else {
                continue;
            };
            let run = runs[y.abs_diff(source)];
            for (cell, &gap) in out.iter_mut().zip(gaps) {
                *cell |= gap <= run;
            }
        }
    }
    near
}

/// For each row offset `dy` from 0 on, the largest column offset `dx` below `columns` with
/// `within(dx² + dy²)`, up to the first row offset (below `rows`) without one; `within` is
/// monotone.
fn half_widths(within: &impl Fn(f64) -> bool, columns: usize, rows: usize) -> Vec<u32> {
    let mut runs = Vec::new();
    // One past the largest column offset within, for the row offset before.
    let mut end = columns;
    for dy in 0..rows {
        while end > 0 && !within(((end - 1) * (end - 1) + dy * dy) as f64) {
            end -= 1;
        }
        if end == 0 {
            break;
        }
        runs.push(u32::try_from(end - 1).unwrap_or(u32::MAX));
    }
    runs
}

/// Each cell's distance along `row` to the row's nearest marked cell; `None` without one.
fn row_gaps(row: &[bool]) -> Option<Vec<u32>> {
    let first = row.iter().position(|&m| m)?;
    let gap = |from: usize, to: usize| u32::try_from(from.abs_diff(to)).unwrap_or(u32::MAX);
    let mut gaps = vec![u32::MAX; row.len()];
    let mut last = first;
    for (x, (&m, g)) in row.iter().zip(gaps.iter_mut()).enumerate().skip(first) {
        if m {
            last = x;
        }
        *g = gap(x, last);
    }
    let mut next = row.len();
    for (x, (&m, g)) in row.iter().zip(gaps.iter_mut()).enumerate().rev() {
        if m {
            next = x;
        }
        if next < row.len() {
            *g = (*g).min(gap(x, next));
        }
    }
    Some(gaps)
}

/// The box of the marked cells (columns and rows, half-open) grown by `reach` and a cell on every
/// side (the whole raster for an infinite or NaN reach), within the raster; `None` without a
/// marked cell.
pub(super) fn grown_marked_box(
    marked: &[bool],
    columns: usize,
    rows: usize,
    reach: f64,
) -> Option<(Range<usize>, Range<usize>)> {
    let (i, j) = marked_box(marked, columns)?;
    let grow = if reach.is_finite() {
        reach.max(0.0).ceil() as usize + 1
    } else {
        columns.max(rows)
    };
    Some((
        i.start.saturating_sub(grow)..(i.end + grow).min(columns),
        j.start.saturating_sub(grow)..(j.end + grow).min(rows),
    ))
}

/// The columns and rows (half-open) of the smallest box holding every marked cell; `None`
/// without one.
fn marked_box(marked: &[bool], columns: usize) -> Option<(Range<usize>, Range<usize>)> {
    let mut found: Option<(Range<usize>, Range<usize>)> = None;
    for (row, line) in marked.chunks(columns).enumerate() {
        // A scan without a short cut first (vectorized): most rows hold no marked cell.
        if !line.iter().fold(false, |any, &m| any | m) {
            continue;
        }
        let (Some(first), Some(last)) =
            (line.iter().position(|&m| m), line.iter().rposition(|&m| m))
        else {
            continue;
        };
        found = Some(match found {
            None => (first..last + 1, row..row + 1),
            Some((i, j)) => (i.start.min(first)..i.end.max(last + 1), j.start..row + 1),
        });
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Squared distance (in cells) from every cell centre to the nearest marked cell centre,
    /// exact (Felzenszwalb and Huttenlocher's two passes of lower envelopes of parabolas);
    /// `INFINITY` without marked cells: the reference [`near_marked`] is tested against.
    fn squared_distance(marked: &[bool], columns: usize, rows: usize) -> Vec<f64> {
        let mut grid: Vec<f64> = marked
            .iter()
            .map(|&m| if m { 0.0 } else { f64::INFINITY })
            .collect();
        let mut line = Vec::new();
        for i in 0..columns {
            line.clear();
            line.extend((0..rows).map(|j| grid[j * columns + i]));
            for (j, d) in lower_envelope(&line).into_iter().enumerate() {
                grid[j * columns + i] = d;
            }
        }
        for j in 0..rows {
            let row = &mut grid[j * columns..(j + 1) * columns];
            let lowered = lower_envelope(row);
            row.copy_from_slice(&lowered);
        }
        grid
    }

    /// [`squared_distance`] over the box of the marked cells grown by `reach` and a cell,
    /// `INFINITY` outside it.
    fn squared_distance_within(
        marked: &[bool],
        columns: usize,
        rows: usize,
        reach: f64,
    ) -> Vec<f64> {
        let mut distance = vec![f64::INFINITY; marked.len()];
        let Some((i, j)) = grown_marked_box(marked, columns, rows, reach) else {
            return distance;
        };
        let (width, height) = (i.len(), j.len());
        let mut held = Vec::with_capacity(width * height);
        for row in j.clone() {
            held.extend_from_slice(&marked[row * columns + i.start..row * columns + i.end]);
        }
        let near = squared_distance(&held, width, height);
        for (row, line) in j.zip(near.chunks(width)) {
            distance[row * columns + i.start..row * columns + i.end].copy_from_slice(line);
        }
        distance
    }

    /// `min_q f(q) + (p − q)²` for every `p`.
    fn lower_envelope(f: &[f64]) -> Vec<f64> {
        let (mut v, mut z): (Vec<usize>, Vec<f64>) = (Vec::new(), Vec::new());
        let mut out = vec![f64::INFINITY; f.len()];
        let meet = |a: usize, b: usize| {
            ((f[b] + (b * b) as f64) - (f[a] + (a * a) as f64)) / (2.0 * (b as f64 - a as f64))
        };
        for q in (0..f.len()).filter(|&q| f[q].is_finite()) {
            while let Some(&last) = v.last() {
                let s = meet(last, q);
                if v.len() > 1 && s <= z[z.len() - 1] {
                    v.pop();
                    z.pop();
                } else {
                    z.push(s);
                    break;
                }
            }
            v.push(q);
        }
        if v.is_empty() {
            return out;
        }
        let mut k = 0;
        for (p, value) in out.iter_mut().enumerate() {
            while k + 1 < v.len() && z[k] < p as f64 {
                k += 1;
            }
            let d = p as f64 - v[k] as f64;
            *value = d * d + f[v[k]];
        }
        out
    }

    #[test]
    fn the_cells_near_marked_ones_are_those_the_distance_transform_finds() {
        let mut random = crate::random::SplitMix64::new(0x9e37_79b9_7f4a_7c15);
        let mut next = move || random.unit();
        // Reaches whose square is an integer (where `<` and `≤` part), between, tiny, huge,
        // negative (the box alone bounds the cells) and not a number.
        let reaches = [
            -3.0,
            0.0,
            0.3,
            1.0,
            2.0f64.sqrt(),
            2.5,
            5.0,
            50.0f64.sqrt(),
            10.4,
            f64::INFINITY,
            f64::NAN,
        ];
        for case in 0..400 {
            let (columns, rows) = (1 + (next() * 60.0) as usize, 1 + (next() * 40.0) as usize);
            let density = [0.0, 0.002, 0.02, 0.2, 0.7][case % 5];
            let marked: Vec<bool> = (0..columns * rows).map(|_| next() < density).collect();
            let reach = if case % 3 == 0 {
                next() * 12.0
            } else {
                reaches[case % reaches.len()]
            };
            let limit = reach * reach;
            let distance = squared_distance_within(&marked, columns, rows, reach);
            let below = near_marked(&marked, columns, rows, reach, |d| d < limit);
            let expected: Vec<bool> = distance.iter().map(|&d| d < limit).collect();
            assert_eq!(below, expected, "{columns} × {rows}, reach {reach}, <");
            if marked.iter().any(|&m| m) {
                let at_most = near_marked(&marked, columns, rows, reach, |d| d <= limit);
                let expected: Vec<bool> = distance.iter().map(|&d| d <= limit).collect();
                assert_eq!(at_most, expected, "{columns} × {rows}, reach {reach}, ≤");
            }
        }
    }
}
