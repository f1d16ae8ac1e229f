//! Capsule voids in the raster: the cells a void takes out of a layer, and the perimeters the
//! slicer lays around each hole it leaves.

use nalgebra::Point3;

use super::cells::CellBox;
use super::layout::{Layout, U, UP, V};
use super::sides::Sides;
use crate::geometry::distance::point_segment_distance;

/// Points of a void's cross-section outline [`Void::section`] passes through.
const SECTION_SIDES: usize = 48;

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

    /// The void's cross-section by the plane at height `z` (print frame), seen from above: a
    /// convex polygon through `SECTION_SIDES` points of its outline (each the point farthest
    /// along a direction, found in closed form), as its corners in order around it (some may
    /// repeat); empty when the plane misses it.
    pub(super) fn section(&self, z: f64) -> Vec<(f64, f64)> {
        if !self.crosses(z) {
            return Vec::new();
        }
        let (a, b, r) = (self.from, self.to, self.radius);
        let (du, dv, dz) = (b[U] - a[U], b[V] - a[V], b[UP] - a[UP]);
        // Along the axis, t in [0, 1]: the centre (a + t d) seen from above, and the radius of
        // the disc its sphere leaves in the plane, ρ(t) = sqrt(r² − (e − t dz)²).
        let e = z - a[UP];
        let (low, high) = if dz.abs() > 0.0 {
            let (t0, t1) = ((e - r) / dz, (e + r) / dz);
            (t0.min(t1).max(0.0), t0.max(t1).min(1.0))
        } else {
            (0.0, 1.0)
        };
        if low.is_nan() || high.is_nan() || low > high {
            return Vec::new();
        }
        let disc = |t: f64| (r * r - (e - t * dz).powi(2)).max(0.0).sqrt();
        (0..SECTION_SIDES)
            .map(|side| {
                let angle = std::f64::consts::TAU * side as f64 / SECTION_SIDES as f64;
                let (nu, nv) = (angle.cos(), angle.sin());
                // The farthest point along n maximises k t + ρ(t), k = d·n seen from above:
                // concave, so the stationary point (u = e − t dz with u dz = −k ρ) clamped to
                // the range, or an end of it.
                let k = du * nu + dv * nv;
                let reach = |t: f64| k * t + disc(t);
                let mut best = if reach(high) > reach(low) { high } else { low };
                if dz.abs() > 0.0 {
                    let u = -(k * dz.signum()) * r / (dz * dz + k * k).sqrt();
                    let stationary = ((e - u) / dz).clamp(low, high);
                    if reach(stationary) > reach(best) {
                        best = stationary;
                    }
                }
                let rho = disc(best);
                (a[U] + best * du + rho * nu, a[V] + best * dv + rho * nv)
            })
            .collect()
    }

    /// Whether `point` lies inside the void (strictly within the radius of the axis).
    fn contains(&self, point: &Point3<f64>) -> bool {
        point_segment_distance(point, &self.from, &self.to) < self.radius
    }
}

impl Layout {
    /// For each of `voids`' cross-sections in layer `k` (print frame), the squared distance from
    /// each cell `inside` (in `area`'s order) within `reach` cells of the section's box to the
    /// section, handed to `measured` with the cell's column and row in `area`: a cell near two
    /// sections is measured twice. Exact (to the sections' polygons): the nearest side is
    /// walked to from the last cell's ([`Sides::nearest_from`]). A straight line from a cell to
    /// a hole that crosses the outline is longer than the cell's distance to the outline, so
    /// the depth a cut layer takes from this and the bare layer's is what measuring inside it
    /// would give.
    pub(super) fn hole_distances(
        &self,
        k: usize,
        voids: &[Void],
        area: &CellBox,
        inside: &[bool],
        reach: usize,
        mut measured: impl FnMut(usize, usize, f64),
    ) {
        let z = self.slice_height(k);
        let width = area.width();
        for void in voids {
            let sides = Sides::of_convex(&void.section(z));
            let near = self
                .cover_at(void, z)
                .and_then(|cover| cover.grown(reach, self).within(area));
            let Some(near) = near.filter(|_| !sides.is_empty()) else {
                continue;
            };
            // Each row starts walking from the side the row before started from.
            let mut row_start = 0;
            for j in near.j.clone() {
                let v = self.origin.1 + (j as f64 + 0.5) * self.cell;
                let row = (j - area.j.start) * width;
                let (mut along, mut first) = (row_start, true);
                for i in near.i.clone() {
                    let c = row + (i - area.i.start);
                    if !inside[c] {
                        continue;
                    }
                    let point = (self.origin.0 + (i as f64 + 0.5) * self.cell, v);
                    let (side, d2) = sides.nearest_from(along, point);
                    if first {
                        (row_start, first) = (side, false);
                    }
                    along = side;
                    measured(i - area.i.start, j - area.j.start, d2);
                }
            }
        }
    }

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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sections_corners_are_the_farthest_points_of_the_cross_section() {
        let capsules = [
            // Tilted, level, upright, and nearly level.
            Void {
                from: Point3::new(0.0, 0.0, 0.0),
                to: Point3::new(20.0, 5.0, 12.0),
                radius: 4.0,
            },
            Void {
                from: Point3::new(0.0, 0.0, 5.0),
                to: Point3::new(0.0, 15.0, 5.0),
                radius: 3.0,
            },
            Void {
                from: Point3::new(1.0, 1.0, 0.0),
                to: Point3::new(1.0, 1.0, 9.0),
                radius: 2.5,
            },
            Void {
                from: Point3::new(0.0, 0.0, 5.0),
                to: Point3::new(30.0, 0.0, 5.3),
                radius: 6.0,
            },
        ];
        for void in capsules {
            let (low, high) = (
                void.from[UP].min(void.to[UP]),
                void.from[UP].max(void.to[UP]),
            );
            for step in 1..40 {
                let z = low - void.radius + (high - low + 2.0 * void.radius) * step as f64 / 40.0;
                let corners = void.section(z);
                assert_eq!(corners.len(), SECTION_SIDES, "{void:?} at {z}");
                for (side, corner) in corners.iter().enumerate() {
                    // On the capsule's surface.
                    let point = Point3::new(corner.0, corner.1, z);
                    let distance = point_segment_distance(&point, &void.from, &void.to);
                    assert!(
                        (distance - void.radius).abs() < 1e-9,
                        "{void:?} at {z}: {distance}"
                    );
                    // Farthest along its direction among the axis's discs, by a dense scan.
                    let angle = std::f64::consts::TAU * side as f64 / SECTION_SIDES as f64;
                    let (nu, nv) = (angle.cos(), angle.sin());
                    let reach = corner.0 * nu + corner.1 * nv;
                    let scanned = (0..=20_000)
                        .map(|i| {
                            let t = i as f64 / 20_000.0;
                            let centre = void.from + (void.to - void.from) * t;
                            let rise = z - centre[UP];
                            let disc = (void.radius.powi(2) - rise * rise).max(0.0).sqrt();
                            if rise.abs() > void.radius {
                                f64::NEG_INFINITY
                            } else {
                                centre[U] * nu + centre[V] * nv + disc
                            }
                        })
                        .fold(f64::NEG_INFINITY, f64::max);
                    assert!(
                        reach >= scanned - 1e-9,
                        "{void:?} at {z}: {reach} < {scanned}"
                    );
                }
            }
            assert!(void.section(low - void.radius - 0.01).is_empty());
            assert!(void.section(high + void.radius + 0.01).is_empty());
        }
    }
}
