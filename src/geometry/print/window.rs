//! Cutting voids from sliced layers: re-classifying only the cells the voids can change.
//!
//! A void changes a layer's inside cells, perimeters and depths only near its cross-section in
//! that layer; the surfaces and the classes read those within the surface margin (and a
//! widened strip reads depths up to the fill boundary and three widenings), over the layers the
//! voids cross and the solid layers above and below them. So a layer's classes before the
//! small-region rule change only within the box of the cross-sections of the layers it reads
//! (itself and its solid layers above and below), grown by that reach, and are computed there
//! alone. The small-region rule then settles every sparse region that reaches the window (or
//! touches it), stopping a region's flood as soon as it is known to be large: the classes are
//! those of re-classifying every cell.

use std::ops::RangeInclusive;

use super::cells::{CellBox, Overlay, Planes};
use super::classes::{neighbours, strip_reach, Cell, Classifier, DepthPatch, Depths};
use super::depth::{depth_value, DEPTH_RANGE};
use super::layout::Layout;
use super::tally::{corners, Corners, Totals};
use super::{Layers, Void};
use crate::parallel::map_each;

/// The small-region rule's verdict on a cell of one layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Verdict {
    /// Not reached.
    Unseen,
    /// Waiting in a flood.
    Queued,
    /// In a sparse region smaller than the minimum area: solid.
    Small,
    /// In a sparse region at least the minimum area: sparse.
    Large,
}

impl Verdict {
    /// The class of a cell with this verdict, whose class before the rule is `unsettled`: the
    /// rule's when it reached the cell, else `unreached`.
    fn class(self, unsettled: Cell, unreached: Cell) -> Cell {
        match self {
            Verdict::Small => Cell::Small,
            Verdict::Large => unsettled.in_large_region(),
            Verdict::Unseen | Verdict::Queued => unreached,
        }
    }
}

impl Layers {
    /// The solid and sparse cells of every layer with `voids` (print frame) cut: the bare
    /// totals when the voids cross no layer or miss the raster.
    pub(super) fn cut(&self, voids: &[Void]) -> Totals {
        let mut totals = self.totals;
        for change in self.cut_window(voids).unwrap_or_default() {
            totals += change;
        }
        totals
    }

    /// Per layer the cut changes, the change in its solid and sparse cells; `None` for no
    /// change.
    fn cut_window(&self, voids: &[Void]) -> Option<Vec<Totals>> {
        let layout = &self.layout;
        let crossed: Vec<usize> = (0..layout.layers)
            .filter(|&k| {
                voids
                    .iter()
                    .any(|void| void.crosses(layout.slice_height(k)))
            })
            .collect();
        let (&first, &last) = (crossed.first()?, crossed.last()?);
        // Per layer from `first` to `last`, the box of the voids' cross-sections.
        let sections: Vec<Option<CellBox>> = (first..=last)
            .map(|k| layout.sections_cover(k, voids))
            .collect();
        let cover = sections
            .iter()
            .flatten()
            .cloned()
            .reduce(|a, b| a.union(&b))?;
        let changed = (changed_reach(layout) / layout.cell).ceil() as usize + 2;
        // Every layer's window lies within `cover` grown by `changed`; what its classes read,
        // within the raster's strips' reach and the surface margin of that.
        let margin = (layout.slicing.surface_margin.max(0.0) / layout.cell).ceil() as usize + 2;
        let area = cover.grown(changed + strip_reach(layout) + margin, layout);
        let (inside, near, depth) = self.cut_planes(voids, first..=last, &area);
        let overlay = |bare, planes| Overlay {
            columns: layout.columns,
            bare,
            planes,
        };
        let (inside, near) = (overlay(&self.inside, &inside), overlay(&self.near, &near));
        let window = reach(layout, first, last);
        let low = *window.start();
        let count = window.clone().count();
        let depths = Depths {
            bare: &self.depth,
            first,
            held: &depth,
        };
        let classifier = Classifier::new(layout, inside, near, window, depths);
        let (top, bottom) = (layout.slicing.top_layers, layout.slicing.bottom_layers);
        Some(map_each(count, |offset| {
            let k = low + offset;
            // The cells of layer k whose class before the rule the cut can change: near the
            // sections of the layers its class reads.
            let read = k.saturating_sub(bottom).max(first)..=k.saturating_add(top).min(last);
            let near_sections = read
                .filter_map(|l| sections[l - first].as_ref())
                .cloned()
                .reduce(|a, b| a.union(&b));
            let Some(valid) = near_sections.map(|cells| cells.grown(changed, layout)) else {
                return Totals::default();
            };
            // Each cell's class before the rule: the bare layer's, re-classified over `valid`.
            let mut before_rule = self.unsettled[k].clone();
            classifier.layer(k, &valid, &mut before_rule);
            self.settle(k, &valid, &before_rule)
        }))
    }

