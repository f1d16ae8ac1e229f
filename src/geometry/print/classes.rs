//! Each cell's class: outside, solid (perimeters, top and bottom layers, small regions) or
//! sparse, over a box of the raster and a range of layers.

use std::ops::{Range, RangeInclusive};

use super::cells::{CellBox, Overlay, Rows};
use super::distance::near_marked;
use super::layout::Layout;
use super::narrow::widened_narrow;
use crate::parallel::map_each;

/// What a raster cell of one layer holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Cell {
    Outside,
    /// Perimeters, and the layer's own top and bottom surfaces: never part of a sparse region.
    Solid,
    /// Solid for a surface of another layer (or a widened strip, or a surface's margin), but
    /// part of the layer's interior when the small-region rule measures it (before the rule).
    Shell,
    /// In an interior region smaller than the minimum area, filled solid by the rule.
    Small,
    Sparse,
}

impl Cell {
    /// Whether the small-region rule counts the cell in the layer's interior regions: what
    /// PrusaSlicer calls internal when it applies `solid_infill_below_area`
    /// (`LayerRegion::prepare_fill_surfaces`), before any shell is spread.
    pub(super) fn is_interior(self) -> bool {
        matches!(self, Cell::Shell | Cell::Sparse)
    }

    /// The cell's class once its interior region is known to be large.
    pub(super) fn in_large_region(self) -> Cell {
        match self {
            Cell::Shell => Cell::Solid,
            other => other,
        }
    }
}

/// A layer's top and bottom surface over the area; `None` for one without a cell (or one not
/// read).
struct Surfaces {
    top: Option<Vec<bool>>,
    bottom: Option<Vec<bool>>,
}

/// What the classes of a range of layers read: every layer's `inside` cells and perimeters
/// (`near`), and the top and bottom surfaces, over the planes' area.
pub(super) struct Classifier<'a> {
    layout: &'a Layout,
    inside: Overlay<'a>,
    near: Overlay<'a>,
    /// The layers classified.
    layers: RangeInclusive<usize>,
    /// Per layer from the first surface read on, its surfaces.
    surfaces: Vec<Surfaces>,
    /// The layer of `surfaces[0]`.
    surfaces_from: usize,
    /// Every layer's depth ([`Layout::depth`]).
    depth: Depths<'a>,
}

/// Every layer's depth of each cell ([`Layout::depth`]): the bare layer's, but within the
/// patch `held` has for a layer from `first` on (where a cut changes it).
#[derive(Clone, Copy)]
pub(super) struct Depths<'a> {
    pub(super) bare: &'a [Vec<f32>],
    pub(super) first: usize,
    pub(super) held: &'a [Option<DepthPatch>],
}

/// A layer's depths over a box of its cells (in the box's order).
#[derive(Debug, Clone)]
pub(super) struct DepthPatch {
    pub(super) cells: CellBox,
    pub(super) depth: Vec<f32>,
}

impl Depths<'_> {
    /// Layer `l`'s depths of columns `columns` of raster row `j`, in at most three pieces in
    /// order (some perhaps empty), each with where it starts among `columns`: the bare layer's,
    /// the patch's where it covers part of the row, the bare layer's again. Read in place.
    fn pieces(
        &self,
        l: usize,
        j: usize,
        columns: Range<usize>,
        raster: usize,
    ) -> [(usize, &[f32]); 3] {
        let bare = &self.bare[l][j * raster..][columns.clone()];
        let whole = [(0, bare), (0, &[][..]), (0, &[][..])];
        let patch = l
            .checked_sub(self.first)
            .and_then(|h| self.held.get(h)?.as_ref());
        let Some(patch) = patch.filter(|patch| patch.cells.j.contains(&j)) else {
            return whole;
        };
        let (from, to) = (
            columns.start.max(patch.cells.i.start),
            columns.end.min(patch.cells.i.end),
        );
        if from >= to {
            return whole;
        }
        let row = (j - patch.cells.j.start) * patch.cells.width();
        let (start, end) = (from - patch.cells.i.start, to - patch.cells.i.start);
        let (before, after) = (from - columns.start, to - columns.start);
        [
            (0, &bare[..before]),
            (before, &patch.depth[row + start..row + end]),
            (after, &bare[after..]),
        ]
    }

    /// Layer `l`'s depths of columns `columns` of raster row `j`: borrowed where one source holds
    /// them all, else patched together in `buffer`.
    fn row<'b>(
        &'b self,
        l: usize,
        j: usize,
        columns: Range<usize>,
        raster: usize,
        buffer: &'b mut Vec<f32>,
    ) -> &'b [f32] {
        let pieces = self.pieces(l, j, columns, raster);
        if let [(_, whole), (_, []), (_, [])] = pieces {
            return whole;
        }
        if let [(_, []), (_, whole), (_, [])] = pieces {
            return whole;
        }
        buffer.clear();
        for (_, piece) in pieces {
            buffer.extend_from_slice(piece);
        }
        buffer
    }
}

