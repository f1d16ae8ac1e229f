//! Where an FDM slicer puts solid material and where sparse infill in a closed mesh.
//!
//! The mesh is turned into its print frame (+z up, away from the bed) and cut into layers along
//! z, as a slicer does: the first layer
//! `first_layer_height` thick, the others `layer_height`, each sliced at its mid-height. Every
//! slice is rasterised on a square grid (a cell is inside when its centre is, by the even-odd
//! rule on the slice's segments) and each inside cell is classified:
//! - **perimeter**: within `perimeter_thickness` (horizontally) of the slice outline;
//! - **top or bottom**: the same column is outside the mesh in one of the `top_layers` layers
//!   above, or the `bottom_layers` below (the solid layers under every top surface and over
//!   every bottom surface, sloping ones included); or within `surface_margin` of a top surface
//!   (the part of a layer's fill region, inside the perimeters, that the layer above does not
//!   cover) of this layer or one of the `top_layers − 1` above, or of a bottom surface of this
//!   layer or one of the `bottom_layers − 1` below (PrusaSlicer grows every top and bottom
//!   surface by a margin before it adds the solid layers);
//! - **small region**: what is left forms a region (4-connected cells) smaller than
//!   `min_sparse_area`, which the slicer fills solid;
//! - **sparse**: the rest, printed at the infill fraction.
//!
//! The first three are [`PrintVolumes::solid`]; their centroids are turned back into the rest
//! frame. The result does not depend on the design and is computed once per component and print
//! orientation.

use nalgebra::{Point3, Rotation3, Vector3};

use super::mass::MassProperties;
use super::mesh::TriMesh;

/// How the slicer prints, in the mesh's units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slicing {
    /// The print orientation: rest frame to print frame, whose +z is the build direction.
    pub to_print: Rotation3<f64>,
    /// Horizontal thickness of the perimeters.
    pub perimeter_thickness: f64,
    /// Height of every layer but the first.
    pub layer_height: f64,
    /// Height of the first layer.
    pub first_layer_height: f64,
    /// Solid layers under a top surface.
    pub top_layers: usize,
    /// Solid layers over a bottom surface.
    pub bottom_layers: usize,
    /// Interior regions of a layer smaller than this area are filled solid.
    pub min_sparse_area: f64,
    /// How far a top or bottom surface's solid layers reach past it into the sparse infill.
    pub surface_margin: f64,
}

/// A volume and its centroid, rest frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Region {
    /// Cubic units.
    pub volume: f64,
    /// The centroid (a representative point when the volume is zero).
    pub centroid: Point3<f64>,
}

/// A printed component's material: solid everywhere in `solid`, at the infill fraction in
/// `sparse`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrintVolumes {
    /// Printed at full density: perimeters, top and bottom layers, small regions.
    pub solid: Region,
    /// Printed at the infill fraction.
    pub sparse: Region,
}

impl PrintVolumes {
    /// The uniform model: the whole solid of `mass` at the infill fraction, nothing solid.
    pub fn uniform(mass: &MassProperties) -> PrintVolumes {
        PrintVolumes {
            solid: Region {
                volume: 0.0,
                centroid: mass.centroid,
            },
            sparse: Region {
                volume: mass.volume,
                centroid: mass.centroid,
            },
        }
    }
}

/// The raster holds at most about this many cells over all layers; a finer cell than
/// `perimeter_thickness / CELLS_PER_PERIMETER` is never used.
const CELL_BUDGET: f64 = 1e7;

/// Cells across the perimeter thickness, at most.
const CELLS_PER_PERIMETER: f64 = 4.0;

