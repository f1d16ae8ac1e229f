//! The solid and sparse material of a raster, summed exactly: counts of cells and sums of their
//! indices, in integers. A cut adds and takes away only the cells it changes, and the volumes
//! are the same bits whatever order the cells were added in.

use std::ops::AddAssign;

use nalgebra::Point3;

use super::classes::Cell;
use super::layout::Layout;
use super::Region;

/// Integer sums over a set of cells of one layer thickness: how many, and the sums of their
/// column, row and layer indices.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct CellSums {
    count: i64,
    i: i64,
    j: i64,
    k: i64,
}

impl CellSums {
    fn add(&mut self, sign: i64, i: usize, j: usize, k: usize) {
        self.count += sign;
        self.i += sign * i as i64;
        self.j += sign * j as i64;
        self.k += sign * k as i64;
    }
}

impl AddAssign for CellSums {
    /// Counts the cells of `other` too.
    fn add_assign(&mut self, other: CellSums) {
        self.count += other.count;
        self.i += other.i;
        self.j += other.j;
        self.k += other.k;
    }
}

/// The cells of one class: the first layer apart, as it has its own thickness.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Tally {
    first: CellSums,
    upper: CellSums,
}

impl Tally {
    fn add(&mut self, sign: i64, i: usize, j: usize, k: usize) {
        let sums = if k == 0 {
            &mut self.first
        } else {
            &mut self.upper
        };
        sums.add(sign, i, j, k);
    }

    /// The cells' volume and centroid, print frame; `fallback` as the centroid of none.
    fn region(&self, layout: &Layout, fallback: Point3<f64>) -> Region {
        let (h0, h) = (
            layout.slicing.first_layer_height,
            layout.slicing.layer_height,
        );
        let (first, upper) = (&self.first, &self.upper);
        let (n0, n) = (first.count as f64, upper.count as f64);
        // Cell volumes per unit of cross-section: the weights of the two thicknesses.
        let weight = h0 * n0 + h * n;
        let volume = layout.cell * layout.cell * weight;
        if weight.is_nan() || weight <= 0.0 {
            return Region {
                volume: volume.max(0.0),
                centroid: fallback,
            };
        }
        // Mean cell index along a raster axis (the cell centre is half a cell past its corner).
        let mean = |first_sum: i64, upper_sum: i64| {
            (h0 * (first_sum as f64 + 0.5 * n0) + h * (upper_sum as f64 + 0.5 * n)) / weight
        };
        // Layer k ≥ 1 is sliced at bottom + h0 + (k − ½)h, layer 0 at bottom + h0/2.
        let upper_heights = n * (h0 - 0.5 * h) + h * upper.k as f64;
        let z = layout.bottom + (h0 * n0 * 0.5 * h0 + h * upper_heights) / weight;
        Region {
            volume,
            centroid: Point3::new(
                layout.origin.0 + layout.cell * mean(first.i, upper.i),
                layout.origin.1 + layout.cell * mean(first.j, upper.j),
                z,
            ),
        }
    }
}

impl AddAssign for Tally {
    /// Counts the cells of `other` too.
    fn add_assign(&mut self, other: Tally) {
        self.first += other.first;
        self.upper += other.upper;
    }
}

/// The solid and the sparse cells of some layers.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct Totals {
    solid: Tally,
    sparse: Tally,
}

impl Totals {
    /// Counts cell (`i`, `j`) of layer `k` as `class` (`sign` 1) or no longer as it (−1).
    pub(super) fn add(&mut self, sign: i64, class: Cell, i: usize, j: usize, k: usize) {
        match class {
            Cell::Solid => self.solid.add(sign, i, j, k),
            Cell::Sparse => self.sparse.add(sign, i, j, k),
            Cell::Outside => {}
        }
    }

    /// Counts every cell of layer `k`, of `class` (row by row over the raster).
    pub(super) fn add_layer(&mut self, layout: &Layout, k: usize, class: &[Cell]) {
        for (j, row) in class.chunks(layout.columns).enumerate() {
            for (i, &cell) in row.iter().enumerate() {
                self.add(1, cell, i, j, k);
            }
        }
    }

    /// The solid and the sparse region, print frame.
    pub(super) fn regions(&self, layout: &Layout) -> (Region, Region) {
        let fallback = layout.centre();
        (
            self.solid.region(layout, fallback),
            self.sparse.region(layout, fallback),
        )
    }
}

impl AddAssign for Totals {
    /// Counts the cells of `other` too (a change: some counted no longer).
    fn add_assign(&mut self, other: Totals) {
        self.solid += other.solid;
        self.sparse += other.sparse;
    }
}
