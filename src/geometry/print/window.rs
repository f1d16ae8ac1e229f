//! Cutting voids from sliced layers: re-classifying only the cells the voids can change.
//!
//! A void changes a layer's inside cells and perimeters only within the box of the voids, grown
//! by the perimeter thickness; the surfaces and the classes read those within the surface
//! margin, over the layers the voids cross and the solid layers above and below them. So the
//! classes before the small-region rule change only in that window, and are computed there
//! alone. The small-region rule then settles every sparse region that reaches the window (or
//! touches it), stopping a region's flood as soon as it is known to be large: the classes are
//! those of re-classifying every cell.

use std::ops::RangeInclusive;

use super::cells::{CellBox, Overlay, Planes};
use super::classes::{self, neighbours, Cell};
use super::layout::Layout;
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

/// The cells of one layer whose class a cut changes.
pub(super) struct Changed {
    /// The layer.
    pub(super) layer: usize,
    /// Each changed cell's index in the layer and its class with the voids cut; no cell twice.
    pub(super) cells: Vec<(usize, Cell)>,
}

impl Layers {
    /// The cells whose class cutting `voids` (print frame) changes, per layer; none when the
    /// voids cross no layer or miss the raster.
    pub(super) fn cut(&self, voids: &[Void]) -> Vec<Changed> {
        self.cut_window(voids).unwrap_or_default()
    }

