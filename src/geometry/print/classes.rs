//! Each cell's class: outside, solid (perimeters, top and bottom layers, small regions) or
//! sparse, over a box of the raster and a range of layers.

use std::ops::RangeInclusive;

use super::cells::{CellBox, Overlay, Planes};
use super::distance::near_marked;
use super::layout::Layout;
use crate::parallel::map_each;

/// What a raster cell of one layer holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Cell {
    Outside,
    Solid,
    Sparse,
}

/// The class of every cell of `valid` in each layer of `layers`, before the small-region rule,
/// from every layer's `inside` cells and perimeters (`near`). The surfaces the classes read are
/// computed over `area`, which must hold `valid` grown by the surface margin and a cell; the
/// cells outside `valid` are not classified. Each layer's classes are in `valid`'s order.
pub(super) fn classify(
    layout: &Layout,
    inside: Overlay,
    near: Overlay,
    area: &CellBox,
    valid: &CellBox,
    layers: RangeInclusive<usize>,
) -> Vec<Vec<Cell>> {
    let (low, high) = (*layers.start(), *layers.end());
    let count = layout.layers;
    let (top, bottom) = (layout.slicing.top_layers, layout.slicing.bottom_layers);
    // Every layer the classes read, over `area`.
    let first = low.saturating_sub(bottom);
    let last = high.saturating_add(top).min(count - 1);
    let held = |cells: Overlay| Planes {
        first,
        area: area.clone(),
        layers: map_each(last - first + 1, |offset| cells.over(first + offset, area)),
    };
    let (inside, near) = (held(inside), held(near));
    // The top surfaces the classes read, and the bottom ones.
    let tops_to = high.saturating_add(top.saturating_sub(1)).min(count - 1);
    let bottoms_from = low.saturating_sub(bottom.saturating_sub(1));
    let surfaces = |from: usize, to: usize, next: fn(usize) -> Option<usize>| Planes {
        first: from,
        area: area.clone(),
        layers: map_each(to - from + 1, |offset| {
            let k = from + offset;
            let (here, rim) = (layer(&inside, k), layer(&near, k));
            let fill: Vec<bool> = here.iter().zip(rim).map(|(i, n)| *i && !n).collect();
            let above = next(k).and_then(|l| inside.layer(l));
            surface(layout, area, &fill, above)
        }),
    };
    let tops = surfaces(low, tops_to, |k| k.checked_add(1));
    let bottoms = surfaces(bottoms_from, high, |k| k.checked_sub(1));
    // A layer past the raster is outside: every cell under (or over) it is uncovered.
    let inside_at = |k: usize| inside.layer(k);
    // Where `valid`'s rows lie in `area`'s.
    let (width, from) = (valid.width(), valid.i.start - area.i.start);
    let rows = valid.j.clone().map(|j| {
        let start = (j - area.j.start) * area.width() + from;
        start..start + width
    });
    map_each(high - low + 1, |offset| {
        let k = low + offset;
        let here = layer(&inside, k);
        let rim = layer(&near, k);
        // The solid layers above and below; `None` when one is past the raster.
        let covering: Option<Vec<&[bool]>> = (1..=top)
            .map(|d| inside_at(k + d))
            .chain((1..=bottom).map(|d| k.checked_sub(d).and_then(inside_at)))
            .collect();
        let surfaces: Vec<&[bool]> = (0..top)
            .filter_map(|d| tops.layer(k + d))
            .chain((0..bottom).filter_map(|d| k.checked_sub(d).and_then(|l| bottoms.layer(l))))
            .collect();
        let mut classes = Vec::with_capacity(valid.len());
        let mut shell = vec![false; width];
        for cells in rows.clone() {
            // The perimeters, the cells some solid layer above or below leaves uncovered, and
            // the surfaces.
            match &covering {
                Some(covering) => {
                    shell.copy_from_slice(&rim[cells.clone()]);
                    for layer in covering {
                        for (s, &c) in shell.iter_mut().zip(&layer[cells.clone()]) {
                            *s |= !c;
                        }
                    }
                    for layer in &surfaces {
                        for (s, &c) in shell.iter_mut().zip(&layer[cells.clone()]) {
                            *s |= c;
                        }
                    }
                }
                None => shell.fill(true),
            }
            classes.extend(here[cells].iter().zip(&shell).map(|(&h, &s)| match (h, s) {
                (false, _) => Cell::Outside,
                (true, true) => Cell::Solid,
                (true, false) => Cell::Sparse,
            }));
        }
        classes
    })
}

/// Layer `k` of `planes`, which hold it.
fn layer(planes: &Planes, k: usize) -> &[bool] {
    planes.layer(k).unwrap_or_default()
}

/// The fill cells of a layer (`fill`, over `area`) under which (or over which) the layer
/// `next` (over `area`; `None` past the raster) is outside, grown by the surface margin within
/// `fill`: the slicer's top (or bottom) surface of the layer with the ring it adds around it.
fn surface(layout: &Layout, area: &CellBox, fill: &[bool], next: Option<&[bool]>) -> Vec<bool> {
    let exposed: Vec<bool> = match next {
        Some(next) => fill.iter().zip(next).map(|(f, n)| *f && !n).collect(),
        None => fill.to_vec(),
    };
    let reach = layout.slicing.surface_margin / layout.cell;
    if reach <= 0.0 || !exposed.iter().any(|&e| e) {
        return exposed;
    }
    let limit = reach * reach;
    let near = near_marked(&exposed, area.width(), area.height(), reach, |d| d <= limit);
    near.iter().zip(fill).map(|(&n, &f)| f && n).collect()
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
            if seen[start] || class[start] != Cell::Sparse {
                continue;
            }
            seen[start] = true;
            stack.push((i, j));
            region.clear();
            while let Some(cell) = stack.pop() {
                region.push(cell);
                for (i, j) in neighbours(layout, cell).into_iter().flatten() {
                    let next = j * columns + i;
                    if !seen[next] && class[next] == Cell::Sparse {
                        seen[next] = true;
                        stack.push((i, j));
                    }
                }
            }
            if (region.len() as f64) * cell_area < limit {
                for &(i, j) in &region {
                    class[j * columns + i] = Cell::Solid;
                }
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
