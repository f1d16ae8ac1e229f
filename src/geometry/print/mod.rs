//! Where an FDM slicer puts solid material and where sparse infill in a closed mesh.
//!
//! The mesh is turned into its print frame (+z up, away from the bed) and cut into layers along
//! z, as a slicer does: the first layer
//! `first_layer_height` thick, the others `layer_height`, each sliced at its mid-height. Every
//! slice is rasterised on a square grid (a cell is inside when its centre is, by a positive
//! winding number of the slice's segments: the even-odd rule for a surface that does not cross
//! itself, the union of overlapping shells) and each inside cell is classified:
//! - **perimeter**: within `perimeter_thickness` (horizontally) of the slice outline;
//! - **top or bottom**: the same column is outside the mesh in one of the `top_layers` layers
//!   above, or the `bottom_layers` below (the solid layers under every top surface and over
//!   every bottom surface, sloping ones included); or within `surface_margin` of a top surface
//!   (the part of a layer's fill region, inside the perimeters, that the layer above does not
//!   cover, however narrow: found from the exact depths) of this layer or one of the
//!   `top_layers − 1` above, or of a bottom surface of this layer or one of the
//!   `bottom_layers − 1` below (PrusaSlicer grows every top and bottom surface by a margin
//!   before it adds the solid layers);
//!   or within `shell_widening` of a strip narrower than twice that, which the surfaces of
//!   one of the `top_layers − 1` layers above (or the `bottom_layers − 1` below) add to this
//!   layer's fill, their slices' slivers and their margins alike, less this layer's own
//!   surfaces (PrusaSlicer widens such strips "so that they do not collapse");
//! - **small region**: what is left forms a region (4-connected cells) smaller than
//!   `min_sparse_area`, which the slicer fills solid;
//! - **sparse**: the rest, printed at the infill fraction.
//!
//! The first three are [`PrintVolumes::solid`]; their centroids are turned back into the rest
//! frame. The result does not depend on the design and is computed once per component and print
//! orientation.

use nalgebra::{Point3, Rotation3};

use super::mass::MassProperties;
use super::mesh::TriMesh;

mod cells;
mod classes;
mod depth;
mod distance;
mod layout;
mod narrow;
mod outline;
mod overlap;
mod sides;
mod tally;
mod voids;
mod window;

use crate::parallel::map_each;
use cells::{CellBox, Overlay, Planes};
use classes::{Cell, Classifier, Depths};
use layout::Layout;
pub use overlap::{overlap, Overlap};
use tally::Totals;
pub use voids::Void;

/// Which rules [`print_volumes`] follows: raised whenever what it gives for some mesh and
/// settings changes, so that what was measured against an earlier model (a calibration) is
/// known not to hold.
pub const MODEL_REVISION: u32 = 3;

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
    /// How far a solid strip that a top or bottom surface adds to a layer next to it is widened
    /// within that layer's fill, where it is narrower than twice this (PrusaSlicer: 3 × the
    /// solid infill's extrusion width).
    pub shell_widening: f64,
    /// How far from the outline the slicer's fill region begins (the perimeters less the
    /// infill's overlap with them).
    pub fill_boundary: f64,
    /// Spacing of the sparse infill's lines at full density: the width of the material one
    /// line lays per unit of its length and of layer height.
    pub infill_spacing: f64,
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
    PrintRaster::new(mesh, slicing).volumes()
}

/// The solid and sparse volumes of `mesh` with `voids` (rest frame) cut from it, printed with
/// `slicing`: as [`print_volumes`], with each void's cells taken out of every layer it crosses,
/// so the slicer's perimeters around each hole, the solid layers under its floor and over its
/// ceiling, and the small regions it leaves are classified as for the mesh's own outline.
pub fn print_volumes_with_voids(mesh: &TriMesh, slicing: &Slicing, voids: &[Void]) -> PrintVolumes {
    PrintRaster::new(mesh, slicing).volumes_with_voids(voids)
}