    /// Over `area`, in the layers `crossed`: the inside cells with `voids`' cells taken out, the
    /// perimeters with those around each hole added (the cells within the perimeter thickness
    /// of a void's cross-section), and each cell's depth with the holes' outlines counted. Only
    /// the cells within the depth range of a cross-section's box can change; the others keep
    /// the bare layer's.
    pub(super) fn cut_planes(
        &self,
        voids: &[Void],
        crossed: RangeInclusive<usize>,
        area: &CellBox,
    ) -> (Planes, Planes, Vec<Option<DepthPatch>>) {
        let layout = &self.layout;
        let first = *crossed.start();
        let thickness = layout.slicing.perimeter_thickness;
        let reach = (thickness.max(DEPTH_RANGE) / layout.cell).ceil() as usize + 2;
        let cut: Vec<(Vec<bool>, Vec<bool>, Option<DepthPatch>)> =
            map_each(crossed.count(), |offset| {
                let k = first + offset;
                let mut inside = Vec::with_capacity(area.len());
                let mut near = Vec::with_capacity(area.len());
                for j in area.j.clone() {
                    let row = j * layout.columns + area.i.start..j * layout.columns + area.i.end;
                    inside.extend_from_slice(&self.inside[k][row.clone()]);
                    near.extend_from_slice(&self.near[k][row]);
                }
                let changed = layout
                    .sections_cover(k, voids)
                    .and_then(|cells| cells.grown(reach, layout).within(area));
                let Some(changed) = changed else {
                    return (inside, near, None);
                };
                let hole = layout.in_voids(k, voids, &changed);
                // The changed box's cells as the area's: row y of the box starts at `at(y)`.
                let at = |y: usize| {
                    (changed.j.start - area.j.start + y) * area.width() + changed.i.start
                        - area.i.start
                };
                let width = changed.width();
                let mut cut_inside = Vec::with_capacity(changed.len());
                let mut depth = Vec::with_capacity(changed.len());
                for (y, hole) in hole.chunks(width).enumerate() {
                    let row = &mut inside[at(y)..at(y) + width];
                    for (cell, &h) in row.iter_mut().zip(hole) {
                        *cell &= !h;
                    }
                    cut_inside.extend_from_slice(row);
                    let j = changed.j.start + y;
                    let bare = j * layout.columns + changed.i.start;
                    let cells = self.depth[k][bare..bare + width].iter().zip(&*row);
                    depth.extend(cells.map(|(&d, &inside)| if inside { d } else { -1.0 }));
                }
                // A cell within the perimeter thickness of a hole is a perimeter, and its depth
                // is its distance to the nearest hole where that is less than the bare layer's.
                let thickness2 = thickness * thickness;
                let measured = |x: usize, y: usize, d2: f64| {
                    near[at(y) + x] |= d2 < thickness2;
                    let depth = &mut depth[y * width + x];
                    *depth = depth.min(depth_value(true, d2));
                };
                layout.hole_distances(k, voids, &changed, &cut_inside, reach, measured);
                let patch = DepthPatch {
                    cells: changed,
                    depth,
                };
                (inside, near, Some(patch))
            });
        let mut inside = Vec::new();
        let mut near = Vec::new();
        let mut depth = Vec::new();
        for (i, n, d) in cut {
            inside.push(i);
            near.push(n);
            depth.push(d);
        }
        let planes = |layers| Planes {
            first,
            area: area.clone(),
            layers,
        };
        (planes(inside), planes(near), depth)
    }

