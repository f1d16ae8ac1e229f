//! Capsule voids in the raster: the cells a void takes out of a layer, and the perimeters the
//! slicer lays around each hole it leaves.

use nalgebra::Point3;

use super::cells::CellBox;
use super::distance::squared_distance;
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
            let cover = self.cover(void).and_then(|cover| cover.within(area));
            let Some(cover) = cover else {
                continue;
            };
            for j in cover.j {
                for i in cover.i.clone() {
                    if let Some(local) = area.local(i, j) {
                        if !cells[local] && void.contains(&self.point_at(i, j, z)) {
                            cells[local] = true;
                        }
                    }
                }
            }
        }
        cells
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

    /// The cells of `area` within the perimeter thickness of a hole's outline: of a cell of
    /// `hole` (the void cells of a layer that lie inside the mesh, over `area`), measured from
    /// the hole's edge, half a cell past its outermost cell centres. Exact for the cells of
    /// `area` when `area` holds every hole cell.
    pub(super) fn near_hole(&self, hole: &[bool], area: &CellBox) -> Vec<bool> {
        let reach = self.slicing.perimeter_thickness / self.cell + 0.5;
        let mut near = vec![false; hole.len()];
        // The distances that matter lie within the reach of the hole's box.
        let Some(held) = holding(hole, area) else {
            return near;
        };
        let around = held.grown(reach.ceil() as usize + 1, self).within(area);
        let Some(around) = around else {
            return near;
        };
        let marked: Vec<bool> = around
            .cells()
            .map(|(i, j)| area.local(i, j).is_some_and(|a| hole[a]))
            .collect();
        let distance = squared_distance(&marked, around.width(), around.height());
        for ((i, j), (d, &h)) in around.cells().zip(distance.iter().zip(&marked)) {
            if !h && *d < reach * reach {
                if let Some(a) = area.local(i, j) {
                    near[a] = true;
                }
            }
        }
        near
    }
}

/// The smallest box holding every marked cell of `cells` (over `area`); `None` without one.
fn holding(cells: &[bool], area: &CellBox) -> Option<CellBox> {
    area.cells()
        .zip(cells)
        .filter(|(_, &marked)| marked)
        .map(|((i, j), _)| CellBox {
            i: i..i + 1,
            j: j..j + 1,
        })
        .reduce(|a, b| a.union(&b))
}