/// A mesh sliced once, for cutting any set of voids from it: each layer's inside cells, its
/// perimeters, and its cells' classes before a void is cut. Cutting voids re-classifies only
/// the cells they can change: in the layers they cross and the solid layers above and below
/// those, within the perimeters and the surface margin of the voids' cross-sections in the
/// layers each one reads, and the regions the small-region rule joins to those (`window`).
/// The material is summed exactly, as counts of cells and sums of their indices (`tally`): a
/// cut takes the cells it changes away from the bare sums and adds them back as they now are,
/// and gives the same bits as slicing the whole mesh with the voids again.
#[derive(Clone)]
pub struct PrintRaster {
    to_print: Rotation3<f64>,
    /// `None` for a mesh that cannot be sliced (see [`print_volumes`]).
    layers: Option<Layers>,
}

impl std::fmt::Debug for PrintRaster {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut out = f.debug_struct("PrintRaster");
        out.field("to_print", &self.to_print);
        if let Some(layers) = &self.layers {
            let layout = &layers.layout;
            out.field("layers", &layout.layers)
                .field("cell", &layout.cell)
                .field("columns", &layout.columns)
                .field("rows", &layout.rows);
        }
        out.finish()
    }
}

/// The sliced layers of a [`PrintRaster`], before a void is cut.
#[derive(Clone)]
struct Layers {
    layout: Layout,
    /// Per layer, the cells inside the mesh.
    inside: Vec<Vec<bool>>,
    /// Per layer, the cells within the perimeter thickness of the outline.
    near: Vec<Vec<bool>>,
    /// Per layer, each cell's distance to the outline ([`Layout::depth`]).
    depth: Vec<Vec<f32>>,
    /// Per layer, each cell's class before the small-region rule.
    unsettled: Vec<Vec<Cell>>,
    /// Per layer, each cell's class.
    classes: Vec<Vec<Cell>>,
    /// The solid and sparse cells of every layer.
    totals: Totals,
}

impl PrintRaster {
    /// Slices `mesh` with `slicing`.
    pub fn new(mesh: &TriMesh, slicing: &Slicing) -> PrintRaster {
        let to_print = exact_axes(&slicing.to_print);
        let printed = TriMesh {
            positions: mesh.positions.iter().map(|p| to_print * p).collect(),
            triangles: mesh.triangles.clone(),
        };
        let layers = Layout::new(&printed, slicing).map(|layout| {
            // Every layer's raster is independent of the others' until the surfaces and the
            // classes, which read their neighbours' finished rasters: each step runs over the
            // layers on every core.
            let segments = layout.slice(&printed);
            let mut inside = Vec::new();
            let mut near = Vec::new();
            let mut depth = Vec::new();
            for (a, b, c) in map_each(layout.layers, |k| layout.rasterize(&segments[k])) {
                inside.push(a);
                near.push(b);
                depth.push(c);
            }
            Layers::classified(layout, inside, near, depth)
        });
        PrintRaster { to_print, layers }
    }

    /// The mesh's solid and sparse volumes before a void is cut.
    pub fn volumes(&self) -> PrintVolumes {
        match &self.layers {
            Some(layers) => self.volumes_of(&layers.layout, &layers.totals),
            None => empty_volumes(),
        }
    }

    /// The mesh's solid and sparse volumes with `voids` (rest frame) cut from it
    /// ([`print_volumes_with_voids`]).
    pub fn volumes_with_voids(&self, voids: &[Void]) -> PrintVolumes {
        let Some(layers) = &self.layers else {
            return empty_volumes();
        };
        let voids = self.in_print_frame(voids);
        self.volumes_of(&layers.layout, &layers.cut(&voids))
    }

    /// `voids` (rest frame) turned into the print frame.
    fn in_print_frame(&self, voids: &[Void]) -> Vec<Void> {
        voids
            .iter()
            .map(|void| Void {
                from: self.to_print * void.from,
                to: self.to_print * void.to,
                ..*void
            })
            .collect()
    }