    /// The change in layer `k`'s solid and sparse cells when its classes before the
    /// small-region rule are `before_rule` (the whole layer's, changed only in `valid`): the
    /// rule applied to every sparse region that reaches `valid` or its edge.
    fn settle(&self, k: usize, valid: &CellBox, before_rule: &[Cell]) -> Totals {
        let layout = &self.layout;
        let columns = layout.columns;
        let (bare_unsettled, bare) = (&self.unsettled[k], &self.classes[k]);
        // The layer's indices of a row of a box's cells.
        let row =
            |cells: &CellBox, j: usize| j * columns + cells.i.start..j * columns + cells.i.end;
        let mut verdict = vec![Verdict::Unseen; bare.len()];
        // The cells outside `valid` whose class the rule settles here.
        let mut settled = Vec::new();
        let limit = layout.slicing.min_sparse_area;
        if limit > 0.0 {
            let edge = valid.grown(1, layout);
            let cell_area = layout.cell * layout.cell;
            let mut flood = Flood::default();
            for j in edge.j.clone() {
                let cells = row(&edge, j);
                let sparse = before_rule[cells.clone()].iter().enumerate();
                for (offset, _) in sparse.filter(|&(_, &class)| class.is_interior()) {
                    let (i, start) = (edge.i.start + offset, cells.start + offset);
                    if verdict[start] != Verdict::Unseen {
                        continue;
                    }
                    let region = flood.region(layout, (i, j), before_rule, &mut verdict, |n| {
                        (n as f64) * cell_area >= limit
                    });
                    settled.extend(
                        region
                            .iter()
                            .copied()
                            .filter(|&(i, j)| !valid.contains(i, j)),
                    );
                }
            }
            // A region the bare layer filled solid that now joins a large one is reached by no
            // stopped flood, but each of its parts outside `valid` holds a cell of the edge.
            let filled = |index: usize| bare[index] == Cell::Small;
            // Without such parts when the edge is all inside `valid` (the whole raster).
            let ring = if edge == *valid { 0..0 } else { edge.j.clone() };
            // Allocated at the first filled cell of the ring: most layers have none.
            let mut seen = Vec::new();
            let mut stack = Vec::new();
            for j in ring {
                // The edge's columns outside `valid` in this row.
                let outside = if valid.j.contains(&j) {
                    [edge.i.start..valid.i.start, valid.i.end..edge.i.end]
                } else {
                    [edge.i.clone(), 0..0]
                };
                for i in outside.into_iter().flatten() {
                    let start = j * columns + i;
                    if !filled(start) {
                        continue;
                    }
                    if seen.is_empty() {
                        seen = vec![false; bare.len()];
                    }
                    if seen[start] {
                        continue;
                    }
                    let of_region = verdict[start];
                    seen[start] = true;
                    stack.push((i, j));
                    while let Some(cell) = stack.pop() {
                        let index = cell.1 * columns + cell.0;
                        if verdict[index] == Verdict::Unseen {
                            verdict[index] = of_region;
                            settled.push(cell);
                        }
                        for (i, j) in neighbours(layout, cell).into_iter().flatten() {
                            let next = j * columns + i;
                            if !seen[next] && !valid.contains(i, j) && filled(next) {
                                seen[next] = true;
                                stack.push((i, j));
                            }
                        }
                    }
                }
            }
        }
        // A cell the rule reached takes its verdict; one it did not keeps its class before the
        // rule inside `valid`, the bare layer's outside.
        let mut change = Totals::default();
        // The cells that become sparse or stop being sparse: all the sparse outline reads.
        let mut flipped = Vec::new();
        let mut set = |(i, j): (usize, usize), was: Cell, to: Cell| {
            if to != was {
                change.add(-1, was, i, j, k);
                change.add(1, to, i, j, k);
                if (was == Cell::Sparse) != (to == Cell::Sparse) {
                    flipped.push(j * columns + i);
                }
            }
        };
        for j in valid.j.clone() {
            let cells = row(valid, j);
            let verdicts = verdict[cells.clone()]
                .iter()
                .zip(&before_rule[cells.clone()]);
            for (i, ((verdict, &unreached), &was)) in
                valid.i.clone().zip(verdicts.zip(&bare[cells]))
            {
                set(
                    (i, j),
                    was,
                    verdict.class(unreached, unreached.in_large_region()),
                );
            }
        }
        // Each settled cell lies outside `valid`, and a flood or a walk settles it once.
        for (i, j) in settled {
            let index = j * columns + i;
            set(
                (i, j),
                bare[index],
                verdict[index].class(bare_unsettled[index], bare[index]),
            );
        }
        // The blocks of the sparse outline with a flipped cell at a corner, before and after:
        // over the box of the flipped cells (blocks reach one cell further up and right).
        if let Some(flips) = Flips::of(&flipped, columns) {
            let was_sparse = |i: usize, j: usize| bare[j * columns + i] == Cell::Sparse;
            let raster = (columns, layout.rows);
            flips.each_block(|block, flipped| {
                let before = corners(block, raster, was_sparse);
                change.change_block(before, before ^ flipped, (block.0, block.1, k));
            });
        }
        change
    }
}

