//! The solid and sparse material of a raster, summed exactly: counts of cells and sums of their
//! indices, in integers. A cut adds and takes away only the cells it changes, and the volumes
//! are the same bits whatever order the cells were added in.

use std::ops::AddAssign;

use nalgebra::{Point3, Vector3};

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

    /// The counted items' summed thickness (`Σ h`) and its first moment (`Σ h × position`),
    /// print frame: `offset` is where an item sits from its index along a raster axis, in cells
    /// (½ for a cell's centre, 0 for the corner between cells).
    fn moments(&self, layout: &Layout, offset: f64) -> Moments {
        let (h0, h) = (
            layout.slicing.first_layer_height,
            layout.slicing.layer_height,
        );
        let (first, upper) = (&self.first, &self.upper);
        let (n0, n) = (first.count as f64, upper.count as f64);
        let weight = h0 * n0 + h * n;
        // Σ h × index along a raster axis.
        let along = |first_sum: i64, upper_sum: i64| {
            h0 * (first_sum as f64 + offset * n0) + h * (upper_sum as f64 + offset * n)
        };
        // Layer k ≥ 1 is sliced at bottom + h0 + (k − ½)h, layer 0 at bottom + h0/2.
        let upper_heights = n * (h0 - 0.5 * h) + h * upper.k as f64;
        Moments {
            weight,
            moment: Vector3::new(
                layout.origin.0 * weight + layout.cell * along(first.i, upper.i),
                layout.origin.1 * weight + layout.cell * along(first.j, upper.j),
                layout.bottom * weight + h0 * n0 * 0.5 * h0 + h * upper_heights,
            ),
        }
    }
}

/// A sum of weights and of weights times positions.
#[derive(Debug, Clone, Copy)]
struct Moments {
    weight: f64,
    moment: Vector3<f64>,
}

impl Moments {
    /// These moments scaled by `factor`.
    fn scaled(self, factor: f64) -> Moments {
        Moments {
            weight: self.weight * factor,
            moment: self.moment * factor,
        }
    }

    /// The sum of these moments and `other`.
    fn plus(self, other: Moments) -> Moments {
        Moments {
            weight: self.weight + other.weight,
            moment: self.moment + other.moment,
        }
    }