impl<'a> Classifier<'a> {
    /// The surfaces the classes of `layers` read, from every layer's `inside` cells, perimeters
    /// (`near`), both read over the same area, and `depth`.
    pub(super) fn new(
        layout: &'a Layout,
        inside: Overlay<'a>,
        near: Overlay<'a>,
        layers: RangeInclusive<usize>,
        depth: Depths<'a>,
    ) -> Classifier<'a> {
        debug_assert_eq!(inside.area(), near.area());
        let (low, high) = (*layers.start(), *layers.end());
        let count = layout.layers;
        let (top, bottom) = (layout.slicing.top_layers, layout.slicing.bottom_layers);
        // The top surfaces the classes read, and the bottom ones.
        let tops_to = high.saturating_add(top.saturating_sub(1)).min(count - 1);
        let bottoms_from = low.saturating_sub(bottom.saturating_sub(1));
        let surfaces = map_each(tops_to - bottoms_from + 1, |offset| {
            let k = bottoms_from + offset;
            let of = |next: Option<usize>| {
                let layer = Layer {
                    here: inside.rows(k)?,
                    rim: near.rows(k)?,
                    index: k,
                };
                let next = next.and_then(|l| Some((inside.rows(l)?, l)));
                surface(layout, inside.area(), layer, next, depth)
            };
            let top = (k >= low).then(|| of(k.checked_add(1))).flatten();
            let bottom = (k <= high).then(|| of(k.checked_sub(1))).flatten();
            Surfaces { top, bottom }
        });
        Classifier {
            layout,
            inside,
            near,
            layers,
            surfaces,
            surfaces_from: bottoms_from,
            depth,
        }
    }

    /// The class of every cell of `valid` in layer `k` (one of the layers classified) before
    /// the small-region rule, written to `classes` (the whole layer, row by row). `valid` must
    /// lie within the area grown back by the surface margin, the raster's strips' reach
    /// ([`strip_reach`]) and a cell.
    pub(super) fn layer(&self, k: usize, valid: &CellBox, classes: &mut [Cell]) {
        debug_assert!(self.layers.contains(&k));
        let (layout, area) = (self.layout, self.inside.area());
        let (top, bottom) = (layout.slicing.top_layers, layout.slicing.bottom_layers);
        let (Some(here), Some(rim)) = (self.inside.rows(k), self.near.rows(k)) else {
            return;
        };
        // The solid layers above and below; `None` when one is past the raster (outside: every
        // cell under or over it is uncovered).
        let covering: Option<Vec<Rows>> = (1..=top)
            .map(|d| self.inside.rows(k + d))
            .chain((1..=bottom).map(|d| k.checked_sub(d).and_then(|l| self.inside.rows(l))))
            .collect();
        let widened = covering
            .is_some()
            .then(|| self.widened(k, here, rim, valid))
            .flatten();
        let held = |l: usize| self.surfaces.get(l.checked_sub(self.surfaces_from)?);
        let surfaces: Vec<Rows> = (0..top)
            .filter_map(|d| held(k + d)?.top.as_deref())
            .chain((0..bottom).filter_map(|d| held(k.checked_sub(d)?)?.bottom.as_deref()))
            .map(|cells| Rows::held(cells, area))
            .collect();
        // Where `valid`'s columns lie in the area's.
        let (width, from) = (valid.width(), valid.i.start - area.i.start);
        let columns = from..from + width;
        // The layers just above and below: the cells either leaves uncovered are the layer's own
        // top and bottom surfaces (`None` past the raster: all of them).
        let above = self.inside.rows(k + 1);
        let below = k.checked_sub(1).and_then(|l| self.inside.rows(l));
        let mut own = vec![false; width];
        let mut shell = vec![false; width];
        for j in valid.j.clone() {
            let y = j - area.j.start;
            // The perimeters and the layer's own surfaces.
            own.copy_from_slice(rim.part(y, columns.clone()));
            for next in [above, below] {
                match next {
                    Some(next) => {
                        for (o, &c) in own.iter_mut().zip(next.part(y, columns.clone())) {
                            *o |= !c;
                        }
                    }
                    None => own.fill(true),
                }
            }
            // The cells some solid layer above or below leaves uncovered, and the surfaces.
            match &covering {
                Some(covering) => {
                    shell.fill(false);
                    for layer in covering {
                        for (s, &c) in shell.iter_mut().zip(layer.part(y, columns.clone())) {
                            *s |= !c;
                        }
                    }
                    for layer in &surfaces {
                        for (s, &c) in shell.iter_mut().zip(layer.part(y, columns.clone())) {
                            *s |= c;
                        }
                    }
                    if let Some(widened) = &widened {
                        let row = &widened[(j - valid.j.start) * width..][..width];
                        for (s, &c) in shell.iter_mut().zip(row) {
                            *s |= c;
                        }
                    }
                }
                None => shell.fill(true),
            }
            let start = j * layout.columns + valid.i.start;
            let cells = classes[start..start + width].iter_mut();
            let here = here.part(y, columns.clone());
            for (class, ((&h, &o), &s)) in cells.zip(here.iter().zip(&own).zip(&shell)) {
                *class = match (h, o, s) {
                    (false, _, _) => Cell::Outside,
                    (true, true, _) => Cell::Solid,
                    (true, false, true) => Cell::Shell,
                    (true, false, false) => Cell::Sparse,
                };
            }
        }
    }
}

