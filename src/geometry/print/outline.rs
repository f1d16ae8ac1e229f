//! A slice's outline: the parts of its segments on the boundary of its union, read from where
//! they cross the raster's rows and columns (a segment that crosses neither, at its middle).

use super::layout::Segment;

/// Where a segment crosses a row (or a column) of the raster, and whether the slice's union
/// begins or ends there (the crossings at one place taken together, so that two shells that
/// touch have no outline between them).
#[derive(Debug, Clone, Copy)]
pub(super) struct Mark {
    /// The segment's index in the slice.
    pub(super) segment: u32,
    /// How far along the segment, from its first end (0) to its second (1).
    pub(super) along: f64,
    /// Whether the union begins or ends there.
    pub(super) bounds: bool,
    /// Found on a row (else on a column).
    pub(super) by_row: bool,
}

/// The segments of a slice whose span along one axis may hold a given value: uniform bands over
/// the span of all of them, each listing the segments that reach into it, so that a query reads
/// one band's segments instead of every segment.
struct Bands {
    low: f64,
    /// Width of a band (0 when every segment spans one value).
    width: f64,
    members: Vec<Vec<u32>>,
}

impl Bands {
    /// The bands of `segments` along the axis `span` gives each one's ends on.
    fn new(segments: &[Segment], span: impl Fn(&Segment) -> (f64, f64)) -> Bands {
        let spans: Vec<(f64, f64)> = segments
            .iter()
            .map(|segment| {
                let (a, b) = span(segment);
                (a.min(b), a.max(b))
            })
            .collect();
        let low = spans.iter().map(|s| s.0).fold(f64::INFINITY, f64::min);
        let high = spans.iter().map(|s| s.1).fold(f64::NEG_INFINITY, f64::max);
        // About as many bands as segments in a band, for short segments.
        let count = (segments.len() as f64).sqrt().ceil().max(1.0) as usize;
        let width = if high > low {
            (high - low) / count as f64
        } else {
            0.0
        };
        let mut bands = Bands {
            low,
            width,
            members: vec![Vec::new(); count],
        };
        for (index, &(from, to)) in spans.iter().enumerate() {
            for band in bands.band(from)..=bands.band(to) {
                bands.members[band].push(index as u32);
            }
        }
        bands
    }

    /// The band holding `at` (the first or last for a value beyond them all). It never falls as
    /// `at` grows, so a segment whose span holds `at` is listed in it.
    fn band(&self, at: f64) -> usize {
        if self.width > 0.0 {
            (((at - self.low) / self.width).floor().max(0.0) as usize).min(self.members.len() - 1)
        } else {
            0
        }
    }

    /// The segments that may reach `at`.
    fn near(&self, at: f64) -> &[u32] {
        &self.members[self.band(at)]
    }
}

/// The segments along the rows' direction and along the columns', indexed for
/// [`Middles::bounds`].
struct Middles<'a> {
    segments: &'a [Segment],
    /// By their span along v (for lines along a row).
    by_v: Bands,
    /// By their span along u (for lines along a column).
    by_u: Bands,
}