/// The solid and sparse volumes of `mesh` printed with `slicing` (see the module
/// documentation). A mesh without extent or with a non-finite coordinate, or settings without a
/// positive layer height, gives empty regions at the origin.
pub fn print_volumes(mesh: &TriMesh, slicing: &Slicing) -> PrintVolumes {
    let empty = PrintVolumes {
        solid: Region {
            volume: 0.0,
            centroid: Point3::origin(),
        },
        sparse: Region {
            volume: 0.0,
            centroid: Point3::origin(),
        },
    };
    let to_print = exact_axes(&slicing.to_print);
    let printed = TriMesh {
        positions: mesh.positions.iter().map(|p| to_print * p).collect(),
        triangles: mesh.triangles.clone(),
    };
    let mesh = &printed;
    let Some(layout) = Layout::new(mesh, slicing) else {
        return empty;
    };
    let segments = layout.slice(mesh);
    let inside: Vec<Vec<bool>> = segments.iter().map(|s| layout.inside(s)).collect();
    let near: Vec<Vec<bool>> = segments.iter().map(|s| layout.near_outline(s)).collect();
    let fill: Vec<Vec<bool>> = inside
        .iter()
        .zip(&near)
        .map(|(inside, near)| inside.iter().zip(near).map(|(i, n)| *i && !n).collect())
        .collect();
    let tops: Vec<Vec<bool>> = (0..layout.layers)
        .map(|k| layout.surface(&fill[k], k.checked_add(1), &inside))
        .collect();
    let bottoms: Vec<Vec<bool>> = (0..layout.layers)
        .map(|k| layout.surface(&fill[k], k.checked_sub(1), &inside))
        .collect();
    let mut solid = Sum::default();
    let mut sparse = Sum::default();
    for k in 0..layout.layers {
        let class = layout.classify(k, &inside, &near, &tops, &bottoms);
        let z = layout.slice_height(k);
        let cell_volume = layout.cell * layout.cell * layout.thickness(k);
        for (index, kind) in class.iter().enumerate() {
            let point = layout.point(index, z);
            match kind {
                Cell::Solid => solid.add(cell_volume, &point),
                Cell::Sparse => sparse.add(cell_volume, &point),
                Cell::Outside => {}
            }
        }
    }
    let fallback = layout.centre();
    let back = |region: Region| Region {
        centroid: to_print.inverse() * region.centroid,
        ..region
    };
    PrintVolumes {
        solid: back(solid.region(fallback)),
        sparse: back(sparse.region(fallback)),
    }
}

/// What a raster cell of one layer holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Cell {
    Outside,
    Solid,
    Sparse,
}

/// Entries of a print rotation this close to 0 or ±1 are taken as exactly that.
const AXIS_SNAP: f64 = 1e-12;

/// `rotation` with every entry within [`AXIS_SNAP`] of 0, 1 or −1 made exact, so a quarter turn
/// computed in floating point (cos 90° = 6e-17) maps a face lying on a layer boundary exactly
/// there: a part is sliced the same whether its orientation was declared or chosen.
fn exact_axes(rotation: &Rotation3<f64>) -> Rotation3<f64> {
    let matrix = rotation.matrix().map(|entry| {
        let nearest = entry.round();
        if (entry - nearest).abs() <= AXIS_SNAP {
            nearest + 0.0
        } else {
            entry
        }
    });
    Rotation3::from_matrix_unchecked(matrix)
}

/// The print frame's axes: up (the build direction), and the raster's columns and rows.
const UP: usize = 2;
const U: usize = 0;
const V: usize = 1;

/// The layers and the raster of one mesh, print frame.
struct Layout {
    slicing: Slicing,
    /// The mesh's lowest point along z.
    bottom: f64,
    layers: usize,
    /// Raster origin (the corner of cell 0) and cell size.
    origin: (f64, f64),
    cell: f64,
    columns: usize,
    rows: usize,
}

/// A slice segment in raster coordinates (u, v).
type Segment = [(f64, f64); 2];

