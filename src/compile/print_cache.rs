//! `PrintCache`: each component's sliced print kept between builds of one process, so a watch
//! session slices an unchanged mesh with unchanged print settings and orientation once, and a
//! build slices each part once: for its bare volumes and for cutting every design's voids.

use std::sync::Arc;

use nalgebra::Rotation3;

use crate::balance::{component_print, slicing};
use crate::geometry::{MassProperties, PrintRaster, PrintVolumes, Slicing, TriMesh};
use crate::optimize::content_hash;
use crate::spec::model::{MassModel, Project};

/// Sliced prints and their volumes by mesh content and slicing. Entries not asked for since
/// [`start_build`](Self::start_build) are dropped by [`prune`](Self::prune).
#[derive(Debug, Default)]
pub struct PrintCache {
    /// In insertion order.
    entries: Vec<Entry>,
    /// Meshes sliced (not found) since the last `start_build`.
    sliced: usize,
}

/// One mesh sliced with one slicing.
#[derive(Debug)]
struct Entry {
    /// The mesh's content hash.
    mesh: u64,
    /// The slicing, the print orientation in it.
    slicing: Slicing,
    /// The sliced print, for cutting designs' voids from.
    raster: Arc<PrintRaster>,
    /// Its volumes before a void is cut.
    volumes: PrintVolumes,
    /// Asked for in this build.
    used: bool,
}

impl PrintCache {
    /// An empty cache.
    pub fn new() -> PrintCache {
        PrintCache::default()
    }

    /// `project`'s print volumes of `mesh`, whose solid has the mass properties `solid`, printed
    /// turned by `to_print`: from the cache under the `fdm` model when this mesh was sliced with
    /// these settings and this orientation before, else computed (and kept).
    pub fn volumes(
        &mut self,
        project: &Project,
        mesh: &TriMesh,
        solid: &MassProperties,
        to_print: Rotation3<f64>,
    ) -> PrintVolumes {
        if project.print.model == MassModel::Uniform {
            return component_print(project, mesh, solid, to_print);
        }
        let (hash, slicing) = (content_hash(mesh), slicing(&project.print, to_print));
        if let Some(entry) = self.find(hash, &slicing) {
            entry.used = true;
            return entry.volumes;
        }
        // The same slicing `component_print` does, kept whole.
        let raster = PrintRaster::new(mesh, &slicing);
        let volumes = raster.volumes();
        self.sliced += 1;
        self.entries.push(Entry {
            mesh: hash,
            slicing,
            raster: Arc::new(raster),
            volumes,
            used: true,
        });
        volumes
    }

    /// The sliced print of `mesh` printed turned by `to_print` with `project`'s settings, when
    /// [`volumes`](Self::volumes) sliced it (only under the `fdm` model).
    pub fn raster(
        &mut self,
        project: &Project,
        mesh: &TriMesh,
        to_print: Rotation3<f64>,
    ) -> Option<Arc<PrintRaster>> {
        if project.print.model == MassModel::Uniform {
            return None;
        }
        let (hash, slicing) = (content_hash(mesh), slicing(&project.print, to_print));
        self.find(hash, &slicing).map(|entry| entry.raster.clone())
    }

    /// The entry of this mesh and slicing.
    fn find(&mut self, mesh: u64, slicing: &Slicing) -> Option<&mut Entry> {
        self.entries
            .iter_mut()
            .find(|entry| entry.mesh == mesh && entry.slicing == *slicing)
    }

    /// Marks the start of a build: [`prune`](Self::prune) keeps only what is asked for from now.
    pub fn start_build(&mut self) {
        self.sliced = 0;
        for entry in &mut self.entries {
            entry.used = false;
        }
    }

    /// Drops every entry not asked for since the last [`start_build`](Self::start_build).
    pub fn prune(&mut self) {
        self.entries.retain(|entry| entry.used);
    }

    /// Meshes sliced, not found in the cache, since the last [`start_build`](Self::start_build).
    pub fn sliced(&self) -> usize {
        self.sliced
    }
}
