//! The optimizer's precomputation kept between builds in one process (watch mode): each
//! component's distance grid and skeleton, keyed by the exact content of its mesh and the grid's
//! node spacing, so a build where only poses, goals or options changed samples nothing again.
//! With a [`DiskCache`] under it, what one process computed is found by the next.

use std::collections::HashMap;
use std::sync::Arc;

use super::disk_cache::DiskCache;
use super::grids::content_hash;
use crate::cancel::Cancel;
use crate::geometry::{DistanceGrid, Skeleton, TriMesh};

/// Grids and skeletons already built. Entries not asked for since [`start_build`] can be dropped
/// with [`prune`], so a session that edits a mesh many times does not hold every version.
///
/// With a disk layer ([`with_disk`]), an entry not held is looked for on disk before it is
/// computed, and what is computed is stored there.
///
/// [`start_build`]: PrecomputeCache::start_build
/// [`prune`]: PrecomputeCache::prune
/// [`with_disk`]: PrecomputeCache::with_disk
#[derive(Debug, Default)]
pub struct PrecomputeCache {
    entries: HashMap<GridKey, Entry>,
    build: u64,
    built: Built,
    disk: Option<DiskCache>,
}

/// What an entry is found by: the [`content_hash`] of a mesh and a grid spacing. The hash reads
/// every coordinate, so a build makes one key per mesh and passes it to every call.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct GridKey {
    /// The mesh's [`content_hash`].
    pub mesh: u64,
    /// The node spacing's bits.
    pub cell: u64,
}

impl GridKey {
    /// The key of `mesh` at node spacing `cell`.
    pub fn new(mesh: &TriMesh, cell: f64) -> GridKey {
        GridKey {
            mesh: content_hash(mesh),
            cell: cell.to_bits(),
        }
    }

    /// The node spacing.
    pub fn cell(&self) -> f64 {
        f64::from_bits(self.cell)
    }
}

/// What one build had to compute because the cache did not hold it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Built {
    /// Distance grids sampled.
    pub grids: usize,
    /// Skeletons thinned.
    pub skeletons: usize,
    /// Entries (a grid, with its skeleton when one was stored) read from the disk cache.
    pub loaded: usize,
}

#[derive(Debug)]
struct Entry {
    grid: Arc<DistanceGrid>,
    skeleton: Option<Arc<Skeleton>>,
    /// The build that last asked for it.
    used: u64,
}

impl PrecomputeCache {
    /// An empty cache, in memory only.
    pub fn new() -> PrecomputeCache {
        PrecomputeCache::default()
    }

    /// An empty cache over `disk`: entries not held are read from it when there, and what is
    /// computed is stored in it (unless the build was cancelled). Errors of the disk are ignored.
    pub fn with_disk(disk: DiskCache) -> PrecomputeCache {
        PrecomputeCache {
            disk: Some(disk),
            ..PrecomputeCache::default()
        }
    }

    /// The disk layer, if any.
    pub fn disk(&self) -> Option<&DiskCache> {
        self.disk.as_ref()
    }

    /// Marks the start of a build: [`built`](Self::built) counts from zero again, and
    /// [`prune`](Self::prune) keeps only what is asked for from now on.
    pub fn start_build(&mut self) {
        self.build += 1;
        self.built = Built::default();
    }

    /// The grid of `mesh` (whose key is `key`), sampled now unless an identical mesh was seen
    /// with the same spacing; `None` when `cancel` was set while sampling (nothing is kept).
    pub fn grid(
        &mut self,
        mesh: &TriMesh,
        key: GridKey,
        cancel: &Cancel,
    ) -> Option<Arc<DistanceGrid>> {
        Some(self.entry(mesh, key, cancel)?.grid.clone())
    }

    /// The skeleton of `mesh` (whose key is `key`) thinned on its grid, each built now unless
    /// held; `None` when `cancel` was set.
    pub fn skeleton(
        &mut self,
        mesh: &TriMesh,
        key: GridKey,
        cancel: &Cancel,
    ) -> Option<Arc<Skeleton>> {
        let entry = self.entry(mesh, key, cancel)?;
        if let Some(skeleton) = &entry.skeleton {
            return Some(skeleton.clone());
        }
        let skeleton = Arc::new(Skeleton::from_grid_unless(mesh, &entry.grid, cancel)?);
        entry.skeleton = Some(skeleton.clone());
        let grid = entry.grid.clone();
        self.built.skeletons += 1;
        if let Some(disk) = self.disk.as_ref().filter(|_| !cancel.is_cancelled()) {
            let _ = disk.store(mesh, key.cell(), &grid, Some(&skeleton));
        }
        Some(skeleton)
    }