impl Classifier<'_> {
    /// Layer `k`'s widened strips over `valid` (in its order): where the solid that the top
    /// surface of a layer above (`top_layers − 1` at most) or the bottom surface of a layer
    /// below adds to `k`'s fill, less `k`'s own surfaces, is narrower than twice the widening,
    /// the strip grown by the widening within that fill (`PrintObject::discover_horizontal_shells`:
    /// a strip that narrow would collapse); `None` when no strip is narrow. The slivers a
    /// surface's slice adds are found from the exact depths ([`mark_strips`]), the strips its
    /// margin adds on the raster ([`Classifier::narrow_margins`]).
    fn widened(&self, k: usize, here: Rows, rim: Rows, valid: &CellBox) -> Option<Vec<bool>> {
        let (layout, area) = (self.layout, self.inside.area());
        let slicing = &layout.slicing;
        let w = slicing.shell_widening as f32;
        let depth = self.depth;
        if w <= 0.0 {
            return None;
        }
        let f = slicing.fill_boundary as f32;
        let held = |l: usize| self.surfaces.get(l.checked_sub(self.surfaces_from)?);
        // Where `valid` lies in the area.
        let (width, from) = (valid.width(), valid.i.start - area.i.start);
        let columns = from..from + width;
        let rows = valid.j.start - area.j.start..valid.j.end - area.j.start;
        // The layer's fill less its own top and bottom surfaces, over `valid` grown by what the
        // raster's strips read.
        let own = held(k)?;
        let wide = valid.grown(strip_reach(layout), layout).within(area)?;
        let wide_columns = wide.i.start - area.i.start..wide.i.end - area.i.start;
        let wide_rows = wide.j.start - area.j.start..wide.j.end - area.j.start;
        let mut internal_wide = Vec::with_capacity(wide.len());
        for y in wide_rows.clone() {
            let (h, r) = (
                here.part(y, wide_columns.clone()),
                rim.part(y, wide_columns.clone()),
            );
            internal_wide.extend(h.iter().zip(r).map(|(&h, &r)| h && !r));
        }
        for surface in [&own.top, &own.bottom].into_iter().flatten() {
            let surface = Rows::held(surface, area);
            let chunks = internal_wide.chunks_mut(wide.width());
            for (y, internal) in wide_rows.clone().zip(chunks) {
                for (i, &s) in internal
                    .iter_mut()
                    .zip(surface.part(y, wide_columns.clone()))
                {
                    *i &= !s;
                }
            }
        }
        // Where `valid`'s rows lie in a set held over `wide`.
        let (dx, dy) = (valid.i.start - wide.i.start, valid.j.start - wide.j.start);
        let in_valid = (0..valid.height()).map(|y| (y + dy) * wide.width() + dx..);
        // (i, m): the layer whose surface is projected (its inside cells), and the layer over
        // (under) it.
        let pairs: Vec<_> = (1..slicing.top_layers)
            .map(|d| (k + d, k + d + 1))
            .chain((1..slicing.bottom_layers).filter_map(|d| {
                let i = k.checked_sub(d)?;
                Some((i, i.checked_sub(1)?))
            }))
            .filter(|&(i, m)| i < layout.layers && m < layout.layers)
            .filter_map(|(i, m)| Some((self.inside.rows(i)?, m)))
            .collect();
        // The layer's own rows of the area's cells of `valid`, patched together in this where a
        // void's patch covers part of a row; the other layers' rows are read in pieces.
        let mut here_buffer = Vec::new();
        let mut widened = vec![false; valid.len()];
        let rows_in_wide = rows.clone().zip(in_valid.clone());
        for ((y, start), marks) in rows_in_wide.zip(widened.chunks_mut(width)) {
            let j = area.j.start + y;
            // Only the row's fill cells can be marked: the pairs are read from its first to its
            // last.
            let fill = &internal_wide[start][..width];
            let (Some(first), Some(last)) =
                (fill.iter().position(|&f| f), fill.iter().rposition(|&f| f))
            else {
                continue;
            };
            let (fill, marks) = (&fill[first..=last], &mut marks[first..=last]);
            let cells = valid.i.start + first..valid.i.start + last + 1;
            // The layer's own row once for every pair.
            let here_row = depth.row(k, j, cells.clone(), layout.columns, &mut here_buffer);
            for (inside_i, m) in &pairs {
                let inside_i = inside_i.part(y, columns.start + first..columns.start + last + 1);
                for (at, there) in depth.pieces(*m, j, cells.clone(), layout.columns) {
                    let span = at..at + there.len();
                    mark_strips(
                        Strip {
                            here: &here_row[span.clone()],
                            there,
                            inside_i: &inside_i[span.clone()],
                            fill: &fill[span.clone()],
                        },
                        (w, f),
                        &mut marks[span],
                    );
                }
            }
        }
        if let Some(margins) = self.narrow_margins(k, &wide, &internal_wide) {
            for (marks, start) in widened.chunks_mut(width).zip(in_valid) {
                for (mark, &g) in marks.iter_mut().zip(&margins[start]) {
                    *mark |= g;
                }
            }
        }
        widened.iter().any(|&w| w).then_some(widened)
    }

    /// Layer `k`'s widened strips over `wide` (in its order) that the raster shows: the solid
    /// that the top surface of a layer above (`top_layers − 1` at most) or the bottom surface
    /// of a layer below adds to `k`'s `internal` fill (its slice's uncovered ring and its
    /// margin, read on the raster), where narrower than twice the widening, grown by it within
    /// that fill ([`widened_narrow`]); `None` when none is narrow. PrusaSlicer's surface adds
    /// its margin, and what its neighbour's own surfaces leave of that is often narrow: a band
    /// beside them on a gentle slope, or along an overhang.
    fn narrow_margins(&self, k: usize, wide: &CellBox, internal: &[bool]) -> Option<Vec<bool>> {
        let (layout, area) = (self.layout, self.inside.area());
        let slicing = &layout.slicing;
        let held = |l: usize| self.surfaces.get(l.checked_sub(self.surfaces_from)?);
        let columns = wide.i.start - area.i.start..wide.i.end - area.i.start;
        let rows = wide.j.start - area.j.start..wide.j.end - area.j.start;
        let widening = slicing.shell_widening / layout.cell;
        // (s, m, top): the layer whose surface is projected, the layer over (under) it, and
        // whether the surface is a top one.
        let sources = (1..slicing.top_layers)
            .map(|d| (k + d, Some(k + d + 1), true))
            .chain((1..slicing.bottom_layers).filter_map(|d| {
                let s = k.checked_sub(d)?;
                Some((s, s.checked_sub(1), false))
            }));
        let mut widened: Option<Vec<bool>> = None;
        for (s, m, top) in sources {
            let (Some(source), Some(surfaces)) = (self.inside.rows(s), held(s)) else {
                continue;
            };
            let over = m.and_then(|m| self.inside.rows(m));
            let surface = if top { &surfaces.top } else { &surfaces.bottom };
            let surface = surface.as_deref().map(|cells| Rows::held(cells, area));
            let mut strip = vec![false; wide.len()];
            let chunks = strip
                .chunks_mut(wide.width())
                .zip(internal.chunks(wide.width()));
            for (y, (strip, internal)) in rows.clone().zip(chunks) {
                // Without short cuts, so that the loops are vectorized.
                strip.copy_from_slice(source.part(y, columns.clone()));
                if let Some(over) = over {
                    for (cell, &o) in strip.iter_mut().zip(over.part(y, columns.clone())) {
                        *cell &= !o;
                    }
                }
                if let Some(surface) = surface {
                    for (cell, &m) in strip.iter_mut().zip(surface.part(y, columns.clone())) {
                        *cell |= m;
                    }
                }
                for (cell, &i) in strip.iter_mut().zip(internal) {
                    *cell &= i;
                }
            }
            let Some(grown) = widened_narrow(&strip, internal, wide.width(), widening) else {
                continue;
            };
            match &mut widened {
                Some(widened) => widened.iter_mut().zip(grown).for_each(|(w, g)| *w |= g),
                None => widened = Some(grown),
            }
        }
        widened
    }
}

