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

mod distance;
mod layout;
mod voids;

use super::parallel::map_each;
use layout::Layout;
pub use voids::Void;

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

/// The solid and sparse volumes of `mesh` printed with `slicing` (see the module
/// documentation). A mesh without extent or with a non-finite coordinate, or settings without a
/// positive layer height, gives empty regions at the origin.
pub fn print_volumes(mesh: &TriMesh, slicing: &Slicing) -> PrintVolumes {
    print_volumes_with_voids(mesh, slicing, &[])
}

/// The solid and sparse volumes of `mesh` with `voids` (rest frame) cut from it, printed with
/// `slicing`: as [`print_volumes`], with each void's cells taken out of every layer it crosses,
/// so the slicer's perimeters around each hole, the solid layers under its floor and over its
/// ceiling, and the small regions it leaves are classified as for the mesh's own outline.
pub fn print_volumes_with_voids(mesh: &TriMesh, slicing: &Slicing, voids: &[Void]) -> PrintVolumes {
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
    let voids: Vec<Void> = voids
        .iter()
        .map(|void| Void {
            from: to_print * void.from,
            to: to_print * void.to,
            ..*void
        })
        .collect();
    // Every layer's raster is independent of the others' until the surfaces and the classes,
    // which read their neighbours' finished rasters: each step runs over the layers on every
    // core, and the sums below run in layer order, so the result does not depend on the cores.
    let layers = layout.layers;
    let segments = layout.slice(mesh);
    let mut inside: Vec<Vec<bool>> = map_each(layers, |k| layout.inside(&segments[k]));
    let mut near: Vec<Vec<bool>> = map_each(layers, |k| layout.near_outline(&segments[k]));
    if !voids.is_empty() {
        let holes: Vec<(Vec<bool>, Vec<bool>)> = map_each(layers, |k| {
            let mut hole = layout.in_voids(k, &voids);
            for (h, i) in hole.iter_mut().zip(&inside[k]) {
                *h &= *i;
            }
            let around = layout.near_hole(&hole);
            (hole, around)
        });
        for ((inside, near), (hole, around)) in inside.iter_mut().zip(&mut near).zip(&holes) {
            for ((i, n), (h, a)) in inside
                .iter_mut()
                .zip(near.iter_mut())
                .zip(hole.iter().zip(around))
            {
                *i &= !h;
                *n |= *a;
            }
        }
    }
    let fill: Vec<Vec<bool>> = inside
        .iter()
        .zip(&near)
        .map(|(inside, near)| inside.iter().zip(near).map(|(i, n)| *i && !n).collect())
        .collect();
    let tops: Vec<Vec<bool>> = map_each(layers, |k| {
        layout.surface(&fill[k], k.checked_add(1), &inside)
    });
    let bottoms: Vec<Vec<bool>> = map_each(layers, |k| {
        layout.surface(&fill[k], k.checked_sub(1), &inside)
    });
    let classes: Vec<Vec<Cell>> = map_each(layers, |k| {
        layout.classify(k, &inside, &near, &tops, &bottoms)
    });
    let mut solid = Sum::default();
    let mut sparse = Sum::default();
    for (k, class) in classes.iter().enumerate() {
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
