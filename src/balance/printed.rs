//! Each component's material with a design's voids cut from it: what the report, the judge of
//! every design and `verify` weigh (`docs/physics.md`, "The mass of a print").
//!
//! Under the `fdm` model the component's mesh is sliced again with the design's capsules cut
//! from it ([`PrintRaster::volumes_with_voids`]), so the perimeters the slicer lays around each hole,
//! the solid layers under each floor and over each ceiling, and the narrow regions between a
//! void and the surface are classified as the slicer classifies them. Under `uniform` each void
//! is taken out of the sparse material in closed form. The calibration's correction is added to
//! the solid part in both. The optimizer's smooth objective keeps the closed-form capsule term
//! ([`capsule_shell`](super::capsule_shell)) and is corrected towards this material between
//! solves.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use nalgebra::Rotation3;

use super::mass::{capsule_volume, Weighted};
use super::{slicing, ComponentBody};
use crate::design::Design;
use crate::geometry::{
    ConvexHull, MassProperties, PrintCorrection, PrintRaster, PrintVolumes, Region, TriMesh, Void,
};
use crate::spec::model::{MassModel, Print};

/// The voids `design`'s capsules in component `component` cut from it.
pub fn component_voids(design: &Design, component: usize) -> Vec<Void> {
    design
        .capsules
        .iter()
        .filter(|capsule| capsule.component == component)
        .map(|capsule| Void {
            from: capsule.from,
            to: capsule.to,
            radius: capsule.radius,
        })
        .collect()
}

/// The bodies of `meshes`, whose convex hulls are `hulls` and whose solids have the mass
/// properties `solids`, whose material `printed` (one per mesh) has a design's voids cut from it
/// already ([`PartPrints::cut`]).
pub fn cut_bodies<'a>(
    meshes: &'a [TriMesh],
    hulls: &'a [Option<ConvexHull>],
    solids: &[MassProperties],
    printed: &[PrintVolumes],
) -> Vec<ComponentBody<'a>> {
    meshes
        .iter()
        .zip(hulls)
        .zip(solids)
        .zip(printed)
        .map(|(((mesh, hull), solid), print)| {
            ComponentBody::with_voids_cut(mesh, *solid, *print).with_hull(hull.as_ref())
        })
        .collect()
}

/// The bodies of `meshes`, whose convex hulls are `hulls` and whose solids have the mass
/// properties `solids`, with their material `bare` (one per mesh) before any capsule is cut.
pub fn bare_bodies<'a>(
    meshes: &'a [TriMesh],
    hulls: &'a [Option<ConvexHull>],
    solids: &[MassProperties],
    bare: &[PrintVolumes],
) -> Vec<ComponentBody<'a>> {
    meshes
        .iter()
        .zip(hulls)
        .zip(solids)
        .zip(bare)
        .map(|(((mesh, hull), solid), print)| {
            ComponentBody::with_print(mesh, *solid, *print).with_hull(hull.as_ref())
        })
        .collect()
}

/// What it takes to print each component's material for any design: the material before a
/// capsule is cut (the mass model's, with the calibration's correction), how the component is
/// printed, and the correction. Under the `fdm` model each component is sliced the first time a
/// design's voids are cut from it, and its layers are kept for the next design.
#[derive(Debug, Clone)]
pub struct PartPrints {
    /// Per component, in project order: the material before capsules are cut, corrected.
    pub bare: Vec<PrintVolumes>,
    /// Per component: the rotation from its rest frame to its print frame.
    pub to_print: Vec<Rotation3<f64>>,
    /// Per component: the calibration's correction already in `bare` (zero without one).
    pub corrections: Vec<PrintCorrection>,
    /// The print settings and the mass model.
    pub print: Print,
    /// Per component: the mass properties of its solid ([`ComponentBody::mass`]).
    pub solids: Vec<MassProperties>,
    /// Per component: the convex hull of its mesh, rest frame ([`ComponentBody::hull`]).
    pub hulls: Arc<[Option<ConvexHull>]>,
    /// Per component, its layers, once sliced.
    rasters: Vec<OnceLock<Arc<PrintRaster>>>,
    /// The latest cuts.
    cuts: CutCache,
}

/// Most cuts a [`CutCache`] holds before it starts again.
const CACHED_CUTS: usize = 1024;

/// A component's material with a set of voids cut, by component and the voids' bits: a design
/// judged again, or a component whose capsules stayed where they were while another's moved, is
/// not cut again. A copy starts empty, so prints changed after copying never see a stale cut.
#[derive(Debug, Default)]
struct CutCache(Mutex<HashMap<CutKey, PrintVolumes>>);

/// A component's index and the bits of each void's ends and radius.
type CutKey = (usize, Vec<[u64; 7]>);

impl Clone for CutCache {
    fn clone(&self) -> Self {
        CutCache::default()
    }
}