/// The cells of a layer that flipped (became sparse or stopped being sparse), over their box.
struct Flips {
    cells: CellBox,
    /// Row by row over the box.
    flipped: Vec<bool>,
}

impl Flips {
    /// The flipped cells at layer indices `indices` of a raster `raster` columns wide; `None`
    /// for none.
    fn of(indices: &[usize], raster: usize) -> Option<Flips> {
        let at = |index: &usize| (index % raster, index / raster);
        let (mut low, mut high) = (at(indices.first()?), at(indices.first()?));
        for (i, j) in indices.iter().map(at) {
            low = (low.0.min(i), low.1.min(j));
            high = (high.0.max(i), high.1.max(j));
        }
        let cells = CellBox {
            i: low.0..high.0 + 1,
            j: low.1..high.1 + 1,
        };
        let mut flipped = vec![false; cells.len()];
        for (i, j) in indices.iter().map(at) {
            flipped[(j - cells.j.start) * cells.width() + (i - cells.i.start)] = true;
        }
        Some(Flips { cells, flipped })
    }

    /// Each outline block with a flipped cell at a corner, and its flipped corners
    /// ([`Corners`]), row by row (blocks reach one cell further up and right than cells).
    fn each_block(&self, mut visit: impl FnMut((usize, usize), Corners)) {
        let cells = &self.cells;
        let (width, height) = (cells.width(), cells.height());
        // Row `y` of the box's flipped cells; none past the box.
        let row = |y: Option<usize>| {
            y.filter(|&y| y < height)
                .map_or(&[][..], |y| &self.flipped[y * width..(y + 1) * width])
        };
        for y in 0..=height {
            let (below, above) = (row(y.checked_sub(1)), row(Some(y)));
            // Whether the cells of column `x` below and above the block row flipped (bits 1
            // and 2); none left or right of the box.
            let column = |x: usize| {
                let flipped = |row: &[bool]| u8::from(row.get(x).copied().unwrap_or(false));
                flipped(below) | flipped(above) << 1
            };
            let mut left = 0;
            for x in 0..=width {
                let right = column(x);
                if left | right != 0 {
                    let flipped =
                        (left & 1) | (right & 1) << 1 | (left & 2) << 1 | (right & 2) << 2;
                    visit((cells.i.start + x, cells.j.start + y), flipped);
                }
                left = right;
            }
        }
    }
}