    /// The volumes of `totals`, turned back to the rest frame.
    fn volumes_of(&self, layout: &Layout, totals: &Totals) -> PrintVolumes {
        let back = |region: Region| Region {
            centroid: self.to_print.inverse() * region.centroid,
            ..region
        };
        let (solid, sparse) = totals.regions(layout);
        PrintVolumes {
            solid: back(solid),
            sparse: back(sparse),
        }
    }
}

impl Layers {
    /// The layers of `layout` with these `inside` cells and perimeters (`near`), classified.
    fn classified(
        layout: Layout,
        inside: Vec<Vec<bool>>,
        near: Vec<Vec<bool>>,
        depth: Vec<Vec<f32>>,
    ) -> Layers {
        let whole = CellBox::whole(&layout);
        let none = Planes {
            first: 0,
            area: whole.clone(),
            layers: Vec::new(),
        };
        let over = |bare| Overlay {
            columns: layout.columns,
            bare,
            planes: &none,
        };
        let (unsettled, classes): (Vec<Vec<Cell>>, Vec<Vec<Cell>>) = {
            let all = 0..=layout.layers - 1;
            let depths = Depths {
                bare: &depth,
                first: 0,
                held: &[],
            };
            let classifier = Classifier::new(&layout, over(&inside), over(&near), all, depths);
            map_each(layout.layers, |k| {
                let mut unsettled = vec![Cell::Outside; whole.len()];
                classifier.layer(k, &whole, &mut unsettled);
                let mut class = unsettled.clone();
                classes::fill_small_regions(&layout, &mut class);
                (unsettled, class)
            })
            .into_iter()
            .unzip()
        };
        // Integer tallies: the layers are counted on every core and summed in any order.
        let mut totals = Totals::default();
        for layer in map_each(layout.layers, |k| {
            let mut layer = Totals::default();
            layer.add_layer(&layout, k, &classes[k]);
            layer
        }) {
            totals += layer;
        }
        Layers {
            layout,
            inside,
            near,
            depth,
            unsettled,
            classes,
            totals,
        }
    }
}

