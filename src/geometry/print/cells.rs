//! Sets of raster cells over layers, held over a box of the raster.

use std::ops::Range;

use super::layout::Layout;

/// A box of raster cells: columns `i`, rows `j`, both half-open.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct CellBox {
    pub(super) i: Range<usize>,
    pub(super) j: Range<usize>,
}

impl CellBox {
    /// Every cell of `layout`'s raster.
    pub(super) fn whole(layout: &Layout) -> CellBox {
        CellBox {
            i: 0..layout.columns,
            j: 0..layout.rows,
        }
    }

    /// This box grown by `cells` on every side, within `layout`'s raster.
    pub(super) fn grown(&self, cells: usize, layout: &Layout) -> CellBox {
        CellBox {
            i: self.i.start.saturating_sub(cells)..(self.i.end + cells).min(layout.columns),
            j: self.j.start.saturating_sub(cells)..(self.j.end + cells).min(layout.rows),
        }
    }

    /// The cells of this box that lie in `other` too; `None` when none do.
    pub(super) fn within(&self, other: &CellBox) -> Option<CellBox> {
        let i = self.i.start.max(other.i.start)..self.i.end.min(other.i.end);
        let j = self.j.start.max(other.j.start)..self.j.end.min(other.j.end);
        (!i.is_empty() && !j.is_empty()).then_some(CellBox { i, j })
    }

    /// The smallest box holding this one and `other`.
    pub(super) fn union(&self, other: &CellBox) -> CellBox {
        CellBox {
            i: self.i.start.min(other.i.start)..self.i.end.max(other.i.end),
            j: self.j.start.min(other.j.start)..self.j.end.max(other.j.end),
        }
    }

    /// Whether raster cell (`i`, `j`) lies in the box.
    pub(super) fn contains(&self, i: usize, j: usize) -> bool {
        self.i.contains(&i) && self.j.contains(&j)
    }

    /// Columns across.
    pub(super) fn width(&self) -> usize {
        self.i.len()
    }

    /// Rows down.
    pub(super) fn height(&self) -> usize {
        self.j.len()
    }

    /// Cells in the box.
    pub(super) fn len(&self) -> usize {
        self.width() * self.height()
    }

    /// The box's index of the raster cell (`i`, `j`), when it lies in the box.
    pub(super) fn local(&self, i: usize, j: usize) -> Option<usize> {
        (self.i.contains(&i) && self.j.contains(&j))
            .then(|| (j - self.j.start) * self.width() + (i - self.i.start))
    }
}

/// Per layer from `first` on, a set of the cells of `area` (each layer's cells in the box's
/// order).
#[derive(Debug, Clone)]
pub(super) struct Planes {
    pub(super) first: usize,
    pub(super) area: CellBox,
    pub(super) layers: Vec<Vec<bool>>,
}

impl Planes {
    /// Whether cell (`i`, `j`) of layer `k` is in the set; `None` when the planes do not hold it.
    pub(super) fn get(&self, k: usize, i: usize, j: usize) -> Option<bool> {
        let layer = self.layers.get(k.checked_sub(self.first)?)?;
        Some(layer[self.area.local(i, j)?])
    }

    /// Layer `k`'s cells, when held.
    pub(super) fn layer(&self, k: usize) -> Option<&[bool]> {
        let layer = self.layers.get(k.checked_sub(self.first)?)?;
        Some(layer)
    }
}

/// Cell sets over every layer of the raster: `planes` where they hold a cell, else `bare`
/// (one full layer each).
#[derive(Clone, Copy)]
pub(super) struct Overlay<'a> {
    pub(super) columns: usize,
    pub(super) bare: &'a [Vec<bool>],
    pub(super) planes: &'a Planes,
}

impl Overlay<'_> {
    /// Layer `k`'s cells of `area`, in its order (none for a layer past the raster).
    pub(super) fn over(&self, k: usize, area: &CellBox) -> Vec<bool> {
        let mut cells = Vec::with_capacity(area.len());
        if let Some(layer) = self.planes.layer(k).filter(|_| self.planes.area == *area) {
            cells.extend_from_slice(layer);
            return cells;
        }
        let held = self.planes.layer(k).is_some();
        for j in area.j.clone() {
            match self.bare.get(k) {
                Some(layer) if !held => {
                    let row = j * self.columns;
                    cells.extend_from_slice(&layer[row + area.i.start..row + area.i.end]);
                }
                _ => cells.extend(area.i.clone().map(|i| self.get(k, i, j))),
            }
        }
        cells
    }

    /// Whether cell (`i`, `j`) of layer `k` is in the set (false for a layer past the raster).
    pub(super) fn get(&self, k: usize, i: usize, j: usize) -> bool {
        match self.planes.get(k, i, j) {
            Some(cell) => cell,
            None => self
                .bare
                .get(k)
                .is_some_and(|layer| layer[j * self.columns + i]),
        }
    }
}
