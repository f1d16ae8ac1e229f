//! Each cell's class: outside, solid (perimeters, top and bottom layers, small regions) or
//! sparse, over a box of the raster and a range of layers.

use std::ops::RangeInclusive;

use super::cells::{CellBox, Overlay, Rows};
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
}

impl<'a> Classifier<'a> {
    /// The surfaces the classes of `layers` read, from every layer's `inside` cells and
    /// perimeters (`near`), both read over the same area.
    pub(super) fn new(
        layout: &'a Layout,
        inside: Overlay<'a>,
        near: Overlay<'a>,
        layers: RangeInclusive<usize>,
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
                let here = inside.rows(k)?;
                let rim = near.rows(k)?;
                surface(
                    layout,
                    inside.area(),
                    here,
                    rim,
                    next.and_then(|l| inside.rows(l)),
                )
            };
            Surfaces {
                top: (k >= low).then(|| of(k.checked_add(1))).flatten(),
                bottom: (k <= high).then(|| of(k.checked_sub(1))).flatten(),
            }
        });
        Classifier {
            layout,
            inside,
            near,
            layers,
            surfaces,
            surfaces_from: bottoms_from,
        }
    }

    /// The class of every cell of `valid` in layer `k` (one of the layers classified) before
    /// the small-region rule, written to `classes` (the whole layer, row by row). `valid` must
    /// lie within the area grown back by the surface margin and a cell.
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
        let held = |l: usize| self.surfaces.get(l.checked_sub(self.surfaces_from)?);
        let surfaces: Vec<Rows> = (0..top)
            .filter_map(|d| held(k + d)?.top.as_deref())
            .chain((0..bottom).filter_map(|d| held(k.checked_sub(d)?)?.bottom.as_deref()))
            .map(|cells| Rows::held(cells, area))
            .collect();
        // Where `valid`'s columns lie in the area's.
        let (width, from) = (valid.width(), valid.i.start - area.i.start);
        let columns = from..from + width;
        let mut shell = vec![false; width];
        for j in valid.j.clone() {
            let y = j - area.j.start;
            // The perimeters, the cells some solid layer above or below leaves uncovered, and
            // the surfaces.
            match &covering {
                Some(covering) => {
                    shell.copy_from_slice(rim.part(y, columns.clone()));
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
                }
                None => shell.fill(true),
            }
            let start = j * layout.columns + valid.i.start;
            let cells = classes[start..start + width].iter_mut();
            for (class, (&h, &s)) in cells.zip(here.part(y, columns.clone()).iter().zip(&shell)) {
                *class = match (h, s) {
                    (false, _) => Cell::Outside,
                    (true, true) => Cell::Solid,
                    (true, false) => Cell::Sparse,
                };
            }
        }
    }
}

/// The fill cells of a layer (`here` less its perimeters `rim`, over `area`) under which (or
/// over which) the layer `next` (`None` past the raster) is outside, grown by the surface margin
/// within the fill: the slicer's top (or bottom) surface of the layer with the ring it adds
/// around it, over `area`; `None` when it holds no cell.
fn surface(
    layout: &Layout,
    area: &CellBox,
    here: Rows,
    rim: Rows,
    next: Option<Rows>,
) -> Option<Vec<bool>> {
    let mut fill = Vec::with_capacity(area.len());
    let mut exposed = Vec::with_capacity(area.len());
    for y in 0..area.height() {
        let start = fill.len();
        fill.extend(here.row(y).iter().zip(rim.row(y)).map(|(&h, &r)| h && !r));
        let fill = &fill[start..];
        match next {
            Some(next) => exposed.extend(fill.iter().zip(next.row(y)).map(|(&f, &n)| f && !n)),
            None => exposed.extend_from_slice(fill),
        }
    }
    // Without a short cut, so that the scan is vectorized.
    if !exposed.iter().fold(false, |any, &e| any | e) {
        return None;
    }
    let reach = layout.slicing.surface_margin / layout.cell;
    if reach <= 0.0 {
        return Some(exposed);
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
