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
    /// Layer `k`'s cells, when held.
    pub(super) fn layer(&self, k: usize) -> Option<&[bool]> {
        let layer = self.layers.get(k.checked_sub(self.first)?)?;
        Some(layer)
    }
}

/// Cell sets over every layer of the raster, read over the planes' area: `planes` where they
/// hold a layer, else `bare` (one full layer each).
#[derive(Clone, Copy)]
pub(super) struct Overlay<'a> {
    pub(super) columns: usize,
    pub(super) bare: &'a [Vec<bool>],
    pub(super) planes: &'a Planes,
}

impl<'a> Overlay<'a> {
    /// The box the cells are read over.
    pub(super) fn area(&self) -> &'a CellBox {
        &self.planes.area
    }

    /// Layer `k`'s cells of the planes' area; `None` for a layer past the raster.
    pub(super) fn rows(&self, k: usize) -> Option<Rows<'a>> {
        let area = self.area();
        match self.planes.layer(k) {
            Some(layer) => Some(Rows::held(layer, area)),
            None => Some(Rows::bare(self.bare.get(k)?, self.columns, area)),
        }
    }
}

/// One layer's cells of a box, borrowed from a set held over the box or over the whole
/// raster: the box's rows, each a slice.
#[derive(Clone, Copy)]
pub(super) struct Rows<'a> {
    cells: &'a [bool],
    /// Where the box's first row starts in `cells`.
    start: usize,
    /// From one row's start to the next's.
    stride: usize,
    width: usize,
}

impl<'a> Rows<'a> {
    /// The rows of `cells`, held over `area` (in its order).
    pub(super) fn held(cells: &'a [bool], area: &CellBox) -> Rows<'a> {
        Rows {
            cells,
            start: 0,
            stride: area.width(),
            width: area.width(),
        }
    }

    /// The rows of `area` in `cells`, a whole layer of a raster `columns` wide.
    pub(super) fn bare(cells: &'a [bool], columns: usize, area: &CellBox) -> Rows<'a> {
        Rows {
            cells,
            start: area.j.start * columns + area.i.start,
            stride: columns,
            width: area.width(),
        }
    }

    /// Row `y` of the box (counted from its first row).
    pub(super) fn row(&self, y: usize) -> &'a [bool] {
        let start = self.start + y * self.stride;
        &self.cells[start..start + self.width]
    }

    /// Columns `columns` of row `y` of the box (both counted from the box's first).
    pub(super) fn part(&self, y: usize, columns: Range<usize>) -> &'a [bool] {
        &self.row(y)[columns]
    }
}