/// A flood over a layer's sparse cells, reused between regions.
#[derive(Default)]
struct Flood {
    stack: Vec<(usize, usize)>,
    region: Vec<(usize, usize)>,
}

impl Flood {
    /// The region of sparse cells (`class`, a layer's) around cell `start`, each cell's verdict
    /// set: large as soon as `large` holds for the cells reached or the flood meets a cell of a
    /// large region, small when the whole region is reached first. A large region is left
    /// partly unreached.
    fn region(
        &mut self,
        layout: &Layout,
        start: (usize, usize),
        class: &[Cell],
        verdict: &mut [Verdict],
        large: impl Fn(usize) -> bool,
    ) -> &[(usize, usize)] {
        let columns = layout.columns;
        self.stack.clear();
        self.region.clear();
        verdict[start.1 * columns + start.0] = Verdict::Queued;
        self.stack.push(start);
        let mut is_large = false;
        while let Some(cell) = self.stack.pop() {
            self.region.push(cell);
            if large(self.region.len()) {
                is_large = true;
                break;
            }
            let (i, j) = cell;
            let index = j * columns + i;
            let mut reach = |next: (usize, usize), at: usize| {
                if !class[at].is_interior() {
                    return;
                }
                match verdict[at] {
                    Verdict::Unseen => {
                        verdict[at] = Verdict::Queued;
                        self.stack.push(next);
                    }
                    Verdict::Large => is_large = true,
                    Verdict::Queued | Verdict::Small => {}
                }
            };
            // The 4-connected neighbours: left, right, up, down.
            if i > 0 {
                reach((i - 1, j), index - 1);
            }
            if i + 1 < columns {
                reach((i + 1, j), index + 1);
            }
            if j > 0 {
                reach((i, j - 1), index - columns);
            }
            if j + 1 < layout.rows {
                reach((i, j + 1), index + columns);
            }
            if is_large {
                break;
            }
        }
        self.region.append(&mut self.stack);
        let outcome = if is_large {
            Verdict::Large
        } else {
            Verdict::Small
        };
        for &(i, j) in &self.region {
            verdict[j * columns + i] = outcome;
        }
        &self.region
    }
}

/// How far from a void's cross-section in a layer the classes of the layers that read it can
/// change: the surfaces around the hole (their uncovered fill, found within the perimeters or
/// the fill boundary and half a cell's diagonal, and their margin), and the raster's narrow
/// strips within three widenings and half-cells of those. That holds the reach of an exact
/// widened strip too, which reads depths up to the fill boundary and three widenings
/// ([`Classifier`]).
fn changed_reach(layout: &Layout) -> f64 {
    let slicing = &layout.slicing;
    let uncovered = slicing
        .perimeter_thickness
        .max(slicing.fill_boundary + layout.cell * std::f64::consts::FRAC_1_SQRT_2);
    let surfaces = uncovered + slicing.surface_margin.max(0.0);
    surfaces + 3.0 * (slicing.shell_widening.max(0.0) + layout.cell / 2.0)
}

/// The layers whose class cutting the layers `first` to `last` can change: a layer's class
/// reads the inside cells of the solid layers above and below it, and the top surfaces of the
/// layers above it (the bottom surfaces of those below), which a cut layer changes at itself
/// and its neighbour.
pub(super) fn reach(layout: &Layout, first: usize, last: usize) -> RangeInclusive<usize> {
    let slicing = &layout.slicing;
    let low = first.saturating_sub(slicing.top_layers);
    let high = last.saturating_add(slicing.bottom_layers);
    low..=high.min(layout.layers - 1)
}
