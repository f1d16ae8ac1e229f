//! The exact Euclidean distance transform of a raster.

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