    /// Whether the grid of `mesh` (whose key is `key`) is held, after reading it (and its
    /// skeleton, when stored) from the disk cache if it is not held but is there. Computes
    /// nothing.
    pub fn recall(&mut self, mesh: &TriMesh, key: GridKey) -> bool {
        if self.entries.contains_key(&key) {
            return true;
        }
        let loaded = self
            .disk
            .as_ref()
            .and_then(|disk| disk.load(mesh, key.cell()));
        let Some((grid, skeleton)) = loaded else {
            return false;
        };
        self.built.loaded += 1;
        self.entries.insert(
            key,
            Entry {
                grid: Arc::new(grid),
                skeleton: skeleton.map(Arc::new),
                used: self.build,
            },
        );
        true
    }

    /// Whether the grid of the mesh whose key is `key` is held.
    pub fn holds_grid(&self, key: GridKey) -> bool {
        self.entries.contains_key(&key)
    }

    /// Whether the skeleton of the mesh whose key is `key` is held.
    pub fn holds_skeleton(&self, key: GridKey) -> bool {
        self.entries
            .get(&key)
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

    fn entry(&mut self, mesh: &TriMesh, key: GridKey, cancel: &Cancel) -> Option<&mut Entry> {
        let build = self.build;
        if !self.recall(mesh, key) {
            let grid = DistanceGrid::new_unless(mesh, key.cell(), cancel)?;
            self.built.grids += 1;
            if let Some(disk) = self.disk.as_ref().filter(|_| !cancel.is_cancelled()) {
                let _ = disk.store(mesh, key.cell(), &grid, None);
            }
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
    use crate::optimize::test_meshes::cube;

    /// The key of the cube of edge `side` at spacing 0.25.
    fn key(side: f64) -> GridKey {
        GridKey::new(&cube(side, 0.0), 0.25)
    }

    #[test]
    fn a_mesh_seen_before_is_not_sampled_again_and_unused_entries_are_pruned() {
        let never = Cancel::new();
        let mut cache = PrecomputeCache::new();
        cache.start_build();
        let first = cache.grid(&cube(1.0, 0.0), key(1.0), &never).unwrap();
        cache.skeleton(&cube(1.0, 0.0), key(1.0), &never).unwrap();
        assert_eq!(
            cache.built(),
            Built {
                grids: 1,
                skeletons: 1,
                loaded: 0
            }
        );

        cache.start_build();
        let again = cache.grid(&cube(1.0, 0.0), key(1.0), &never).unwrap();
        cache.skeleton(&cube(1.0, 0.0), key(1.0), &never).unwrap();
        assert!(Arc::ptr_eq(&first, &again));
        assert_eq!(cache.built(), Built::default());

        cache.start_build();
        cache.grid(&cube(2.0, 0.0), key(2.0), &never).unwrap();
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
        assert!(cache.grid(&cube(1.0, 0.0), key(1.0), &cancel).is_none());
        assert!(cache.is_empty());
        assert_eq!(cache.built(), Built::default());
    }

    #[test]
    fn a_new_cache_over_the_same_disk_reads_what_an_earlier_one_computed() {
        let never = Cancel::new();
        let folder = tempfile::tempdir().unwrap();
        let mut first = PrecomputeCache::with_disk(DiskCache::at(folder.path()));
        first.start_build();
        let grid = first.grid(&cube(1.0, 0.0), key(1.0), &never).unwrap();
        let skeleton = first.skeleton(&cube(1.0, 0.0), key(1.0), &never).unwrap();
        assert_eq!(
            first.built(),
            Built {
                grids: 1,
                skeletons: 1,
                loaded: 0
            }
        );

        let mut second = PrecomputeCache::with_disk(DiskCache::at(folder.path()));
        second.start_build();
        assert!(!second.holds_grid(key(1.0)));
        assert!(second.recall(&cube(1.0, 0.0), key(1.0)));
        assert!(second.holds_skeleton(key(1.0)));
        let read = second.grid(&cube(1.0, 0.0), key(1.0), &never).unwrap();
        assert_eq!(
            *second.skeleton(&cube(1.0, 0.0), key(1.0), &never).unwrap(),
            *skeleton
        );
        let bits = |grid: &DistanceGrid| -> Vec<u64> {
            grid.stored_values().iter().map(|v| v.to_bits()).collect()
        };
        assert_eq!(bits(&read), bits(&grid));
        assert_eq!(
            second.built(),
            Built {
                grids: 0,
                skeletons: 0,
                loaded: 1
            }
        );

        // Without a disk layer nothing is read.
        let mut memory = PrecomputeCache::new();
        assert!(!memory.recall(&cube(1.0, 0.0), key(1.0)));
    }

    #[test]
    fn a_cancelled_build_stores_nothing_on_disk() {
        let cancel = Cancel::new();
        cancel.cancel();
        let folder = tempfile::tempdir().unwrap();
        let mut cache = PrecomputeCache::with_disk(DiskCache::at(folder.path()));
        cache.start_build();
        assert!(cache.grid(&cube(1.0, 0.0), key(1.0), &cancel).is_none());
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 0);
    }
}