/// How many cells from a cell the raster's narrow strips read ([`widened_narrow`]: three
/// reaches of the widening and half a cell, and a cell).
pub(super) fn strip_reach(layout: &Layout) -> usize {
    let widening = layout.slicing.shell_widening.max(0.0) / layout.cell;
    (3.0 * (widening + 0.5)).ceil() as usize + 1
}

/// One piece of a row, for [`mark_strips`]: the depths of the layer classified (`here`) and of
/// the layer `m` over (under) the projected layer `i` (`there`), `i`'s inside cells and the
/// classified layer's fill, all of one length.
struct Strip<'a> {
    here: &'a [f32],
    there: &'a [f32],
    inside_i: &'a [bool],
    fill: &'a [bool],
}

/// Marks in `marks` the fill cells of `strip` in a widened strip, for the widening `w` and the
/// fill boundary `f`: outside `m` and inside `i`, or within the widening of `m`'s outline and the
/// strip's width beyond the fill boundary.
fn mark_strips(strip: Strip, (w, f): (f32, f32), marks: &mut [bool]) {
    let n = marks.len();
    // All of one length and without short cuts, so that the loop is vectorized.
    let (here, there) = (&strip.here[..n], &strip.there[..n]);
    let (inside_i, fill) = (&strip.inside_i[..n], &strip.fill[..n]);
    for x in 0..n {
        let (here, there) = (here[x], there[x]);
        let b = here - there;
        let outside = (there < 0.0) & inside_i[x];
        let strip = (there >= 0.0) & (there <= w) & (b > f) & (b < f + 2.0 * w);
        marks[x] |= fill[x] & (outside | strip);
    }
}

