//! The layers and the raster of one mesh in its print frame: slicing, the cells inside each
//! slice and those within the perimeters of its outline.

use nalgebra::{Point3, Vector3};

use super::Slicing;
use crate::geometry::mesh::TriMesh;

/// The raster holds at most about this many cells over all layers; a finer cell than
/// `perimeter_thickness / CELLS_PER_PERIMETER` is never used.
const CELL_BUDGET: f64 = 1e7;

/// Cells across the perimeter thickness, at most.
const CELLS_PER_PERIMETER: f64 = 4.0;

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
        let finest = slicing.perimeter_thickness / CELLS_PER_PERIMETER;
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
        Some(Layout {
            slicing: *slicing,
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
        })
    }

    /// Row `j`'s cell centre, along v.
    pub(super) fn row_centre(&self, j: usize) -> f64 {
        self.origin.1 + (j as f64 + 0.5) * self.cell
    }

    /// The cells whose centres lie inside the slice: where the winding number of its segments
    /// is positive, row by row. For a closed, outward-oriented surface that does not cross
    /// itself this is the even-odd rule; where surfaces cross or shells overlap, it is their
    /// union, as a slicer prints it.
    pub(super) fn inside(&self, segments: &[Segment]) -> Vec<bool> {
        let mut crossings: Vec<Vec<(f64, i8)>> = vec![Vec::new(); self.rows];
        for segment in segments {
            let [(u0, v0), (u1, v1)] = segment.ends;
            let (low, high) = (v0.min(v1), v0.max(v1));
            let first = ((low - self.origin.1) / self.cell - 0.5).ceil().max(0.0) as usize;
            for (j, row) in crossings.iter_mut().enumerate().skip(first) {
                let v = self.row_centre(j);
                if v > high {
                    break;
                }
                if (v0 >= v) != (v1 >= v) {
                    row.push((u0 + (v - v0) * (u1 - u0) / (v1 - v0), segment.winding));
                }
            }
        }
        let mut inside = vec![false; self.columns * self.rows];
        let mut spans = Vec::new();
        for (j, row) in crossings.iter_mut().enumerate() {
            row.sort_by(|a, b| a.0.total_cmp(&b.0));
            // The spans of positive winding number, from where it turns positive to where it
            // falls back.
            spans.clear();
            let (mut winding, mut from) = (0i32, 0.0);
            for &(u, turn) in row.iter() {
                let before = winding;
                winding += i32::from(turn);
                if before <= 0 && winding > 0 {
                    from = u;
                } else if before > 0 && winding <= 0 {
                    spans.push((from, u));
                }
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
        inside
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
