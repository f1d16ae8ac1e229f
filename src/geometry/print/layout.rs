//! The layers and the raster of one mesh in its print frame: slicing, the cells inside each
//! slice and those within the perimeters of its outline.

use nalgebra::{Point3, Vector3};

use super::outline::{outline, Mark};
use super::Slicing;
use crate::geometry::mesh::TriMesh;

/// The raster holds at most about this many cells over all layers; a finer cell than
/// `perimeter_thickness / CELLS_PER_PERIMETER` is never used.
const CELL_BUDGET: f64 = 1e7;

/// Cells across the perimeter thickness, at most.
const CELLS_PER_PERIMETER: f64 = 4.0;

/// Cells across the part's narrower side, at least (before the budget coarsens them).
const MIN_CELLS_ACROSS: f64 = 32.0;

/// Cells along the part's wider side, at most: the budget alone allows any number along one
/// side of a part without width in the other.
const MAX_CELLS_ALONG: f64 = 4096.0;

/// The print frame's axes: up (the build direction), and the raster's columns and rows.
pub(super) const UP: usize = 2;
pub(super) const U: usize = 0;
pub(super) const V: usize = 1;

/// The layers and the raster of one mesh, print frame.
#[derive(Clone)]
pub(super) struct Layout {
    pub(super) slicing: Slicing,
    /// The mesh's lowest point along z.
    pub(super) bottom: f64,
    pub(super) layers: usize,
    /// Raster origin (the corner of cell 0) and cell size.
    pub(super) origin: (f64, f64),
    pub(super) cell: f64,
    pub(super) columns: usize,
    pub(super) rows: usize,
}

/// A slice segment in raster coordinates (u, v), and which way it turns the winding number.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Segment {
    /// Its ends, in the order its triangle's edges meet the slice plane.
    pub(super) ends: [(f64, f64); 2],
    /// What crossing it towards +u adds to the winding number: +1 into the solid its triangle
    /// bounds, −1 out of it.
    pub(super) winding: i8,
    /// What crossing it towards +v adds.
    pub(super) column_winding: i8,
}

impl Layout {
    pub(super) fn new(mesh: &TriMesh, slicing: &Slicing) -> Option<Layout> {
        let (u, v) = (U, V);
        if mesh
            .positions
            .iter()
            .any(|p| !p.iter().all(|x| x.is_finite()))
        {
            return None;
        }
        let first = mesh.positions.first()?;
        let (mut low, mut high) = (first.coords, first.coords);
        for p in &mesh.positions {
            low = low.inf(&p.coords);
            high = high.sup(&p.coords);
        }
        let height = high[UP] - low[UP];
        let (h, h0) = (slicing.layer_height, slicing.first_layer_height);
        if !(h > 0.0 && h0 > 0.0 && height > 0.0 && height.is_finite()) {
            return None;
        }
        // Layer 0 is sliced at h0/2, layer k ≥ 1 at h0 + (k − ½)h; keep those below the top.
        let layers = if height <= h0 / 2.0 {
            1
        } else {
            1 + (((height - h0) / h + 0.5).ceil() - 1.0).max(0.0) as usize
        };
        let (width, depth) = (high[u] - low[u], high[v] - low[v]);
        if !(width.is_finite() && depth.is_finite()) {
            return None;
        }
        // Perimeters as thick as the part itself still leave the outline its cells; a part
        // flat in one direction still gets at most MAX_CELLS_ALONG cells along the other.
        let finest = (slicing.perimeter_thickness / CELLS_PER_PERIMETER)
            .min(width.min(depth) / MIN_CELLS_ACROSS)
            .max(width.max(depth) / MAX_CELLS_ALONG);
        let budget = (width * depth * layers as f64 / CELL_BUDGET).sqrt();
        let mut cell = finest.max(budget);
        if !(cell > 0.0 && cell.is_finite()) {
            cell = (width.max(depth) / 256.0).max(f64::MIN_POSITIVE);
        }
        let columns = ((width / cell).ceil() as usize).max(1);
        let rows = ((depth / cell).ceil() as usize).max(1);
        // Centre the raster on the mesh's footprint.
        let origin = (
            low[u] - (columns as f64 * cell - width) / 2.0,
            low[v] - (rows as f64 * cell - depth) / 2.0,
        );
        // Solid layers past the part's height print it the same: solid.
        let slicing = Slicing {
            top_layers: slicing.top_layers.min(layers),
            bottom_layers: slicing.bottom_layers.min(layers),
            ..*slicing
        };
        Some(Layout {
            slicing,
            bottom: low[UP],
            layers,
            origin,
            cell,
            columns,
            rows,
        })
    }