    /// [`Layers::cut`], `None` for no change.
    fn cut_window(&self, voids: &[Void]) -> Option<Vec<Changed>> {
        let layout = &self.layout;
        let crossed: Vec<usize> = (0..layout.layers)
            .filter(|&k| {
                voids
                    .iter()
                    .any(|void| void.crosses(layout.slice_height(k)))
            })
            .collect();
        let (&first, &last) = (crossed.first()?, crossed.last()?);
        let cover = voids
            .iter()
            .filter_map(|void| layout.cover(void))
            .reduce(|a, b| a.union(&b))?;
        let slicing = &layout.slicing;
        let changed = ((slicing.perimeter_thickness + slicing.surface_margin) / layout.cell).ceil();
        let valid = cover.grown(changed as usize + 2, layout);
        let margin = (slicing.surface_margin / layout.cell).ceil();
        let area = valid.grown(margin as usize + 2, layout);
        let (inside, near) = self.cut_planes(voids, first..=last, &area);
        let inside = Overlay {
            columns: layout.columns,
            bare: &self.inside,
            planes: &inside,
        };
        let near = Overlay {
            columns: layout.columns,
            bare: &self.near,
            planes: &near,
        };
        let window = reach(layout, first, last);
        let low = *window.start();
        let unsettled = classes::classify(layout, inside, near, &area, &valid, window);
        Some(map_each(unsettled.len(), |offset| Changed {
            layer: low + offset,
            cells: self.settle(low + offset, &valid, &unsettled[offset]),
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
            let bare = |layer: &[bool]| -> Vec<bool> {
                let mut cells = Vec::with_capacity(area.len());
                for j in area.j.clone() {
                    let row = j * layout.columns;
                    cells.extend_from_slice(&layer[row + area.i.start..row + area.i.end]);
                }
                cells
            };
            let (bare_inside, bare_near) = (bare(&self.inside[k]), bare(&self.near[k]));
            let mut hole = layout.in_voids(k, voids, area);
            for (h, &inside) in hole.iter_mut().zip(&bare_inside) {
                *h &= inside;
            }
            let around = layout.near_hole(&hole, area);
            let inside = bare_inside.iter().zip(&hole).map(|(&b, &h)| b && !h);
            let near = bare_near.iter().zip(&around).map(|(&b, &a)| b || a);
            (inside.collect(), near.collect())
        });
        let (inside, near) = cut.into_iter().unzip();
        let planes = |layers| Planes {
            first,
            area: area.clone(),
            layers,
        };
        (planes(inside), planes(near))
    }

    /// The cells of layer `k` whose class changes when those of `valid`'s cells before the
    /// small-region rule are replaced by `unsettled` (in `valid`'s order), with their new
    /// class: the rule applied to every sparse region that reaches `valid` or its edge.
    fn settle(&self, k: usize, valid: &CellBox, unsettled: &[Cell]) -> Vec<(usize, Cell)> {
        let layout = &self.layout;
        let columns = layout.columns;
        let (bare_unsettled, bare) = (&self.unsettled[k], &self.classes[k]);
        let at = |index: usize| (index % columns, index / columns);
        // Each cell's class before the rule: the bare layer's, `unsettled` over `valid`.
        let mut rule_input = bare_unsettled.clone();
        for ((i, j), &cell) in valid.cells().zip(unsettled) {
            rule_input[j * columns + i] = cell;
        }
        let before_rule = |index: usize| rule_input[index];
        let mut verdict = vec![Verdict::Unseen; bare.len()];
        // The cells outside `valid` whose class the rule settles here.
        let mut settled = Vec::new();
        let limit = layout.slicing.min_sparse_area;
        if limit > 0.0 {
            let edge = valid.grown(1, layout);
            let cell_area = layout.cell * layout.cell;
            let mut flood = Flood::default();
            for (i, j) in edge.cells() {
                let start = j * columns + i;
                if verdict[start] == Verdict::Unseen && before_rule(start) == Cell::Sparse {
                    let region = flood.region(layout, start, &before_rule, &mut verdict, |n| {
                        (n as f64) * cell_area >= limit
                    });
                    settled.extend(region.iter().copied().filter(|&c| {
                        let (i, j) = at(c);
                        !valid.contains(i, j)
                    }));
                }
            }
            // A region the bare layer filled solid that now joins a large one is reached by no
            // stopped flood, but each of its parts outside `valid` holds a cell of the edge.
            let filled =
                |index: usize| bare_unsettled[index] == Cell::Sparse && bare[index] == Cell::Solid;
            let mut seen = vec![false; bare.len()];
            let mut stack = Vec::new();
            for (i, j) in edge.cells() {
                let start = j * columns + i;
                if valid.contains(i, j) || seen[start] || !filled(start) {
                    continue;
                }
                let of_region = verdict[start];
                seen[start] = true;
                stack.push(start);
                while let Some(index) = stack.pop() {
                    if verdict[index] == Verdict::Unseen {
                        verdict[index] = of_region;
                        settled.push(index);
                    }
                    for next in neighbours(layout, index).into_iter().flatten() {
                        let (i, j) = at(next);
                        if !seen[next] && !valid.contains(i, j) && filled(next) {
                            seen[next] = true;
                            stack.push(next);
                        }
                    }
                }
            }
        }
        // A cell the rule reached takes its verdict; one it did not keeps its class before the
        // rule inside `valid`, the bare layer's outside.
        let class = |index: usize, unreached: Cell| match verdict[index] {
            Verdict::Small => Cell::Solid,
            Verdict::Large => Cell::Sparse,
            Verdict::Unseen | Verdict::Queued => unreached,
        };
        let mut changed = Vec::new();
        let mut set = |index: usize, to: Cell| {
            if to != bare[index] {
                changed.push((index, to));
            }
        };
        for (i, j) in valid.cells() {
            let index = j * columns + i;
            set(index, class(index, before_rule(index)));
        }
        // Each settled cell lies outside `valid`, and a flood or a walk settles it once.
        for index in settled {
            set(index, class(index, bare[index]));
        }
        changed
    }
}

/// A flood over a layer's sparse cells, reused between regions.
#[derive(Default)]
struct Flood {
    stack: Vec<usize>,
    region: Vec<usize>,
}

impl Flood {
    /// The region of sparse cells (`class`) around `start`, each cell's verdict set: large as
    /// soon as `large` holds for the cells reached or the flood meets a cell of a large region,
    /// small when the whole region is reached first. A large region is left partly unreached.
    fn region(
        &mut self,
        layout: &Layout,
        start: usize,
        class: &impl Fn(usize) -> Cell,
        verdict: &mut [Verdict],
        large: impl Fn(usize) -> bool,
    ) -> &[usize] {
        self.stack.clear();
        self.region.clear();
        verdict[start] = Verdict::Queued;
        self.stack.push(start);
        let mut is_large = false;
        while let Some(index) = self.stack.pop() {
            self.region.push(index);
            if large(self.region.len()) {
                is_large = true;
                break;
            }
            for next in neighbours(layout, index).into_iter().flatten() {
                if class(next) != Cell::Sparse {
                    continue;
                }
                match verdict[next] {
                    Verdict::Unseen => {
                        verdict[next] = Verdict::Queued;
                        self.stack.push(next);
                    }
                    Verdict::Large => is_large = true,
                    Verdict::Queued | Verdict::Small => {}
                }
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
        for &index in &self.region {
            verdict[index] = outcome;
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