/// One layer's rows for [`surface`]: its inside cells, its perimeters and its index.
#[derive(Clone, Copy)]
struct Layer<'a> {
    here: Rows<'a>,
    rim: Rows<'a>,
    index: usize,
}

/// The fill cells of `layer` (its inside cells less its perimeters, over `area`) within the
/// surface margin of its top (or bottom) surface, where the layer `next` above (below; with its
/// index, `None` past the raster) leaves its fill region uncovered: the slicer's top (bottom)
/// surface of the layer with the ring it adds around it, over `area`; `None` when it holds no
/// cell.
///
/// The uncovered fill is found from the exact depths: a cell whose centre lies in the fill
/// region (within the fill boundary) and outside `next`, or whose centre lies inside `next`
/// within half a cell's diagonal of its outline where that outline runs through the fill region
/// (the layer's depth less `next`'s at the cell passes the fill boundary; an outline `next`
/// shares with the layer, a vertical wall, leaves nothing uncovered). PrusaSlicer grows a top
/// or bottom surface by the margin however narrow its part in the fill region
/// (`LayerRegion::process_external_surfaces`), and on a sloping face that part is a sliver
/// under a cell, which no cell's centre shows.
fn surface(
    layout: &Layout,
    area: &CellBox,
    layer: Layer,
    next: Option<(Rows, usize)>,
    depth: Depths,
) -> Option<Vec<bool>> {
    let f = layout.slicing.fill_boundary as f32;
    let half_diagonal = (layout.cell * std::f64::consts::FRAC_1_SQRT_2) as f32;
    let mut fill = Vec::with_capacity(area.len());
    let mut exposed = Vec::with_capacity(area.len());
    let (mut here_buffer, mut next_buffer) = (Vec::new(), Vec::new());
    let raster = layout.columns;
    for y in 0..area.height() {
        let j = area.j.start + y;
        let start = fill.len();
        let (here, rim) = (layer.here.row(y), layer.rim.row(y));
        fill.extend(here.iter().zip(rim).map(|(&h, &r)| h && !r));
        let depth_here = depth.row(layer.index, j, area.i.clone(), raster, &mut here_buffer);
        match next {
            Some((rows, l)) => {
                let depth_next = depth.row(l, j, area.i.clone(), raster, &mut next_buffer);
                let cells = here
                    .iter()
                    .zip(rows.row(y))
                    .zip(depth_here.iter().zip(depth_next));
                exposed.extend(cells.map(|((&h, &n), (&d, &e))| {
                    h & (d >= f) & (!n | ((e <= half_diagonal) & (d - e > f)))
                }));
            }
            None => exposed.extend_from_slice(&fill[start..]),
        }
    }
    // Without a short cut, so that the scan is vectorized.
    if !exposed.iter().fold(false, |any, &e| any | e) {
        return None;
    }
    let reach = layout.slicing.surface_margin / layout.cell;
    if reach <= 0.0 {
        return Some(exposed.iter().zip(&fill).map(|(&e, &f)| e && f).collect());
    }
    let limit = reach * reach;
    let near = near_marked(&exposed, area.width(), area.height(), reach, |d| d <= limit);
    Some(near.iter().zip(&fill).map(|(&n, &f)| f && n).collect())
}

