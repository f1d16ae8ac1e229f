//! The exact Euclidean distance transform of a raster.

use std::ops::Range;

/// Squared distance (in cells) from every cell centre to the nearest marked cell centre, exact
/// (Felzenszwalb and Huttenlocher's two passes of lower envelopes of parabolas); `INFINITY`
/// without marked cells.
pub(super) fn squared_distance(marked: &[bool], columns: usize, rows: usize) -> Vec<f64> {
    let mut grid: Vec<f64> = marked
        .iter()
        .map(|&m| if m { 0.0 } else { f64::INFINITY })
        .collect();
    let mut pass = Envelope::default();
    let mut line = Vec::new();
    for i in 0..columns {
        line.clear();
        line.extend((0..rows).map(|j| grid[j * columns + i]));
        pass.lower(&line);
        for (j, d) in pass.out.iter().enumerate() {
            grid[j * columns + i] = *d;
        }
    }
    for j in 0..rows {
        let row = &mut grid[j * columns..(j + 1) * columns];
        pass.lower(row);
        row.copy_from_slice(&pass.out);
    }
    grid
}

/// [`squared_distance`] for every cell within `reach` cells of a marked cell; `INFINITY` for
/// the cells farther than that. Only the box of the marked cells grown by the reach is
/// transformed: every marked cell lies in it, so each distance there is exact.
pub(super) fn squared_distance_within(
    marked: &[bool],
    columns: usize,
    rows: usize,
    reach: f64,
) -> Vec<f64> {
    let mut distance = vec![f64::INFINITY; marked.len()];
    let Some((i, j)) = marked_box(marked, columns) else {
        return distance;
    };
    let grow = if reach.is_finite() {
        reach.max(0.0).ceil() as usize + 1
    } else {
        columns.max(rows)
    };
    let i = i.start.saturating_sub(grow)..(i.end + grow).min(columns);
    let j = j.start.saturating_sub(grow)..(j.end + grow).min(rows);
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

/// The columns and rows (half-open) of the smallest box holding every marked cell; `None`
/// without one.
fn marked_box(marked: &[bool], columns: usize) -> Option<(Range<usize>, Range<usize>)> {
    let mut found: Option<(Range<usize>, Range<usize>)> = None;
    for (row, line) in marked.chunks(columns).enumerate() {
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

/// One pass of [`squared_distance`], its buffers kept between lines.
#[derive(Default)]
struct Envelope {
    /// Parabola apexes.
    v: Vec<usize>,
    /// The boundaries between them: `z[i]` between `v[i]` and `v[i + 1]`.
    z: Vec<f64>,
    /// The pass's result.
    out: Vec<f64>,
}

impl Envelope {
    /// `out[p] = min_q f(q) + (p − q)²` for every `p`.
    fn lower(&mut self, f: &[f64]) {
        let (v, z) = (&mut self.v, &mut self.z);
        v.clear();
        z.clear();
        self.out.clear();
        self.out.resize(f.len(), f64::INFINITY);
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
            return;
        }
        let mut k = 0;
        for (p, value) in self.out.iter_mut().enumerate() {
            while k + 1 < v.len() && z[k] < p as f64 {
                k += 1;
            }
            let d = p as f64 - v[k] as f64;
            *value = d * d + f[v[k]];
        }
    }
}