    /// Height of layer `k`'s slice plane (its middle), along z.
    pub(super) fn slice_height(&self, k: usize) -> f64 {
        let (h, h0) = (self.slicing.layer_height, self.slicing.first_layer_height);
        if k == 0 {
            self.bottom + h0 / 2.0
        } else {
            self.bottom + h0 + (k as f64 - 0.5) * h
        }
    }

    /// The print-frame point at the centre of cell (`i`, `j`) and height `z`.
    pub(super) fn point_at(&self, i: usize, j: usize, z: f64) -> Point3<f64> {
        Point3::new(
            self.origin.0 + (i as f64 + 0.5) * self.cell,
            self.origin.1 + (j as f64 + 0.5) * self.cell,
            z,
        )
    }

    /// The centre of the raster's box, for empty regions.
    pub(super) fn centre(&self) -> Point3<f64> {
        Point3::new(
            self.origin.0 + self.columns as f64 * self.cell / 2.0,
            self.origin.1 + self.rows as f64 * self.cell / 2.0,
            self.slice_height(0),
        )
    }

    /// Each layer's slice of `mesh` as segments (u, v), triangles in order.
    pub(super) fn slice(&self, mesh: &TriMesh) -> Vec<Vec<Segment>> {
        let up = UP;
        let mut layers = vec![Vec::new(); self.layers];
        for triangle in &mesh.triangles {
            let corners = triangle.map(|i| mesh.positions.get(i as usize).map(|p| p.coords));
            let [Some(a), Some(b), Some(c)] = corners else {
                continue;
            };
            let low = a[up].min(b[up]).min(c[up]);
            let high = a[up].max(b[up]).max(c[up]);
            for (k, layer) in layers
                .iter_mut()
                .enumerate()
                .skip(self.first_layer_above(low))
            {
                let z = self.slice_height(k);
                if z > high {
                    break;
                }
                if let Some(segment) = self.cut(&[a, b, c], z) {
                    layer.push(segment);
                }
            }
        }
        layers
    }

    /// The first layer whose slice height is at or above `z`.
    pub(super) fn first_layer_above(&self, z: f64) -> usize {
        let (h, h0) = (self.slicing.layer_height, self.slicing.first_layer_height);
        if z - self.bottom <= h0 / 2.0 {
            return 0;
        }
        (((z - self.bottom - h0) / h + 0.5).ceil().max(1.0) as usize).min(self.layers)
    }

    /// The segment where the plane at height `z` cuts a triangle: points at or above `z`
    /// count as above, so a plane through a vertex cuts consistently across neighbours.
    ///
    /// Its winding: of a triangle seen counter-clockwise from outside, one edge rises through
    /// the plane and one falls; from the rising edge's point to the falling edge's, the solid
    /// lies on the right, so moving towards +u leaves it where the falling point is lower in v.
    pub(super) fn cut(&self, corners: &[Vector3<f64>; 3], z: f64) -> Option<Segment> {
        let up = UP;
        let mut points = Vec::with_capacity(2);
        let (mut rising, mut falling) = (None, None);
        for e in 0..3 {
            let (p, q) = (corners[e], corners[(e + 1) % 3]);
            if (p[up] >= z) != (q[up] >= z) {
                let t = (z - p[up]) / (q[up] - p[up]);
                let x = p + (q - p) * t;
                let point = (x[U], x[V]);
                points.push(point);
                if q[up] >= z {
                    rising = Some(point);
                } else {
                    falling = Some(point);
                }
            }
        }
        let (Some(rising), Some(falling)) = (rising, falling) else {
            return None;
        };
        (points.len() == 2).then(|| Segment {
            ends: [points[0], points[1]],
            winding: if falling.1 < rising.1 { -1 } else { 1 },
            column_winding: if falling.0 < rising.0 { 1 } else { -1 },
        })
    }

    /// Row `j`'s cell centre, along v.
    pub(super) fn row_centre(&self, j: usize) -> f64 {
        self.origin.1 + (j as f64 + 0.5) * self.cell
    }

