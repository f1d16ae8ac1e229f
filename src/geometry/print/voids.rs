//! Capsule voids in the raster: the cells a void takes out of a layer, and the perimeters the
//! slicer lays around each hole it leaves.

use nalgebra::Point3;

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
    /// Whether `point` lies inside the void (strictly within the radius of the axis).
    fn contains(&self, point: &Point3<f64>) -> bool {
        point_segment_distance(point, &self.from, &self.to) < self.radius
    }
}

impl Layout {
    /// The cells of layer `k` whose centres lie in one of `voids` (print frame).
    pub(super) fn in_voids(&self, k: usize, voids: &[Void]) -> Vec<bool> {
        let mut cells = vec![false; self.columns * self.rows];
        let z = self.slice_height(k);
        for void in voids {
            let (r, a, b) = (void.radius, void.from, void.to);
            if z <= a[UP].min(b[UP]) - r || z >= a[UP].max(b[UP]) + r {
                continue;
            }
            let span = |axis: usize, origin: f64, count: usize| {
                let low = a[axis].min(b[axis]) - r;
                let high = a[axis].max(b[axis]) + r;
                let first = ((low - origin) / self.cell - 0.5).ceil().max(0.0) as usize;
                let last = ((high - origin) / self.cell - 0.5).floor();
                (last >= 0.0).then(|| first..(last as usize + 1).min(count))
            };
            let columns = span(U, self.origin.0, self.columns);
            let rows = span(V, self.origin.1, self.rows);
            let (Some(columns), Some(rows)) = (columns, rows) else {
                continue;
            };
            for j in rows {
                for i in columns.clone() {
                    let index = j * self.columns + i;
                    if !cells[index] && void.contains(&self.point(index, z)) {
                        cells[index] = true;
                    }
                }
            }
        }
        cells
    }

    /// The cells within the perimeter thickness of a hole's outline: of a cell of `hole` (the
    /// void cells of a layer that lie inside the mesh), measured from the hole's edge, half a
    /// cell past its outermost cell centres.
    pub(super) fn near_hole(&self, hole: &[bool]) -> Vec<bool> {
        let reach = self.slicing.perimeter_thickness / self.cell + 0.5;
        if !hole.iter().any(|&h| h) {
            return vec![false; hole.len()];
        }
        squared_distance(hole, self.columns, self.rows)
            .iter()
            .zip(hole)
            .map(|(d, &h)| !h && *d < reach * reach)
            .collect()
    }
}
