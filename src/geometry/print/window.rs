//! Cutting voids from sliced layers: re-classifying only the cells the voids can change.
//!
//! A void changes a layer's inside cells and perimeters only within the box of its
//! cross-section in that layer, grown by the perimeter thickness; the surfaces and the classes
//! read those within the surface margin, over the layers the voids cross and the solid layers
//! above and below them. So a layer's classes before the small-region rule change only within
//! the box of the cross-sections of the layers it reads (itself and its solid layers above and
//! below), grown by the perimeter thickness and the surface margin, and are computed there
//! alone: a slanted void's window follows it from layer to layer. The small-region rule then
//! settles every sparse region that reaches the window (or touches it), stopping a region's
//! flood as soon as it is known to be large: the classes are those of re-classifying every
//! cell.

use std::ops::RangeInclusive;

use super::cells::{CellBox, Overlay, Planes, Rows};
use super::classes::{neighbours, Cell, Classifier};
use super::layout::Layout;
use super::tally::Totals;
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
    /// The class of a cell with this verdict: the rule's when it reached the cell, else
    /// `unreached`.
    fn class(self, unreached: Cell) -> Cell {
        match self {
            Verdict::Small => Cell::Solid,
            Verdict::Large => Cell::Sparse,
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
        let slicing = &layout.slicing;
        let changed = ((slicing.perimeter_thickness + slicing.surface_margin) / layout.cell).ceil()
            as usize
            + 2;
        // Every layer's window lies within `cover` grown by `changed`; what its classes read,
        // within the surface margin of that.
        let margin = (slicing.surface_margin / layout.cell).ceil() as usize + 2;
        let area = cover.grown(changed + margin, layout);
        let (inside, near) = self.cut_planes(voids, first..=last, &area);
        let overlay = |bare, planes| Overlay {
            columns: layout.columns,
            bare,
            planes,
        };
        let (inside, near) = (overlay(&self.inside, &inside), overlay(&self.near, &near));
        let window = reach(layout, first, last);
        let low = *window.start();
        let count = window.clone().count();
        let classifier = Classifier::new(layout, inside, near, window);
        let (top, bottom) = (slicing.top_layers, slicing.bottom_layers);
        Some(map_each(count, |offset| {
            let k = low + offset;
            // The cells of layer k whose class before the rule the cut can change: around the
            // cross-sections of the layers its class reads (`reach`).
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

    /// Over `area`, in the layers `crossed`: the inside cells with `voids`' cells taken out, and
    /// the perimeters with those around each hole added.
    pub(super) fn cut_planes(
        &self,
        voids: &[Void],
        crossed: RangeInclusive<usize>,
        area: &CellBox,
    ) -> (Planes, Planes) {
        let layout = &self.layout;
        let first = *crossed.start();
        let cut: Vec<(Vec<bool>, Vec<bool>)> = map_each(crossed.count(), |offset| {
            let k = first + offset;
            let bare_inside = Rows::bare(&self.inside[k], layout.columns, area);
            let bare_near = Rows::bare(&self.near[k], layout.columns, area);
            let mut hole = layout.in_voids(k, voids, area);
            for (y, row) in hole.chunks_mut(area.width()).enumerate() {
                for (h, &inside) in row.iter_mut().zip(bare_inside.row(y)) {
                    *h &= inside;
                }
            }
            let around = layout.near_hole(&hole, area);
            let (mut inside, mut near) = (
                Vec::with_capacity(area.len()),
                Vec::with_capacity(area.len()),
            );
            let rows = hole.chunks(area.width()).zip(around.chunks(area.width()));
            for (y, (hole, around)) in rows.enumerate() {
                inside.extend(bare_inside.row(y).iter().zip(hole).map(|(&b, &h)| b && !h));
                near.extend(bare_near.row(y).iter().zip(around).map(|(&b, &a)| b || a));
            }
            (inside, near)
        });
        let (inside, near) = cut.into_iter().unzip();
        let planes = |layers| Planes {
            first,
            area: area.clone(),
            layers,
        };
        (planes(inside), planes(near))
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
                for (offset, _) in sparse.filter(|&(_, &class)| class == Cell::Sparse) {
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
            let filled =
                |index: usize| bare_unsettled[index] == Cell::Sparse && bare[index] == Cell::Solid;
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
        let mut set = |(i, j): (usize, usize), was: Cell, to: Cell| {
            if to != was {
                change.add(-1, was, i, j, k);
                change.add(1, to, i, j, k);
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
                set((i, j), was, verdict.class(unreached));
            }
        }
        // Each settled cell lies outside `valid`, and a flood or a walk settles it once.
        for (i, j) in settled {
            let index = j * columns + i;
            set((i, j), bare[index], verdict[index].class(bare[index]));
        }
        change
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
                if class[at] != Cell::Sparse {
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