    /// A layer's raster from its slice `segments`: the cells inside it, and those within the
    /// perimeter thickness of its outline.
    pub(super) fn rasterize(&self, segments: &[Segment]) -> (Vec<bool>, Vec<bool>, Vec<f32>) {
        let (inside, mut marks) = self.inside(segments);
        marks.extend(self.column_marks(segments));
        let outline = outline(segments, marks);
        let depth = self.depth(&outline, &inside);
        (inside, self.near_outline(&outline), depth)
    }

    /// The cells whose centres lie inside the slice: where the winding number of its segments
    /// is positive, row by row. For a closed, outward-oriented surface that does not cross
    /// itself this is the even-odd rule; where surfaces cross or shells overlap, it is their
    /// union, as a slicer prints it.
    ///
    /// Beside it, the [`Mark`]s of every crossing of a segment and a row.
    pub(super) fn inside(&self, segments: &[Segment]) -> (Vec<bool>, Vec<Mark>) {
        let crossings = self.row_crossings(segments);
        let mut inside = vec![false; self.columns * self.rows];
        let mut marks = Vec::new();
        let mut spans = Vec::new();
        for (j, row) in crossings.iter().enumerate() {
            // The spans of positive winding number, from where it turns positive to where it
            // falls back; the crossings at one place taken together.
            spans.clear();
            let (mut winding, mut from) = (0i32, 0.0);
            for group in row.chunk_by(|a, b| a.0 == b.0) {
                let (u, before) = (group[0].0, winding);
                winding += group.iter().map(|c| i32::from(c.1)).sum::<i32>();
                if before <= 0 && winding > 0 {
                    from = u;
                } else if before > 0 && winding <= 0 {
                    spans.push((from, u));
                }
                let bounds = (before > 0) != (winding > 0);
                let v = self.row_centre(j);
                marks.extend(group.iter().map(|&(_, _, index)| {
                    let [(_, v0), (_, v1)] = segments[index as usize].ends;
                    Mark {
                        segment: index,
                        along: (v - v0) / (v1 - v0),
                        bounds,
                        by_row: true,
                    }
                }));
            }
            for &(low, high) in &spans {
                let start = ((low - self.origin.0) / self.cell - 0.5).ceil().max(0.0);
                let end = ((high - self.origin.0) / self.cell - 0.5).floor();
                if end < start {
                    continue;
                }
                let (start, end) = (start as usize, (end as usize).min(self.columns - 1));
                if start > end {
                    continue;
                }
                for cell in &mut inside[j * self.columns + start..=j * self.columns + end] {
                    *cell = true;
                }
            }
        }
        (inside, marks)
    }

