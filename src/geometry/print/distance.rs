//! The exact Euclidean distance transform of a raster.

/// Squared distance (in cells) from every cell centre to the nearest marked cell centre, exact
/// (Felzenszwalb and Huttenlocher's two passes of lower envelopes of parabolas); `INFINITY`
/// without marked cells.
pub(super) fn squared_distance(marked: &[bool], columns: usize, rows: usize) -> Vec<f64> {
    let mut grid: Vec<f64> = marked
        .iter()
        .map(|&m| if m { 0.0 } else { f64::INFINITY })
        .collect();
    let mut line = Vec::new();
    for i in 0..columns {
        line.clear();
        line.extend((0..rows).map(|j| grid[j * columns + i]));
        let out = envelope(&line);
        for (j, d) in out.into_iter().enumerate() {
            grid[j * columns + i] = d;
        }
    }
    for j in 0..rows {
        let row = &mut grid[j * columns..(j + 1) * columns];
        let out = envelope(row);
        row.copy_from_slice(&out);
    }
    grid
}

/// One pass of [`squared_distance`]: `min_q f(q) + (p − q)²` for every `p`.
fn envelope(f: &[f64]) -> Vec<f64> {
    let n = f.len();
    let mut out = vec![f64::INFINITY; n];
    let sites: Vec<usize> = (0..n).filter(|&q| f[q].is_finite()).collect();
    if sites.is_empty() {
        return out;
    }
    // Parabola apexes `v` and the boundaries `z` between them.
    let mut v: Vec<usize> = Vec::with_capacity(sites.len());
    let mut z: Vec<f64> = Vec::with_capacity(sites.len() + 1);
    let meet = |a: usize, b: usize| {
        ((f[b] + (b * b) as f64) - (f[a] + (a * a) as f64)) / (2.0 * (b as f64 - a as f64))
    };
    for &q in &sites {
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
    // z[i] is the boundary between v[i] and v[i + 1].
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
