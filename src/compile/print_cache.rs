//! `PrintCache`: each component's print volumes kept between builds of one process, so a watch
//! session slices an unchanged mesh with unchanged print settings and orientation once.

use nalgebra::Rotation3;

use crate::balance::{component_print, slicing};
use crate::geometry::{mass_properties, PrintVolumes, Slicing, TriMesh};
use crate::optimize::content_hash;
use crate::spec::model::{MassModel, Project};

/// Print volumes by mesh content and slicing. Entries not asked for since
/// [`start_build`](Self::start_build) are dropped by [`prune`](Self::prune).
#[derive(Debug, Default)]
pub struct PrintCache {
    /// (mesh content hash, slicing with the print orientation, volumes, asked for in this build), in insertion order.
    entries: Vec<(u64, Slicing, PrintVolumes, bool)>,
    /// Meshes sliced (not found) since the last `start_build`.
    sliced: usize,
}

impl PrintCache {
    /// An empty cache.
    pub fn new() -> PrintCache {
        PrintCache::default()
    }

    /// `project`'s print volumes of `mesh` printed turned by `to_print`: from the cache under the
    /// `fdm` model when this mesh was sliced with these settings and this orientation before,
    /// else computed (and kept).
    pub fn volumes(
        &mut self,
        project: &Project,
        mesh: &TriMesh,
        to_print: Rotation3<f64>,
    ) -> PrintVolumes {
        if project.print.model == MassModel::Uniform {
            return component_print(project, mesh, &mass_properties(mesh), to_print);
        }
        let key = (content_hash(mesh), slicing(&project.print, to_print));
        if let Some(entry) = self
            .entries
            .iter_mut()
            .find(|entry| (entry.0, entry.1) == key)
        {
            entry.3 = true;
            return entry.2;
        }
        let volumes = component_print(project, mesh, &mass_properties(mesh), to_print);
        self.sliced += 1;
        self.entries.push((key.0, key.1, volumes, true));
        volumes
    }

    /// Marks the start of a build: [`prune`](Self::prune) keeps only what is asked for from now.
    pub fn start_build(&mut self) {
        self.sliced = 0;
        for entry in &mut self.entries {
            entry.3 = false;
        }
    }

    /// Drops every entry not asked for since the last [`start_build`](Self::start_build).
    pub fn prune(&mut self) {
        self.entries.retain(|entry| entry.3);
    }

    /// Meshes sliced, not found in the cache, since the last [`start_build`](Self::start_build).
    pub fn sliced(&self) -> usize {
        self.sliced
    }
}