impl<'a> Middles<'a> {
    fn new(segments: &'a [Segment]) -> Middles<'a> {
        Middles {
            segments,
            by_v: Bands::new(segments, |s| (s.ends[0].1, s.ends[1].1)),
            by_u: Bands::new(segments, |s| (s.ends[0].0, s.ends[1].0)),
        }
    }

    /// Whether segment `index`, one that crosses no row and no column, bounds the slice's union
    /// at its middle: whether the winding number just before it along the line through its
    /// middle (a row's direction, or a column's for a segment along a row) and just after it lie
    /// on either side of zero. A segment of no length bounds nothing.
    fn bounds(&self, index: usize) -> bool {
        let segments = self.segments;
        let [(u0, v0), (u1, v1)] = segments[index].ends;
        let (u, v) = ((u0 + u1) / 2.0, (v0 + v1) / 2.0);
        // Along a row (through v), or along a column (through u) for a segment along a row.
        let by_row = v0 != v1;
        if !by_row && u0 == u1 {
            return false;
        }
        let (at, across, turn, near) = if by_row {
            (v, u, segments[index].winding, self.by_v.near(v))
        } else {
            (u, v, segments[index].column_winding, self.by_u.near(u))
        };
        // The winding number just before the segment: the turns of every other segment crossed
        // before it (each counted on the half-open span of its ends, so a shared end counts
        // once).
        let before: i32 = near
            .iter()
            .map(|&other| other as usize)
            .filter(|&other| other != index)
            .filter_map(|other| {
                let segment = &segments[other];
                let [(a0, b0), (a1, b1)] = segment.ends;
                let (from, to, p0, p1, turn) = if by_row {
                    (b0, b1, a0, a1, segment.winding)
                } else {
                    (a0, a1, b0, b1, segment.column_winding)
                };
                let (low, high) = (from.min(to), from.max(to));
                if !(low <= at && at < high) {
                    return None;
                }
                let crossing = p0 + (at - from) / (to - from) * (p1 - p0);
                (crossing < across).then_some(i32::from(turn))
            })
            .sum();
        (before > 0) != (before + i32::from(turn) > 0)
    }
}

/// The parts of `segments` on the outline of the slice's union, from `marks`. A segment is
/// judged by its row crossings, or by its column crossings when it crosses no row (one along a
/// row), or at its middle when it crosses neither. One every crossing of which bounds the union
/// is outline whole (every segment of a mesh that does not cross itself); one none of whose crossings do
/// is a wall hidden inside another shell, and left out; one that passes from outline to hidden
/// keeps its outline part, to halfway between the crossings where it changes.
pub(super) fn outline(segments: &[Segment], mut marks: Vec<Mark>) -> Vec<Segment> {
    let n = segments.len();
    let mut by_row = vec![false; n];
    for mark in &marks {
        by_row[mark.segment as usize] |= mark.by_row;
    }
    marks.retain(|mark| mark.by_row == by_row[mark.segment as usize]);
    let (mut crossed, mut bounding) = (vec![0u32; n], vec![0u32; n]);
    for mark in &marks {
        crossed[mark.segment as usize] += 1;
        bounding[mark.segment as usize] += u32::from(mark.bounds);
    }
    // A segment between two rows and two columns is judged at its middle (the index built at
    // the first: most slices have none).
    let middles = std::cell::OnceCell::new();
    let mut kept: Vec<Segment> = segments
        .iter()
        .enumerate()
        .filter(|&(index, _)| match crossed[index] {
            0 => middles.get_or_init(|| Middles::new(segments)).bounds(index),
            crossings => bounding[index] == crossings,
        })
        .map(|(_, segment)| *segment)
        .collect();
    marks.retain(|mark| {
        let index = mark.segment as usize;
        bounding[index] > 0 && bounding[index] < crossed[index]
    });
    marks.sort_by(|a, b| a.segment.cmp(&b.segment).then(a.along.total_cmp(&b.along)));
    for group in marks.chunk_by(|a, b| a.segment == b.segment) {
        let segment = segments[group[0].segment as usize];
        let [(u0, v0), (u1, v1)] = segment.ends;
        let at = |t: f64| (u0 + t * (u1 - u0), v0 + t * (v1 - v0));
        // Breakpoints along the segment, each with whether it bounds the union there.
        let mut points: Vec<(f64, bool)> = Vec::with_capacity(group.len() + 2);
        points.push((0.0, group[0].bounds));
        points.extend(group.iter().map(|mark| (mark.along, mark.bounds)));
        points.push((1.0, group[group.len() - 1].bounds));
        let mut piece: Option<(f64, f64)> = None;
        let mut emit = |(from, to): (f64, f64)| {
            kept.push(Segment {
                ends: [at(from), at(to)],
                ..segment
            })
        };
        for pair in points.windows(2) {
            let ((a, on_a), (b, on_b)) = (pair[0], pair[1]);
            let middle = (a + b) / 2.0;
            let part = match (on_a, on_b) {
                (true, true) => Some((a, b)),
                (true, false) => Some((a, middle)),
                (false, true) => Some((middle, b)),
                (false, false) => None,
            };
            piece = match (piece, part) {
                (Some((start, end)), Some((from, to))) if from <= end => Some((start, to)),
                (Some(done), next) => {
                    emit(done);
                    next
                }
                (None, next) => next,
            };
        }
        if let Some(done) = piece {
            emit(done);
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix64;

    #[test]
    fn a_band_lists_every_segment_whose_span_holds_the_value() {
        let mut random = SplitMix64::new(7);
        let mut next = || random.unit();
        for count in [1, 2, 5, 40, 300] {
            let segments: Vec<Segment> = (0..count)
                .map(|_| {
                    let (u, v) = (next() * 10.0, next() * 10.0);
                    // Mostly short, a few across the whole slice.
                    let reach = if next() < 0.1 { 10.0 } else { 0.3 };
                    Segment {
                        ends: [
                            (u, v),
                            (u + (next() - 0.5) * reach, v + (next() - 0.5) * reach),
                        ],
                        winding: 1,
                        column_winding: -1,
                    }
                })
                .collect();
            let bands = Bands::new(&segments, |s| (s.ends[0].1, s.ends[1].1));
            let mut queries: Vec<f64> = (0..200).map(|_| next() * 14.0 - 2.0).collect();
            queries.extend(segments.iter().flat_map(|s| [s.ends[0].1, s.ends[1].1]));
            for at in queries {
                let near = bands.near(at);
                for (index, segment) in segments.iter().enumerate() {
                    let (a, b) = (segment.ends[0].1, segment.ends[1].1);
                    if a.min(b) <= at && at <= a.max(b) {
                        assert!(
                            near.contains(&(index as u32)),
                            "{count} segments: segment {index} spans {a}..{b} but is not near {at}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn segments_on_one_line_share_one_band() {
        let segment = |u: f64| Segment {
            ends: [(u, 2.0), (u + 0.1, 2.0)],
            winding: 0,
            column_winding: 1,
        };
        let segments = [segment(0.0), segment(1.0), segment(2.0)];
        let bands = Bands::new(&segments, |s| (s.ends[0].1, s.ends[1].1));
        assert_eq!(bands.near(2.0), &[0, 1, 2]);
        assert_eq!(bands.near(-5.0), &[0, 1, 2]);
    }
}