    /// The weight as a volume, and its centroid; `fallback` as the centroid of none.
    fn region(self, fallback: Point3<f64>) -> Region {
        if self.weight.is_nan() || self.weight <= 0.0 {
            return Region {
                volume: self.weight.max(0.0),
                centroid: fallback,
            };
        }
        Region {
            volume: self.weight,
            centroid: Point3::from(self.moment / self.weight),
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

/// The sparse regions' outlines in some layers, traced by marching squares through the cell
/// centres: each block of 2×2 cells (indexed by its upper right cell's column and row, from 0
/// to the raster's size inclusive, cells past the raster not sparse) holds no segment when its
/// cells are all sparse or none is, a straight one a cell long when two side by side are, and
/// one diagonal one (√½ cell) per corner cut off otherwise: exact along the raster's axes and
/// diagonals (but for cut corners), up to 8 % long between, about 5 % long round a curve.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct Outline {
    straight: Tally,
    diagonal: Tally,
}

impl Outline {
    /// Counts the change in block (`i`, `j`) of layer `k` when its sparse corners
    /// ([`Corners`]) go from `before` to `after`.
    fn change(&mut self, before: Corners, after: Corners, i: usize, j: usize, k: usize) {
        let (straight_before, diagonal_before) = segments(before);
        let (straight, diagonal) = segments(after);
        if straight != straight_before {
            self.straight.add(straight - straight_before, i, j, k);
        }
        if diagonal != diagonal_before {
            self.diagonal.add(diagonal - diagonal_before, i, j, k);
        }
    }

    /// Σ thickness × length of the outlines and its first moment, print frame.
    fn moments(&self, layout: &Layout) -> Moments {
        let straight = self.straight.moments(layout, 0.0);
        let diagonal = self.diagonal.moments(layout, 0.0);
        straight
            .plus(diagonal.scaled(std::f64::consts::FRAC_1_SQRT_2))
            .scaled(layout.cell)
    }
}

/// The corners of an outline block that hold a sparse cell (or some other set), as bits:
/// lower left 1, lower right 2, upper left 4, upper right 8 (cells `i − 1` and `i` by `j − 1`
/// and `j` of block (`i`, `j`)).
pub(super) type Corners = u8;

/// The corners of block (`i`, `j`) whose cells `holds` says are in a set, the cells before or
/// past a raster `columns` × `rows` in none.
pub(super) fn corners(
    (i, j): (usize, usize),
    (columns, rows): (usize, usize),
    holds: impl Fn(usize, usize) -> bool,
) -> Corners {
    let (left, below) = (i.checked_sub(1), j.checked_sub(1));
    let cells = [
        (left, below),
        (Some(i), below),
        (left, Some(j)),
        (Some(i), Some(j)),
    ];
    cells
        .into_iter()
        .enumerate()
        .filter(|(_, (i, j))| match (*i, *j) {
            (Some(i), Some(j)) => i < columns && j < rows && holds(i, j),
            _ => false,
        })
        .fold(0, |corners, (bit, _)| corners | 1 << bit)
}

/// The straight and the diagonal segments of a block of 2×2 cells whose sparse corners are
/// `sparse`.
fn segments(sparse: Corners) -> (i64, i64) {
    match sparse.count_ones() {
        0 | 4 => (0, 0),
        1 | 3 => (0, 1),
        // Two opposite corners: a saddle, two corners cut off.
        _ if sparse == 0b1001 || sparse == 0b0110 => (0, 2),
        _ => (1, 0),
    }
}

/// Length of the joins PrusaSlicer lays between neighbouring ends of the sparse infill's lines
/// along a sparse region's outline, per unit length of outline, whatever the density
/// (`connect_infill`, measured on its 2.5 G-code: squares, circles and rings).
const JOINS_PER_OUTLINE: f64 = 0.19;

/// Length of the anchors at the line ends left unjoined, per unit length of outline and unit of
/// infill fraction: 0.19 × the anchor (6 line spacings) over the spacing of one of the stars'
/// three families of lines (3 spacings over the fraction), as measured with `JOINS_PER_OUTLINE`.
const ANCHORS_PER_OUTLINE: f64 = 0.19 * 6.0 / 3.0;

/// Line length the infill fraction times the fill area over-counts per unit length of outline
/// and unit of fraction: the lines end half a spacing inside the fill region's outline.
const LINE_ENDS_PER_OUTLINE: f64 = 0.5;

/// The solid and the sparse cells of some layers, and the sparse regions' outlines.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct Totals {
    solid: Tally,
    sparse: Tally,
    outline: Outline,
}

impl Totals {
    /// Counts cell (`i`, `j`) of layer `k` as `class` (`sign` 1) or no longer as it (−1).
    pub(super) fn add(&mut self, sign: i64, class: Cell, i: usize, j: usize, k: usize) {
        match class {
            Cell::Solid | Cell::Shell | Cell::Small => self.solid.add(sign, i, j, k),
            Cell::Sparse => self.sparse.add(sign, i, j, k),
            Cell::Outside => {}
        }
    }

    /// Counts the change in block (`i`, `j`) of layer `k`'s sparse outline ([`Outline`]) when
    /// its sparse corners ([`Corners`]) go from `before` to `after`.
    pub(super) fn change_block(
        &mut self,
        before: Corners,
        after: Corners,
        (i, j, k): (usize, usize, usize),
    ) {
        self.outline.change(before, after, i, j, k);
    }

    /// Counts every cell of layer `k`, of `class` (row by row over the raster), and every
    /// block of its sparse outline.
    pub(super) fn add_layer(&mut self, layout: &Layout, k: usize, class: &[Cell]) {
        for (j, row) in class.chunks(layout.columns).enumerate() {
            for (i, &cell) in row.iter().enumerate() {
                self.add(1, cell, i, j, k);
            }
        }
        let of = |i: usize, j: usize| class[j * layout.columns + i] == Cell::Sparse;
        let raster = (layout.columns, layout.rows);
        for j in 0..=layout.rows {
            for i in 0..=layout.columns {
                self.outline.change(0, corners((i, j), raster, of), i, j, k);
            }
        }
    }