impl Layout {
    fn new(mesh: &TriMesh, slicing: &Slicing) -> Option<Layout> {
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
    fn slice_height(&self, k: usize) -> f64 {
        let (h, h0) = (self.slicing.layer_height, self.slicing.first_layer_height);
        if k == 0 {
            self.bottom + h0 / 2.0
        } else {
            self.bottom + h0 + (k as f64 - 0.5) * h
        }
    }

    /// Thickness of layer `k`.
    fn thickness(&self, k: usize) -> f64 {
        if k == 0 {
            self.slicing.first_layer_height
        } else {
            self.slicing.layer_height
        }
    }

    /// The print-frame point at cell `index`'s centre and height `z`.
    fn point(&self, index: usize, z: f64) -> Point3<f64> {
        let (i, j) = (index % self.columns, index / self.columns);
        Point3::new(
            self.origin.0 + (i as f64 + 0.5) * self.cell,
            self.origin.1 + (j as f64 + 0.5) * self.cell,
            z,
        )
    }

    /// The centre of the raster's box, for empty regions.
    fn centre(&self) -> Point3<f64> {
        Point3::new(
            self.origin.0 + self.columns as f64 * self.cell / 2.0,
            self.origin.1 + self.rows as f64 * self.cell / 2.0,
            self.slice_height(0),
        )
    }

    /// Each layer's slice of `mesh` as segments (u, v), triangles in order.
    fn slice(&self, mesh: &TriMesh) -> Vec<Vec<Segment>> {
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
    fn first_layer_above(&self, z: f64) -> usize {
        let (h, h0) = (self.slicing.layer_height, self.slicing.first_layer_height);
        if z - self.bottom <= h0 / 2.0 {
            return 0;
        }
        (((z - self.bottom - h0) / h + 0.5).ceil().max(1.0) as usize).min(self.layers)
    }

    /// The segment where the plane at height `z` cuts a triangle: points at or above `z`
    /// count as above, so a plane through a vertex cuts consistently across neighbours.
    fn cut(&self, corners: &[Vector3<f64>; 3], z: f64) -> Option<Segment> {
        let up = UP;
        let mut points = Vec::with_capacity(2);
        for e in 0..3 {
            let (p, q) = (corners[e], corners[(e + 1) % 3]);
            if (p[up] >= z) != (q[up] >= z) {
                let t = (z - p[up]) / (q[up] - p[up]);
                let x = p + (q - p) * t;
                points.push((x[U], x[V]));
            }
        }
        (points.len() == 2).then(|| [points[0], points[1]])
    }

    /// Row `j`'s cell centre, along v.
    fn row_centre(&self, j: usize) -> f64 {
        self.origin.1 + (j as f64 + 0.5) * self.cell
    }

    /// The cells whose centres lie inside the slice (even-odd rule on each row).
    fn inside(&self, segments: &[Segment]) -> Vec<bool> {
        let mut crossings: Vec<Vec<f64>> = vec![Vec::new(); self.rows];
        for &[(u0, v0), (u1, v1)] in segments {
            let (low, high) = (v0.min(v1), v0.max(v1));
            let first = ((low - self.origin.1) / self.cell - 0.5).ceil().max(0.0) as usize;
            for (j, row) in crossings.iter_mut().enumerate().skip(first) {
                let v = self.row_centre(j);
                if v > high {
                    break;
                }
                if (v0 >= v) != (v1 >= v) {
                    row.push(u0 + (v - v0) * (u1 - u0) / (v1 - v0));
                }
            }
        }
        let mut inside = vec![false; self.columns * self.rows];
        for (j, row) in crossings.iter_mut().enumerate() {
            row.sort_by(f64::total_cmp);
            for pair in row.chunks_exact(2) {
                let start = ((pair[0] - self.origin.0) / self.cell - 0.5)
                    .ceil()
                    .max(0.0);
                let end = ((pair[1] - self.origin.0) / self.cell - 0.5).floor();
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
    fn near_outline(&self, segments: &[Segment]) -> Vec<bool> {
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
        for &[(u0, v0), (u1, v1)] in segments {
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

    /// The fill cells of a layer (`fill`) under which (or over which) layer `next` is outside,
    /// grown by the surface margin within `fill`: the slicer's top (or bottom) surface of the
    /// layer with the ring it adds around it.
    fn surface(&self, fill: &[bool], next: Option<usize>, inside: &[Vec<bool>]) -> Vec<bool> {
        let exposed: Vec<bool> = fill
            .iter()
            .enumerate()
            .map(|(index, &f)| {
                f && !next
                    .and_then(|l| inside.get(l))
                    .is_some_and(|cells| cells[index])
            })
            .collect();
        let reach = self.slicing.surface_margin / self.cell;
        if reach <= 0.0 || !exposed.iter().any(|&e| e) {
            return exposed;
        }
        let distance = squared_distance(&exposed, self.columns, self.rows);
        distance
            .iter()
            .zip(fill)
            .map(|(d, &f)| f && *d <= reach * reach)
            .collect()
    }

    /// Layer `k`'s cells: outside, solid or sparse.
    fn classify(
        &self,
        k: usize,
        inside: &[Vec<bool>],
        near: &[Vec<bool>],
        tops: &[Vec<bool>],
        bottoms: &[Vec<bool>],
    ) -> Vec<Cell> {
        let here = &inside[k];
        let covered = |layer: Option<usize>, index: usize| {
            layer
                .and_then(|l| inside.get(l))
                .is_some_and(|cells| cells[index])
        };
        let (top, bottom) = (self.slicing.top_layers, self.slicing.bottom_layers);
        let mut class: Vec<Cell> = (0..here.len())
            .map(|index| {
                if !here[index] {
                    return Cell::Outside;
                }
                let shell = near[k][index]
                    || (1..=top).any(|j| !covered(k.checked_add(j), index))
                    || (1..=bottom).any(|j| !covered(k.checked_sub(j), index))
                    || (0..top).any(|j| tops.get(k + j).is_some_and(|s| s[index]))
                    || (0..bottom).any(|j| k.checked_sub(j).is_some_and(|l| bottoms[l][index]));
                if shell {
                    Cell::Solid
                } else {
                    Cell::Sparse
                }
            })
            .collect();
        self.fill_small_regions(&mut class);
        class
    }

    /// Sparse regions (4-connected) smaller than the minimum area become solid.
    fn fill_small_regions(&self, class: &mut [Cell]) {
        let limit = self.slicing.min_sparse_area;
        if limit <= 0.0 {
            return;
        }
        let cell_area = self.cell * self.cell;
        let mut seen = vec![false; class.len()];
        let mut stack = Vec::new();
        let mut region = Vec::new();
        for start in 0..class.len() {
            if seen[start] || class[start] != Cell::Sparse {
                continue;
            }
            seen[start] = true;
            stack.push(start);
            region.clear();
            while let Some(index) = stack.pop() {
                region.push(index);
                let (i, j) = (index % self.columns, index / self.columns);
                let neighbours = [
                    (i > 0).then(|| index - 1),
                    (i + 1 < self.columns).then(|| index + 1),
                    (j > 0).then(|| index - self.columns),
                    (j + 1 < self.rows).then(|| index + self.columns),
                ];
                for next in neighbours.into_iter().flatten() {
                    if !seen[next] && class[next] == Cell::Sparse {
                        seen[next] = true;
                        stack.push(next);
                    }
                }
            }
            if (region.len() as f64) * cell_area < limit {
                for &index in &region {
                    class[index] = Cell::Solid;
                }
            }
        }
    }
}

/// Squared distance (in cells) from every cell centre to the nearest marked cell centre, exact
/// (Felzenszwalb and Huttenlocher's two passes of lower envelopes of parabolas); `INFINITY`
/// without marked cells.
fn squared_distance(marked: &[bool], columns: usize, rows: usize) -> Vec<f64> {
    let mut grid: Vec<f64> = marked
        .iter()
        .map(|&m| if m { 0.0 } else { f64::INFINITY })
        .collect();
    let mut line = Vec::new();
    for i in 0..columns {
        line.clear();
        line.extend((0..rows).map(|j| grid[j * columns + i]));
        let out = envelope(&line);
        for (j, d) in out.into_iter().enumerate() {
            grid[j * columns + i] = d;
        }
    }
    for j in 0..rows {
        let row = &mut grid[j * columns..(j + 1) * columns];
        let out = envelope(row);
        row.copy_from_slice(&out);
    }
    grid
}

/// One pass of [`squared_distance`]: `min_q f(q) + (p − q)²` for every `p`.
fn envelope(f: &[f64]) -> Vec<f64> {
    let n = f.len();
    let mut out = vec![f64::INFINITY; n];
    let sites: Vec<usize> = (0..n).filter(|&q| f[q].is_finite()).collect();
    if sites.is_empty() {
        return out;
    }
    // Parabola apexes `v` and the boundaries `z` between them.
    let mut v: Vec<usize> = Vec::with_capacity(sites.len());
    let mut z: Vec<f64> = Vec::with_capacity(sites.len() + 1);
    let meet = |a: usize, b: usize| {
        ((f[b] + (b * b) as f64) - (f[a] + (a * a) as f64)) / (2.0 * (b as f64 - a as f64))
    };
    for &q in &sites {
        while let Some(&last) = v.last() {
            let s = meet(last, q);
            if v.len() > 1 && s <= z[z.len() - 1] {
                v.pop();
                z.pop();
            } else {
                z.push(s);
                break;
            }
        }
        v.push(q);
    }
    // z[i] is the boundary between v[i] and v[i + 1].
    let mut k = 0;
    for (p, value) in out.iter_mut().enumerate() {
        while k + 1 < v.len() && z[k] < p as f64 {
            k += 1;
        }
        let d = p as f64 - v[k] as f64;
        *value = d * d + f[v[k]];
    }
    out
}

/// A running sum of volumes at points.
#[derive(Debug, Default)]
struct Sum {
    volume: f64,
    moment: Vector3<f64>,
}

impl Sum {
    fn add(&mut self, volume: f64, at: &Point3<f64>) {
        self.volume += volume;
        self.moment += at.coords * volume;
    }

    fn region(&self, fallback: Point3<f64>) -> Region {
        let centroid = if self.volume > 0.0 {
            Point3::from(self.moment / self.volume)
        } else {
            fallback
        };
        Region {
            volume: self.volume,
            centroid,
        }
    }
}
