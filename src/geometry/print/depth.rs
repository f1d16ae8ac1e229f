//! Each inside cell's exact distance to its layer's outline (its depth), up to a range: what
//! the widened strips and a void's hole read.

use super::cells::CellBox;
use super::layout::{Layout, Segment};
use super::sides::Sides;

/// How deep into a slice [`Layout::depth`] measures.
pub(super) const DEPTH_RANGE: f64 = 5.5;

/// A cell's depth from its squared distance to the outline: the distance within
/// `DEPTH_RANGE`, infinite beyond, −1 for a cell outside.
pub(super) fn depth_value(inside: bool, distance2: f64) -> f32 {
    match (inside, distance2 <= DEPTH_RANGE * DEPTH_RANGE) {
        (false, _) => -1.0,
        (true, true) => distance2.sqrt() as f32,
        (true, false) => f32::INFINITY,
    }
}

impl Layout {
    /// Each inside cell's distance from its centre to the outline, up to `DEPTH_RANGE`
    /// (infinite beyond); −1 outside.
    pub(super) fn depth(&self, segments: &[Segment], inside: &[bool]) -> Vec<f32> {
        let ends: Vec<[(f64, f64); 2]> = segments.iter().map(|s| s.ends).collect();
        let whole = CellBox::whole(self);
        self.distances(&whole, &ends, inside)
            .into_iter()
            .zip(inside)
            .map(|(d2, &inside)| depth_value(inside, d2))
            .collect()
    }

    /// Over `area` (and `inside`, its inside cells in its order): each inside cell's squared
    /// distance from its centre to the nearest of `segments`, where that is within
    /// `DEPTH_RANGE` (and about two cells more); infinite beyond. The cells within a cell and a
    /// half of a segment measure every segment near them; the others take the nearest segment
    /// of an inside neighbour, passed on in two sweeps (a feature transform: each distance is
    /// exact to the segment it names, and that segment is the nearest but in rare corners; the
    /// straight line from a cell to its nearest outline point lies inside, so inside cells
    /// suffice).
    pub(super) fn distances(
        &self,
        area: &CellBox,
        segments: &[[(f64, f64); 2]],
        inside: &[bool],
    ) -> Vec<f64> {
        let (columns, rows) = (area.width(), area.height());
        let mut nearest = vec![u32::MAX; columns * rows];
        let mut best = vec![f64::INFINITY; columns * rows];
        let centre = |x: usize, y: usize| {
            (
                self.origin.0 + ((area.i.start + x) as f64 + 0.5) * self.cell,
                self.origin.1 + ((area.j.start + y) as f64 + 0.5) * self.cell,
            )
        };
        let sides = Sides::new(segments);
        let distance2 = |s: u32, point: (f64, f64)| sides.distance2(s as usize, point);
        let reach = 1.5 * self.cell;
        // The area's cells whose centres lie in [low − reach, high + reach] along one axis.
        let span = |low: f64, high: f64, origin: f64, from: usize, count: usize| {
            let first = ((low - reach - origin) / self.cell - 0.5)
                .ceil()
                .max(from as f64);
            let last = ((high + reach - origin) / self.cell - 0.5).floor();
            let end = (last + 1.0).min((from + count) as f64);
            (first < end).then(|| first as usize - from..end as usize - from)
        };
        for (index, &[(u0, v0), (u1, v1)]) in segments.iter().enumerate() {
            let near_columns = span(u0.min(u1), u0.max(u1), self.origin.0, area.i.start, columns);
            let near_rows = span(v0.min(v1), v0.max(v1), self.origin.1, area.j.start, rows);
            let (Some(near_columns), Some(near_rows)) = (near_columns, near_rows) else {
                continue;
            };
            for y in near_rows {
                for x in near_columns.clone() {
                    let c = y * columns + x;
                    if !inside[c] {
                        continue;
                    }
                    let d2 = distance2(index as u32, centre(x, y));
                    if d2 < best[c] {
                        best[c] = d2;
                        nearest[c] = index as u32;
                    }
                }
            }
        }
        // A neighbour further than this from its segment cannot bring a cell within the range.
        let band = DEPTH_RANGE + 2.0 * self.cell;
        let band2 = band * band;
        let mut offer = |c: usize, from: usize, at: (f64, f64)| {
            let s = nearest[from];
            if s == u32::MAX || s == nearest[c] || best[from] > band2 {
                return;
            }
            let d2 = distance2(s, at);
            if d2 < best[c] {
                best[c] = d2;
                nearest[c] = s;
            }
        };
        for y in 0..rows {
            for x in 0..columns {
                let c = y * columns + x;
                if !inside[c] {
                    continue;
                }
                let at = centre(x, y);
                if x > 0 {
                    offer(c, c - 1, at);
                }
                if y > 0 {
                    offer(c, c - columns, at);
                    if x > 0 {
                        offer(c, c - columns - 1, at);
                    }
                    if x + 1 < columns {
                        offer(c, c - columns + 1, at);
                    }
                }
            }
            for x in (0..columns.saturating_sub(1)).rev() {
                let c = y * columns + x;
                if inside[c] {
                    offer(c, c + 1, centre(x, y));
                }
            }
        }
        for y in (0..rows).rev() {
            for x in (0..columns).rev() {
                let c = y * columns + x;
                if !inside[c] {
                    continue;
                }
                let at = centre(x, y);
                if x + 1 < columns {
                    offer(c, c + 1, at);
                }
                if y + 1 < rows {
                    offer(c, c + columns, at);
                    if x + 1 < columns {
                        offer(c, c + columns + 1, at);
                    }
                    if x > 0 {
                        offer(c, c + columns - 1, at);
                    }
                }
            }
            for x in 1..columns {
                let c = y * columns + x;
                if inside[c] {
                    offer(c, c - 1, centre(x, y));
                }
            }
        }
        best
    }
}