    /// The solid and the sparse region, print frame. The material the sparse infill lays
    /// along its regions' outlines is counted in them, each piece a line of the infill's
    /// spacing by the layer's height: the joins in the solid region, the anchors less the
    /// lines' ends in the sparse one (the infill fraction scales them).
    pub(super) fn regions(&self, layout: &Layout) -> (Region, Region) {
        let fallback = layout.centre();
        let area = layout.cell * layout.cell;
        let outline = self
            .outline
            .moments(layout)
            .scaled(layout.slicing.infill_spacing);
        let solid =
            (self.solid.moments(layout, 0.5).scaled(area)).plus(outline.scaled(JOINS_PER_OUTLINE));
        let sparse = (self.sparse.moments(layout, 0.5).scaled(area))
            .plus(outline.scaled(ANCHORS_PER_OUTLINE - LINE_ENDS_PER_OUTLINE));
        (solid.region(fallback), sparse.region(fallback))
    }
}

impl AddAssign for Totals {
    /// Counts the cells of `other` too (a change: some counted no longer).
    fn add_assign(&mut self, other: Totals) {
        self.solid += other.solid;
        self.sparse += other.sparse;
        self.outline.straight += other.outline.straight;
        self.outline.diagonal += other.outline.diagonal;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::print::Slicing;
    use nalgebra::Rotation3;

    /// One layer, `size` cells square of 0.1 mm, with infill lines 0.4 mm apart.
    fn layout(size: usize) -> Layout {
        Layout {
            slicing: Slicing {
                to_print: Rotation3::identity(),
                perimeter_thickness: 0.0,
                layer_height: 0.2,
                first_layer_height: 0.2,
                top_layers: 0,
                bottom_layers: 0,
                min_sparse_area: 0.0,
                surface_margin: 0.0,
                shell_widening: 0.0,
                fill_boundary: 0.0,
                infill_spacing: 0.4,
            },
            bottom: 0.0,
            layers: 1,
            origin: (0.0, 0.0),
            cell: 0.1,
            columns: size,
            rows: size,
        }
    }

    /// The length of the sparse outline of the cells whose centre (mm) `inside` holds, and the
    /// centroid of the material along it.
    fn outline(size: usize, inside: impl Fn(f64, f64) -> bool) -> (f64, Point3<f64>) {
        let layout = layout(size);
        let class: Vec<Cell> = (0..size * size)
            .map(|index| {
                let (i, j) = (index % size, index / size);
                let centre = |n: usize| (n as f64 + 0.5) * layout.cell;
                if inside(centre(i), centre(j)) {
                    Cell::Sparse
                } else {
                    Cell::Outside
                }
            })
            .collect();
        let mut totals = Totals::default();
        totals.add_layer(&layout, 0, &class);
        // Only the joins are solid: their volume is the outline's length times theirs.
        let (solid, _) = totals.regions(&layout);
        let per_length = JOINS_PER_OUTLINE * 0.4 * 0.2;
        (solid.volume / per_length, solid.centroid)
    }

    #[test]
    fn outlines_are_measured_whatever_their_direction() {
        // The segments through the cells' mid-sides follow a line along an axis or a diagonal
        // exactly (its corners cut by a diagonal) and are up to 8 % longer between (at 26.6°,
        // one cell up for two across: 1 + √2 for √5).
        let (length, _) = outline(100, |x, y| {
            (2.0..8.0).contains(&x) && (2.0..8.0).contains(&y)
        });
        let corners = 4.0 * 0.1 * (1.0 - std::f64::consts::FRAC_1_SQRT_2);
        assert!((length - (24.0 - corners)).abs() < 1e-9, "square: {length}");
        for (angle, within) in [(30.0, 0.08), (45.0, 0.01)] {
            let angle = f64::to_radians(angle);
            let (length, _) = outline(100, |x, y| {
                let (u, v) = (x - 5.0, y - 5.0);
                let (c, s) = (angle.cos(), angle.sin());
                (c * u + s * v).abs() < 3.0 && (-s * u + c * v).abs() < 3.0
            });
            let error = length / 24.0 - 1.0;
            assert!(
                (0.0..within).contains(&error.abs()),
                "turned by {angle}: {length}"
            );
        }
        // A disc of radius 4 mm about (5, 5) mm, 2π × 4 mm round: every direction, so the
        // segments' mean excess, with the material centred on the disc's centre.
        let (length, centre) = outline(100, |x, y| (x - 5.0).hypot(y - 5.0) < 4.0);
        let circle = std::f64::consts::TAU * 4.0;
        assert!(
            (0.03..0.08).contains(&(length / circle - 1.0)),
            "disc: {length}"
        );
        assert!(
            (centre - Point3::new(5.0, 5.0, 0.1)).norm() < 1e-9,
            "{centre}"
        );
    }
}
