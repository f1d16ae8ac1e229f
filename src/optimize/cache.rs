//! The optimizer's precomputation kept between builds in one process (watch mode): each
//! component's distance grid and skeleton, keyed by the exact content of its mesh and the grid's
//! node spacing, so a build where only poses, goals or options changed samples nothing again.

use std::collections::HashMap;
use std::sync::Arc;

use super::grids::content_hash;
use crate::cancel::Cancel;
use crate::geometry::{DistanceGrid, Skeleton, TriMesh};

/// Grids and skeletons already built. Entries not asked for since [`start_build`] can be dropped
/// with [`prune`], so a session that edits a mesh many times does not hold every version.
///
/// [`start_build`]: PrecomputeCache::start_build
/// [`prune`]: PrecomputeCache::prune
#[derive(Debug, Default)]
pub struct PrecomputeCache {
    entries: HashMap<(u64, u64), Entry>,
    build: u64,
    built: Built,
}

/// What one build had to compute because the cache did not hold it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Built {
    /// Distance grids sampled.
    pub grids: usize,
    /// Skeletons thinned.
    pub skeletons: usize,
}

#[derive(Debug)]
struct Entry {
    grid: Arc<DistanceGrid>,
    skeleton: Option<Arc<Skeleton>>,
    /// The build that last asked for it.
    used: u64,
}

impl PrecomputeCache {
    /// An empty cache.
    pub fn new() -> PrecomputeCache {
        PrecomputeCache::default()
    }

    /// Marks the start of a build: [`built`](Self::built) counts from zero again, and
    /// [`prune`](Self::prune) keeps only what is asked for from now on.
    pub fn start_build(&mut self) {
        self.build += 1;
        self.built = Built::default();
    }

    /// The grid of `mesh` with node spacing `cell`, sampled now unless an identical mesh was seen
    /// with the same spacing; `None` when `cancel` was set while sampling (nothing is kept).
    pub fn grid(
        &mut self,
        mesh: &TriMesh,
        cell: f64,
        cancel: &Cancel,
    ) -> Option<Arc<DistanceGrid>> {
        Some(self.entry(mesh, cell, cancel)?.grid.clone())
    }

    /// The skeleton of `mesh` thinned on its grid with node spacing `cell`, each built now unless
    /// held; `None` when `cancel` was set.
    pub fn skeleton(
        &mut self,
        mesh: &TriMesh,
        cell: f64,
        cancel: &Cancel,
    ) -> Option<Arc<Skeleton>> {
        let entry = self.entry(mesh, cell, cancel)?;
        if let Some(skeleton) = &entry.skeleton {
            return Some(skeleton.clone());
        }
        if cancel.is_cancelled() {
            return None;
        }
        let skeleton = Arc::new(Skeleton::from_grid(mesh, &entry.grid));
        entry.skeleton = Some(skeleton.clone());
        self.built.skeletons += 1;
        Some(skeleton)
    }

    /// Whether the grid of `mesh` at spacing `cell` is held.
    pub fn holds_grid(&self, mesh: &TriMesh, cell: f64) -> bool {
        self.entries
            .contains_key(&(content_hash(mesh), cell.to_bits()))
    }

    /// Whether the skeleton of `mesh` on its grid at spacing `cell` is held.
    pub fn holds_skeleton(&self, mesh: &TriMesh, cell: f64) -> bool {
        self.entries
            .get(&(content_hash(mesh), cell.to_bits()))
            .is_some_and(|entry| entry.skeleton.is_some())
    }

    /// What was computed since the last [`start_build`](Self::start_build).
    pub fn built(&self) -> Built {
        self.built
    }

    /// Drops every entry not asked for since the last [`start_build`](Self::start_build).
    pub fn prune(&mut self) {
        let build = self.build;
        self.entries.retain(|_, entry| entry.used == build);
    }

    /// Number of meshes (at one spacing each) held.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing is held.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    fn entry(&mut self, mesh: &TriMesh, cell: f64, cancel: &Cancel) -> Option<&mut Entry> {
        let key = (content_hash(mesh), cell.to_bits());
        let build = self.build;
        if !self.entries.contains_key(&key) {
            let grid = DistanceGrid::new_unless(mesh, cell, cancel)?;
            self.built.grids += 1;
            self.entries.insert(
                key,
                Entry {
                    grid: Arc::new(grid),
                    skeleton: None,
                    used: build,
                },
            );
        }
        let entry = self.entries.get_mut(&key)?;
        entry.used = build;
        Some(entry)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;

    fn cube(side: f64) -> TriMesh {
        let p = |x: f64, y: f64, z: f64| Point3::new(x * side, y * side, z * side);
        TriMesh {
            positions: vec![
                p(0.0, 0.0, 0.0),
                p(1.0, 0.0, 0.0),
                p(1.0, 1.0, 0.0),
                p(0.0, 1.0, 0.0),
                p(0.0, 0.0, 1.0),
                p(1.0, 0.0, 1.0),
                p(1.0, 1.0, 1.0),
                p(0.0, 1.0, 1.0),
            ],
            triangles: vec![
                [0, 2, 1],
                [0, 3, 2],
                [4, 5, 6],
                [4, 6, 7],
                [0, 1, 5],
                [0, 5, 4],
                [1, 2, 6],
                [1, 6, 5],
                [2, 3, 7],
                [2, 7, 6],
                [3, 0, 4],
                [3, 4, 7],
            ],
        }
    }

    #[test]
    fn a_mesh_seen_before_is_not_sampled_again_and_unused_entries_are_pruned() {
        let never = Cancel::new();
        let mut cache = PrecomputeCache::new();
        cache.start_build();
        let first = cache.grid(&cube(1.0), 0.25, &never).unwrap();
        cache.skeleton(&cube(1.0), 0.25, &never).unwrap();
        assert_eq!(
            cache.built(),
            Built {
                grids: 1,
                skeletons: 1
            }
        );

        cache.start_build();
        let again = cache.grid(&cube(1.0), 0.25, &never).unwrap();
        cache.skeleton(&cube(1.0), 0.25, &never).unwrap();
        assert!(Arc::ptr_eq(&first, &again));
        assert_eq!(cache.built(), Built::default());

        cache.start_build();
        cache.grid(&cube(2.0), 0.25, &never).unwrap();
        assert_eq!(cache.built().grids, 1);
        assert_eq!(cache.len(), 2);
        cache.prune();
        assert_eq!(cache.len(), 1);
    }

    #[test]
    fn a_cancelled_grid_is_not_kept() {
        let cancel = Cancel::new();
        cancel.cancel();
        let mut cache = PrecomputeCache::new();
        cache.start_build();
        assert!(cache.grid(&cube(1.0), 0.25, &cancel).is_none());
        assert!(cache.is_empty());
        assert_eq!(cache.built(), Built::default());
    }
}