impl CutCache {
    /// The material of component `index` with `voids` cut: the one kept, or `cut()`'s, kept.
    fn get_or_cut(
        &self,
        index: usize,
        voids: &[Void],
        cut: impl FnOnce() -> PrintVolumes,
    ) -> PrintVolumes {
        let key = (
            index,
            voids
                .iter()
                .map(|v| {
                    let [a, b, c] = [v.from.x, v.from.y, v.from.z].map(f64::to_bits);
                    let [d, e, f] = [v.to.x, v.to.y, v.to.z].map(f64::to_bits);
                    [a, b, c, d, e, f, v.radius.to_bits()]
                })
                .collect::<Vec<_>>(),
        );
        let lock = || {
            self.0
                .lock()
                .unwrap_or_else(|poisoned| poisoned.into_inner())
        };
        if let Some(kept) = lock().get(&key) {
            return *kept;
        }
        let volumes = cut();
        let mut kept = lock();
        if kept.len() >= CACHED_CUTS {
            kept.clear();
        }
        kept.insert(key, volumes);
        volumes
    }
}

impl PartPrints {
    /// What it takes to print components whose solids have the mass properties `solids` and whose
    /// meshes have the convex hulls `hulls`, whose material before capsules are cut is `bare`
    /// (with `corrections` in it), printed turned by `to_print`, with `print`.
    pub fn new(
        solids: Vec<MassProperties>,
        hulls: Arc<[Option<ConvexHull>]>,
        bare: Vec<PrintVolumes>,
        to_print: Vec<Rotation3<f64>>,
        corrections: Vec<PrintCorrection>,
        print: Print,
    ) -> PartPrints {
        let rasters = bare.iter().map(|_| OnceLock::new()).collect();
        PartPrints {
            bare,
            to_print,
            corrections,
            print,
            solids,
            hulls,
            rasters,
            cuts: CutCache::default(),
        }
    }

    /// These prints with each component's layers already sliced where `rasters` (in component
    /// order) holds them: sliced with these print settings in this orientation, so each cut
    /// gives the bits slicing it here would.
    pub fn with_rasters(self, rasters: Vec<Option<Arc<PrintRaster>>>) -> PartPrints {
        for (slot, raster) in self.rasters.iter().zip(rasters) {
            if let Some(raster) = raster {
                // Each slot is new and empty: setting it cannot fail.
                let _ = slot.set(raster);
            }
        }
        self
    }

    /// Per component, its material with `design`'s voids cut (solid and sparse parts; the sparse
    /// one printed at `design.infill`). A component without capsules keeps its bare material.
    /// `meshes` are the components' meshes, the same on every call.
    pub fn cut(&self, meshes: &[TriMesh], design: &Design) -> Vec<PrintVolumes> {
        self.bare
            .iter()
            .enumerate()
            .map(|(index, bare)| {
                let voids = component_voids(design, index);
                match (meshes.get(index), self.to_print.get(index)) {
                    (Some(mesh), Some(to_print)) if !voids.is_empty() => match self.print.model {
                        MassModel::Fdm => self.cuts.get_or_cut(index, &voids, || {
                            self.cut_one(mesh, *to_print, bare, index, &voids)
                        }),
                        MassModel::Uniform => self.cut_one(mesh, *to_print, bare, index, &voids),
                    },
                    _ => *bare,
                }
            })
            .collect()
    }

    /// The bodies of `meshes` with `design`'s voids cut from their material
    /// ([`ComponentBody::voids_in_print`]): what a pose of `design` weighs.
    pub fn bodies<'a>(&'a self, meshes: &'a [TriMesh], design: &Design) -> Vec<ComponentBody<'a>> {
        cut_bodies(meshes, &self.hulls, &self.solids, &self.cut(meshes, design))
    }

    /// The bodies of `meshes` before any capsule is cut, for the closed-form capsule term.
    pub fn bare_bodies<'a>(&'a self, meshes: &'a [TriMesh]) -> Vec<ComponentBody<'a>> {
        bare_bodies(meshes, &self.hulls, &self.solids, &self.bare)
    }

    /// Component `index`'s material with `voids` cut.
    fn cut_one(
        &self,
        mesh: &TriMesh,
        to_print: Rotation3<f64>,
        bare: &PrintVolumes,
        index: usize,
        voids: &[Void],
    ) -> PrintVolumes {
        match self.print.model {
            MassModel::Fdm => {
                let raster = self.rasters.get(index).map(|raster| {
                    raster.get_or_init(|| {
                        Arc::new(PrintRaster::new(mesh, &slicing(&self.print, to_print)))
                    })
                });
                let sliced = match raster {
                    Some(raster) => raster.volumes_with_voids(voids),
                    None => PrintRaster::new(mesh, &slicing(&self.print, to_print))
                        .volumes_with_voids(voids),
                };
                let correction = self.corrections.get(index).copied().unwrap_or_default();
                if correction == PrintCorrection::default() {
                    sliced
                } else {
                    correction.apply(&sliced).unwrap_or(sliced)
                }
            }
            MassModel::Uniform => {
                let mut sparse = Weighted::default();
                sparse.add(bare.sparse.volume, &bare.sparse.centroid);
                for void in voids {
                    let length = (void.to - void.from).norm();
                    let volume = capsule_volume(length, void.radius);
                    sparse.add(-volume, &nalgebra::center(&void.from, &void.to));
                }
                PrintVolumes {
                    solid: bare.solid,
                    sparse: Region {
                        volume: sparse.total.max(0.0),
                        centroid: sparse.centre().unwrap_or(bare.sparse.centroid),
                    },
                }
            }
        }
    }
}
