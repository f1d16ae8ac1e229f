//! Capsule voids in the raster: the cells a void takes out of a layer, and the perimeters the
//! slicer lays around each hole it leaves.

use nalgebra::Point3;

use super::cells::CellBox;
use super::distance::near_marked;
use super::layout::{Layout, U, UP, V};
use crate::geometry::distance::point_segment_distance;

/// A capsule-shaped void cut from a printed mesh: the points within `radius` of the segment
/// from `from` to `to`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Void {
    /// One end of the axis.
    pub from: Point3<f64>,
    /// The other end of the axis.
    pub to: Point3<f64>,
    /// The radius.
    pub radius: f64,
}

impl Void {
    /// Whether the plane at height `z` (print frame) cuts the void.
    pub(super) fn crosses(&self, z: f64) -> bool {
        let (r, a, b) = (self.radius, self.from, self.to);
        z > a[UP].min(b[UP]) - r && z < a[UP].max(b[UP]) + r
    }

    /// Whether `point` lies inside the void (strictly within the radius of the axis).
    fn contains(&self, point: &Point3<f64>) -> bool {
        point_segment_distance(point, &self.from, &self.to) < self.radius
    }
}

impl Layout {
    /// The cells of `area` in layer `k` whose centres lie in one of `voids` (print frame), in
    /// `area`'s order.
    pub(super) fn in_voids(&self, k: usize, voids: &[Void], area: &CellBox) -> Vec<bool> {
        let mut cells = vec![false; area.len()];
        let z = self.slice_height(k);
        for void in voids {
            if !void.crosses(z) {
                continue;
            }
            let cover = self.cover_at(void, z).and_then(|cover| cover.within(area));
            let Some(cover) = cover else {
                continue;
            };
            // Every cell of the cover is tested (the test is the same, set or not), row by row.
            for j in cover.j {
                let start = (j - area.j.start) * area.width() + cover.i.start - area.i.start;
                let row = &mut cells[start..start + cover.i.len()];
                for (cell, i) in row.iter_mut().zip(cover.i.clone()) {
                    *cell |= void.contains(&self.point_at(i, j, z));
                }
            }
        }
        cells
    }

    /// The box of the cells whose centres can lie in a cross-section of one of `voids` in
    /// layer `k`; `None` when none can.
    pub(super) fn sections_cover(&self, k: usize, voids: &[Void]) -> Option<CellBox> {
        let z = self.slice_height(k);
        voids
            .iter()
            .filter(|void| void.crosses(z))
            .filter_map(|void| self.cover_at(void, z))
            .reduce(|a, b| a.union(&b))
    }

    /// The cells whose centres lie within the box around `void` (print frame), seen from
    /// above; `None` when none do.
    pub(super) fn cover(&self, void: &Void) -> Option<CellBox> {
        let (r, a, b) = (void.radius, void.from, void.to);
        let span = |axis: usize, origin: f64, count: usize| {
            let low = a[axis].min(b[axis]) - r;
            let high = a[axis].max(b[axis]) + r;
            let first = ((low - origin) / self.cell - 0.5).ceil().max(0.0) as usize;
            let last = ((high - origin) / self.cell - 0.5).floor();
            (last >= 0.0)
                .then(|| first..(last as usize + 1).min(count))
                .filter(|range| !range.is_empty())
        };
        Some(CellBox {
            i: span(U, self.origin.0, self.columns)?,
            j: span(V, self.origin.1, self.rows)?,
        })
    }

    /// The cells whose centres can lie in `void`'s cross-section at height `z`: the box, seen
    /// from above, of the part of the void between `z − radius` and `z + radius`, grown by a
    /// cell against rounding; `None` when it holds no cell.
    pub(super) fn cover_at(&self, void: &Void, z: f64) -> Option<CellBox> {
        let (r, a, b) = (void.radius, void.from, void.to);
        let rise = b[UP] - a[UP];
        let (t0, t1) = if rise != 0.0 {
            let (low, high) = ((z - r - a[UP]) / rise, (z + r - a[UP]) / rise);
            (low.min(high).max(0.0), low.max(high).min(1.0))
        } else {
            (0.0, 1.0)
        };
        if t0.is_nan() || t1.is_nan() || t0 > t1 {
            return None;
        }
        let part = Void {
            from: a + (b - a) * t0,
            to: a + (b - a) * t1,
            radius: r,
        };
        self.cover(&part).map(|cover| cover.grown(1, self))
    }

    /// The cells of `area` within the perimeter thickness of a hole's outline: of a cell of
    /// `hole` (the void cells of a layer that lie inside the mesh, over `area`), measured from
    /// the hole's edge, half a cell past its outermost cell centres. Exact for the cells of
    /// `area` when `area` holds every hole cell.
    pub(super) fn near_hole(&self, hole: &[bool], area: &CellBox) -> Vec<bool> {
        let reach = self.slicing.perimeter_thickness / self.cell + 0.5;
        let limit = reach * reach;
        let near = near_marked(hole, area.width(), area.height(), reach, |d| d < limit);
        near.iter().zip(hole).map(|(&n, &h)| n && !h).collect()
    }
}