/// Empty regions at the origin: what a mesh that cannot be sliced prints.
fn empty_volumes() -> PrintVolumes {
    let empty = Region {
        volume: 0.0,
        centroid: Point3::origin(),
    };
    PrintVolumes {
        solid: empty,
        sparse: empty,
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::box_at;

    /// A box with a narrower box standing on it: a step whose top surface rings the upper box.
    fn stepped() -> TriMesh {
        let mut mesh = box_at([0.0; 3], [20.0, 14.0, 8.0], 0);
        let upper = box_at([4.0, 3.0, 8.0], [16.0, 11.0, 14.0], 8);
        mesh.positions.extend(upper.positions);
        mesh.triangles.extend(upper.triangles);
        mesh
    }

    #[test]
    fn depths_are_the_distances_to_the_nearest_side() {
        // A twelve-pointed star, its points 18 mm out and its notches 7 mm, in a 40 mm box's
        // raster: every inside cell within the range measured against every side.
        let mesh = box_at([-20.0, -20.0, 0.0], [20.0, 20.0, 4.0], 0);
        let slicing = Slicing {
            to_print: Rotation3::identity(),
            perimeter_thickness: 1.2,
            layer_height: 0.3,
            first_layer_height: 0.3,
            top_layers: 3,
            bottom_layers: 3,
            min_sparse_area: 0.0,
            surface_margin: 0.0,
            shell_widening: 1.35,
            fill_boundary: 1.1,
            infill_spacing: 0.0,
        };
        let layout = Layout::new(&mesh, &slicing).unwrap();
        let corners: Vec<(f64, f64)> = (0..24)
            .map(|i| {
                let angle = std::f64::consts::TAU * i as f64 / 24.0 + 0.1;
                let radius = if i % 2 == 0 { 18.0 } else { 7.0 };
                (radius * angle.cos(), radius * angle.sin())
            })
            .collect();
        let sides: Vec<[(f64, f64); 2]> = (0..corners.len())
            .map(|i| [corners[i], corners[(i + 1) % corners.len()]])
            .collect();
        let area = cells::CellBox::whole(&layout);
        let centre = |c: usize| {
            let (i, j) = (c % layout.columns, c / layout.columns);
            (
                layout.origin.0 + (i as f64 + 0.5) * layout.cell,
                layout.origin.1 + (j as f64 + 0.5) * layout.cell,
            )
        };
        // Inside by the crossing count of a ray along +u.
        let inside: Vec<bool> = (0..area.len())
            .map(|c| {
                let (u, v) = centre(c);
                sides
                    .iter()
                    .filter(|[(u0, v0), (u1, v1)]| {
                        (v0 > &v) != (v1 > &v) && u < u0 + (v - v0) / (v1 - v0) * (u1 - u0)
                    })
                    .count()
                    % 2
                    == 1
            })
            .collect();
        let found = layout.distances(&area, &sides, &inside);
        let (mut measured, mut off, mut worst) = (0, 0, 0.0f64);
        for c in (0..area.len()).filter(|&c| inside[c]) {
            let (u, v) = centre(c);
            let exact = sides
                .iter()
                .map(|&[(u0, v0), (u1, v1)]| {
                    let (du, dv) = (u1 - u0, v1 - v0);
                    let t = (((u - u0) * du + (v - v0) * dv) / (du * du + dv * dv)).clamp(0.0, 1.0);
                    (u - u0 - t * du).hypot(v - v0 - t * dv)
                })
                .fold(f64::INFINITY, f64::min);
            if exact > depth::DEPTH_RANGE {
                continue;
            }
            measured += 1;
            let error = found[c].sqrt() - exact;
            assert!(
                error >= -1e-9,
                "closer than the nearest side at {:?}",
                centre(c)
            );
            if error > 1e-9 {
                off += 1;
                worst = worst.max(error);
            }
        }
        assert!(measured > 2000, "{measured}");
        eprintln!("{off} of {measured} cells off, worst by {worst}");
        assert!(off * 1000 <= measured, "{off} of {measured} cells off");
        assert!(worst < 0.05 * layout.cell, "{worst}");
    }

    #[test]
    fn overlapping_shells_slice_to_their_union_and_its_outline() {
        // Two 20 mm cubes overlapping by half, as two closed shells, and the 30 mm box they
        // make together: every layer has the same inside cells (the even-odd rule would empty
        // the overlap) and the same perimeters.
        let mut overlapping = box_at([0.0; 3], [20.0; 3], 0);
        let other = box_at([10.0, 0.0, 0.0], [30.0, 20.0, 20.0], 8);
        overlapping.positions.extend(other.positions);
        overlapping.triangles.extend(other.triangles);
        let union = box_at([0.0; 3], [30.0, 20.0, 20.0], 0);
        let slicing = Slicing {
            to_print: Rotation3::identity(),
            perimeter_thickness: 0.9,
            layer_height: 0.3,
            first_layer_height: 0.2,
            top_layers: 5,
            bottom_layers: 3,
            min_sparse_area: 8.0,
            surface_margin: 1.5,
            shell_widening: 1.35,
            fill_boundary: 0.85,
            infill_spacing: 0.4,
        };
        let layout = Layout::new(&union, &slicing).unwrap();
        assert_eq!(
            Layout::new(&overlapping, &slicing).unwrap().columns,
            layout.columns
        );
        let (split, whole) = (layout.slice(&overlapping), layout.slice(&union));
        for (k, (split, whole)) in split.iter().zip(&whole).enumerate() {
            let (inside, near, _) = layout.rasterize(split);
            let (whole_inside, whole_near, _) = layout.rasterize(whole);
            assert_eq!(inside, whole_inside, "layer {k}");
            // Perimeters only along the union's outline, not along the walls inside it.
            assert_eq!(near, whole_near, "layer {k}");
            assert!(inside.iter().filter(|&&c| c).count() > layout.columns * layout.rows / 2);
        }
        // A cavity (an inward shell inside the box) stays empty.
        let mut hollow = union.clone();
        let mut cavity = box_at([5.0, 5.0, 5.0], [25.0, 15.0, 15.0], 8);
        for t in &mut cavity.triangles {
            t.swap(1, 2);
        }
        hollow.positions.extend(cavity.positions);
        hollow.triangles.extend(cavity.triangles);
        let (middle, _, _) = layout.rasterize(&layout.slice(&hollow)[30]);
        let centre = (layout.rows / 2) * layout.columns + layout.columns / 2;
        assert!(!middle[centre] && middle[layout.columns * 2 + 2]);
    }

    fn void(from: [f64; 3], to: [f64; 3], radius: f64) -> Void {
        Void {
            from: Point3::from(from),
            to: Point3::from(to),
            radius,
        }
    }

    /// `voids` cut from every layer of `raster` and every cell classified again.
    fn everywhere(raster: &PrintRaster, voids: &[Void]) -> PrintVolumes {
        let layers = raster.layers.as_ref().expect("a sliced mesh");
        let layout = &layers.layout;
        let voids = raster.in_print_frame(voids);
        let whole = CellBox::whole(layout);
        let (inside, near, patches) = layers.cut_planes(&voids, 0..=layout.layers - 1, &whole);
        // Each layer's depths: the bare layer's with its patch laid on.
        let depth = patches
            .into_iter()
            .zip(&layers.depth)
            .map(|(patch, bare)| {
                let mut depth = bare.clone();
                if let Some(patch) = patch {
                    let width = patch.cells.width();
                    for (y, j) in patch.cells.j.clone().enumerate() {
                        let start = j * layout.columns + patch.cells.i.start;
                        depth[start..start + width]
                            .copy_from_slice(&patch.depth[y * width..(y + 1) * width]);
                    }
                }
                depth
            })
            .collect();
        let cut = Layers::classified(layout.clone(), inside.layers, near.layers, depth);
        raster.volumes_of(layout, &cut.totals)
    }

    #[test]
    fn re_classifying_the_cells_a_cut_reaches_gives_the_bits_of_re_classifying_them_all() {
        // A stepped part printed upright and tilted, with the small-region rule and the surface
        // margin on, and voids at pseudo-random places and sizes: near the floor and the
        // ceiling, across the step, close to the walls (small regions between hole and wall).
        let mut random = crate::random::SplitMix64::new(0x2545_f491_4f6c_dd1d);
        let mut next = move || random.unit();
        let mesh = stepped();
        for to_print in [
            Rotation3::identity(),
            Rotation3::from_euler_angles(0.3, -0.2, 0.1),
        ] {
            let slicing = Slicing {
                to_print,
                perimeter_thickness: 0.9,
                layer_height: 0.3,
                first_layer_height: 0.2,
                top_layers: 5,
                bottom_layers: 3,
                min_sparse_area: 8.0,
                surface_margin: 1.5,
                shell_widening: 1.35,
                fill_boundary: 0.85,
                infill_spacing: 0.4,
            };
            let raster = PrintRaster::new(&mesh, &slicing);
            let bare = raster.volumes();
            for case in 0..24 {
                let voids: Vec<Void> = (0..1 + case % 3)
                    .map(|_| {
                        let at = [4.0 + next() * 12.0, 3.0 + next() * 8.0, 1.0 + next() * 12.0];
                        let along = [next() * 6.0 - 3.0, next() * 6.0 - 3.0, next() * 2.0 - 1.0];
                        let to = [at[0] + along[0], at[1] + along[1], at[2] + along[2]];
                        void(at, to, 0.5 + next() * 2.5)
                    })
                    .collect();
                let windowed = raster.volumes_with_voids(&voids);
                assert_eq!(windowed, everywhere(&raster, &voids), "voids {voids:?}");
                assert_ne!(windowed, bare, "voids {voids:?}");
            }
            // No void: the bare volumes, to the bit, through either path.
            assert_eq!(raster.volumes_with_voids(&[]), bare);
            assert_eq!(everywhere(&raster, &[]), bare);
        }
    }
}