/// Sparse regions (4-connected) of a whole layer's `class` smaller than the minimum area
/// become solid.
pub(super) fn fill_small_regions(layout: &Layout, class: &mut [Cell]) {
    let limit = layout.slicing.min_sparse_area;
    if limit <= 0.0 {
        return;
    }
    let columns = layout.columns;
    let cell_area = layout.cell * layout.cell;
    let mut seen = vec![false; class.len()];
    let mut stack = Vec::new();
    let mut region = Vec::new();
    for j in 0..class.len() / columns {
        for i in 0..columns {
            let start = j * columns + i;
            if seen[start] || !class[start].is_interior() {
                continue;
            }
            seen[start] = true;
            stack.push((i, j));
            region.clear();
            while let Some(cell) = stack.pop() {
                region.push(cell);
                for (i, j) in neighbours(layout, cell).into_iter().flatten() {
                    let next = j * columns + i;
                    if !seen[next] && class[next].is_interior() {
                        seen[next] = true;
                        stack.push((i, j));
                    }
                }
            }
            let small = (region.len() as f64) * cell_area < limit;
            for &(i, j) in &region {
                let cell = &mut class[j * columns + i];
                *cell = if small {
                    Cell::Small
                } else {
                    cell.in_large_region()
                };
            }
        }
    }
}

/// The 4-connected neighbours of raster cell (`i`, `j`): left, right, up, down.
pub(super) fn neighbours(layout: &Layout, (i, j): (usize, usize)) -> [Option<(usize, usize)>; 4] {
    [
        (i > 0).then(|| (i - 1, j)),
        (i + 1 < layout.columns).then(|| (i + 1, j)),
        (j > 0).then(|| (i, j - 1)),
        (j + 1 < layout.rows).then(|| (i, j + 1)),
    ]
}