    /// Per row, where each segment crosses it: (u, the segment's turn of the winding number,
    /// the segment's index), in order of u (segments in their order where u ties).
    fn row_crossings(&self, segments: &[Segment]) -> Vec<Vec<(f64, i8, u32)>> {
        let mut crossings: Vec<Vec<(f64, i8, u32)>> = vec![Vec::new(); self.rows];
        for (index, segment) in segments.iter().enumerate() {
            let [(u0, v0), (u1, v1)] = segment.ends;
            let (low, high) = (v0.min(v1), v0.max(v1));
            let first = ((low - self.origin.1) / self.cell - 0.5).ceil().max(0.0) as usize;
            for (j, row) in crossings.iter_mut().enumerate().skip(first) {
                let v = self.row_centre(j);
                if v > high {
                    break;
                }
                if (v0 >= v) != (v1 >= v) {
                    let u = u0 + (v - v0) * (u1 - u0) / (v1 - v0);
                    row.push((u, segment.winding, index as u32));
                }
            }
        }
        for row in &mut crossings {
            row.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        crossings
    }

    /// Along every row of the slice, how long the winding number of `segments` is positive
    /// (summed, times the row spacing: the union's cross-section), and the moments of what the
    /// winding number counts beyond the union, about `reference` (u, v): `∫ w′`, `∫ w′ u`,
    /// `∫ w′ v`, `∫ w′ u²`, `∫ w′ v²`, `∫ w′ u v` over the slice, with `w′ = w − 1` where `w` is
    /// positive and `w` where it is not. Exact along each row; each row stands for a strip one
    /// cell wide.
    pub(super) fn winding_areas(
        &self,
        segments: &[Segment],
        reference: (f64, f64),
    ) -> (f64, [f64; 6]) {
        let mut union = 0.0;
        let mut moments = [0.0; 6];
        let strip = self.cell * self.cell / 12.0;
        for (j, row) in self.row_crossings(segments).iter().enumerate() {
            let v = self.row_centre(j) - reference.1;
            let mut winding = 0i32;
            for pair in row.windows(2) {
                winding += i32::from(pair[0].1);
                let (a, b) = (pair[0].0 - reference.0, pair[1].0 - reference.0);
                if winding > 0 {
                    union += b - a;
                }
                if !(0..=1).contains(&winding) {
                    let weight = f64::from(winding - i32::from(winding > 0));
                    let length = weight * (b - a);
                    let along = weight * (b * b - a * a) / 2.0;
                    moments[0] += length;
                    moments[1] += along;
                    moments[2] += v * length;
                    moments[3] += weight * (b * b * b - a * a * a) / 3.0;
                    moments[4] += (v * v + strip) * length;
                    moments[5] += v * along;
                }
            }
        }
        (union * self.cell, moments.map(|m| m * self.cell))
    }

    /// The [`Mark`]s of every crossing of a segment and a column (the scan of [`Layout::inside`]
    /// along v): what tells whether a segment that crosses no row, one along a row, bounds the
    /// union.
    fn column_marks(&self, segments: &[Segment]) -> Vec<Mark> {
        let mut crossings: Vec<Vec<(f64, i8, u32)>> = vec![Vec::new(); self.columns];
        for (index, segment) in segments.iter().enumerate() {
            let [(u0, v0), (u1, v1)] = segment.ends;
            let (low, high) = (u0.min(u1), u0.max(u1));
            let first = ((low - self.origin.0) / self.cell - 0.5).ceil().max(0.0) as usize;
            for (i, column) in crossings.iter_mut().enumerate().skip(first) {
                let u = self.origin.0 + (i as f64 + 0.5) * self.cell;
                if u > high {
                    break;
                }
                if (u0 >= u) != (u1 >= u) {
                    let v = v0 + (u - u0) * (v1 - v0) / (u1 - u0);
                    column.push((v, segment.column_winding, index as u32));
                }
            }
        }
        let mut marks = Vec::new();
        for (i, column) in crossings.iter_mut().enumerate() {
            column.sort_by(|a, b| a.0.total_cmp(&b.0));
            let u = self.origin.0 + (i as f64 + 0.5) * self.cell;
            let mut winding = 0i32;
            for group in column.chunk_by(|a, b| a.0 == b.0) {
                let before = winding;
                winding += group.iter().map(|c| i32::from(c.1)).sum::<i32>();
                let bounds = (before > 0) != (winding > 0);
                marks.extend(group.iter().map(|&(_, _, index)| {
                    let [(u0, _), (u1, _)] = segments[index as usize].ends;
                    Mark {
                        segment: index,
                        along: (u - u0) / (u1 - u0),
                        bounds,
                        by_row: false,
                    }
                }));
            }
        }
        marks
    }

    /// The cells within the perimeter thickness of a segment.
    pub(super) fn near_outline(&self, segments: &[Segment]) -> Vec<bool> {
        let t = self.slicing.perimeter_thickness;
        let mut near = vec![false; self.columns * self.rows];
        if t <= 0.0 {
            return near;
        }
        // The cells whose centres lie in [low − t, high + t] along one axis.
        let span = |low: f64, high: f64, origin: f64, count: usize| {
            let first = ((low - t - origin) / self.cell - 0.5).ceil().max(0.0) as usize;
            let last = ((high + t - origin) / self.cell - 0.5).floor();
            (last >= 0.0).then(|| first..(last as usize + 1).min(count))
        };
        for segment in segments {
            let [(u0, v0), (u1, v1)] = segment.ends;
            let columns = span(u0.min(u1), u0.max(u1), self.origin.0, self.columns);
            let rows = span(v0.min(v1), v0.max(v1), self.origin.1, self.rows);
            let (Some(columns), Some(rows)) = (columns, rows) else {
                continue;
            };
            let (du, dv) = (u1 - u0, v1 - v0);
            let length2 = du * du + dv * dv;
            for j in rows {
                let v = self.row_centre(j);
                for i in columns.clone() {
                    let u = self.origin.0 + (i as f64 + 0.5) * self.cell;
                    let s = if length2 > 0.0 {
                        (((u - u0) * du + (v - v0) * dv) / length2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let (eu, ev) = (u - u0 - s * du, v - v0 - s * dv);
                    if eu * eu + ev * ev < t * t {
                        near[j * self.columns + i] = true;
                    }
                }
            }
        }
        near
    }
}
