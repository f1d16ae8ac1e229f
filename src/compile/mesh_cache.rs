//! Meshes kept between builds in one process (watch mode): each component's loaded mesh and its
//! solidity check, keyed by the file's path, the part selected and a hash of the bytes of every
//! file the mesh is read from (the file itself, and a `.gltf` file's external buffers). A build
//! still reads those bytes, to hash them, but parses, welds and checks a mesh only when they
//! changed.

use std::collections::HashMap;
use std::hash::{DefaultHasher, Hasher};
use std::path::{Path, PathBuf};
use std::rc::Rc;

use crate::geometry::{check_mesh, external_buffer_paths, load_mesh_with, LoadError, MeshCheck};
use crate::geometry::{FileReader, LoadedMesh, MeshFile, MeshSelector, ReadPolicy, TriMesh};

/// Loaded meshes and their checks. Entries not asked for since [`start_build`] can be dropped
/// with [`prune`].
///
/// [`start_build`]: MeshCache::start_build
/// [`prune`]: MeshCache::prune
#[derive(Default)]
pub struct MeshCache {
    entries: HashMap<(PathBuf, MeshSelector, u64), Entry>,
    /// This build's hash of each file read, so that a file many components share (a rig) is
    /// read and hashed once a build.
    hashes: HashMap<PathBuf, Option<u64>>,
    /// This build's files opened for a part not cached, so that a file of many parts is parsed
    /// once a build, not once a part.
    opened: HashMap<(PathBuf, u64), Rc<MeshFile>>,
    build: u64,
    loaded: usize,
    /// Files opened since the build started.
    files_opened: usize,
}

impl std::fmt::Debug for MeshCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshCache")
            .field("entries", &self.entries.len())
            .field("build", &self.build)
            .field("loaded", &self.loaded)
            .finish()
    }
}

#[derive(Debug)]
struct Entry {
    mesh: LoadedMesh,
    check: MeshCheck,
    /// The build that last asked for it.
    used: u64,
}

impl MeshCache {
    /// An empty cache.
    pub fn new() -> MeshCache {
        MeshCache::default()
    }

    /// Marks the start of a build: [`loaded`](Self::loaded) counts from zero again, and
    /// [`prune`](Self::prune) keeps only what is asked for from now on.
    pub fn start_build(&mut self) {
        self.build += 1;
        self.loaded = 0;
        self.files_opened = 0;
        self.hashes.clear();
        self.opened.clear();
    }

    /// Drops every entry not asked for since the last [`start_build`](Self::start_build).
    pub fn prune(&mut self) {
        let build = self.build;
        self.entries.retain(|_, entry| entry.used == build);
        self.opened.clear();
    }

    /// Meshes parsed (not found in the cache) since the last [`start_build`](Self::start_build).
    pub fn loaded(&self) -> usize {
        self.loaded
    }

    /// Mesh files read and parsed since the last [`start_build`](Self::start_build): once per
    /// file however many of its parts were loaded.
    pub fn files_opened(&self) -> usize {
        self.files_opened
    }

    /// Number of meshes held.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing is held.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The mesh at `path` (the part `selector` picks) and its check: from the cache when the
    /// files it is read from hold the same bytes as when it was cached, else loaded now. Files
    /// are read only as `policy` allows, the cached ones too. A mesh that fails to load is not
    /// cached. `beside` is run on the mesh as loaded, and what it returns returned with it: on
    /// another thread while the mesh is checked, when the check is not cached (work that needs
    /// the mesh but not its check, such as its convex hull, then costs no time of its own).
    pub fn load<T: Send>(
        &mut self,
        path: &Path,
        selector: &MeshSelector,
        policy: &ReadPolicy,
        beside: impl FnOnce(&TriMesh) -> T + Send,
    ) -> Result<(LoadedMesh, MeshCheck, T), LoadError> {
        let hash = *self
            .hashes
            .entry(path.to_path_buf())
            .or_insert_with(|| content_hash(path, policy));
        let Some(hash) = hash else {
            // Unreadable or not allowed: the loader says why.
            self.loaded += 1;
            let mesh = load_mesh_with(path, selector, policy)?;
            let (check, beside) = check_beside(&mesh.mesh, beside);
            return Ok((mesh, check, beside));
        };
        let key = (path.to_path_buf(), selector.clone(), hash);
        let build = self.build;
        if let Some(entry) = self.entries.get_mut(&key) {
            entry.used = build;
            let beside = beside(&entry.mesh.mesh);
            return Ok((entry.mesh.clone(), entry.check.clone(), beside));
        }
        self.loaded += 1;
        let file = match self.opened.get(&(path.to_path_buf(), hash)) {
            Some(file) => file.clone(),
            None => {
                self.files_opened += 1;
                let file = Rc::new(MeshFile::open(path, policy)?);
                self.opened.insert((path.to_path_buf(), hash), file.clone());
                file
            }
        };
        let mesh = file.load(selector)?;
        let (check, beside) = check_beside(&mesh.mesh, beside);
        self.entries.insert(
            key,
            Entry {
                mesh: mesh.clone(),
                check: check.clone(),
                used: build,
            },
        );
        Ok((mesh, check, beside))
    }
}

/// A mesh of fewer triangles is checked and given to `beside` on one thread: a thread would cost
/// more than it saves, many times over for a rig of thousands of small parts.
const THREAD_BESIDE_FROM: usize = 10_000;

/// [`check_mesh`] of `mesh`, and `beside` run on it on another thread meanwhile (for a mesh of
/// [`THREAD_BESIDE_FROM`] triangles or more).
fn check_beside<T: Send>(
    mesh: &TriMesh,
    beside: impl FnOnce(&TriMesh) -> T + Send,
) -> (MeshCheck, T) {
    if mesh.triangles.len() < THREAD_BESIDE_FROM {
        return (check_mesh(mesh), beside(mesh));
    }
    std::thread::scope(|scope| {
        let other = scope.spawn(|| beside(mesh));
        let check = check_mesh(mesh);
        let beside = other
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (check, beside)
    })
}

/// A hash of the bytes of `path` and of each external buffer file it names, in order; `None`
/// when one of them cannot be read or `policy` does not allow it.
fn content_hash(path: &Path, policy: &ReadPolicy) -> Option<u64> {
    let mut hasher = DefaultHasher::new();
    let mut reader = FileReader::new(policy);
    for file in std::iter::once(path.to_path_buf()).chain(external_buffer_paths(path, policy)) {
        let bytes = reader.read(&file).ok()?;
        hasher.write_usize(bytes.len());
        hasher.write(&bytes);
    }
    Some(hasher.finish())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TETRAHEDRON: &str =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

    #[test]
    fn an_unchanged_file_is_not_parsed_again_and_a_changed_one_is() {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("t.obj");
        std::fs::write(&path, TETRAHEDRON).unwrap();
        let policy = ReadPolicy::within(folder.path());
        let mut cache = MeshCache::new();
        cache.start_build();
        // What runs beside the check sees the mesh, loaded or cached.
        let triangles = |mesh: &TriMesh| mesh.triangles.len();
        let (first, check, counted) = cache
            .load(&path, &MeshSelector::Whole, &policy, triangles)
            .unwrap();
        assert!(check.is_closed());
        assert_eq!(counted, 4);
        assert_eq!(cache.loaded(), 1);

        cache.start_build();
        let (again, _, counted) = cache
            .load(&path, &MeshSelector::Whole, &policy, triangles)
            .unwrap();
        assert_eq!(again, first);
        assert_eq!(counted, 4);
        assert_eq!(cache.loaded(), 0);

        std::fs::write(&path, TETRAHEDRON.replace("v 0 0 1", "v 0 0 2")).unwrap();
        cache.start_build();
        let (moved, ..) = cache
            .load(&path, &MeshSelector::Whole, &policy, triangles)
            .unwrap();
        assert_ne!(moved, first);
        assert_eq!(cache.loaded(), 1);
        assert_eq!(cache.len(), 2);
        cache.prune();
        assert_eq!(cache.len(), 1);
    }

    #[test]
    fn a_file_of_several_parts_is_parsed_once_a_build() {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("two.obj");
        let second = TETRAHEDRON
            .lines()
            .map(|line| match line.strip_prefix("f ") {
                Some(face) => {
                    let shifted: Vec<String> = face
                        .split(' ')
                        .map(|i| (i.parse::<usize>().unwrap() + 4).to_string())
                        .collect();
                    format!("f {}\n", shifted.join(" "))
                }
                None => format!("{}\n", line.replace("v 0 0 0", "v 5 0 0")),
            })
            .collect::<String>();
        std::fs::write(&path, format!("o a\n{TETRAHEDRON}o b\n{second}")).unwrap();
        let policy = ReadPolicy::within(folder.path());
        let mut cache = MeshCache::new();
        cache.start_build();
        let part = |name: &str| MeshSelector::ObjObject(name.to_string());
        let (a, ..) = cache.load(&path, &part("a"), &policy, |_| ()).unwrap();
        let (b, ..) = cache.load(&path, &part("b"), &policy, |_| ()).unwrap();
        assert_eq!(a.mesh.triangles.len(), 4);
        assert_eq!(b.mesh.triangles.len(), 4);
        assert_ne!(a.mesh.positions, b.mesh.positions);
        assert_eq!((cache.loaded(), cache.files_opened()), (2, 1));
        std::fs::write(
            &path,
            format!(
                "o a\n{}o b\n{second}",
                TETRAHEDRON.replace("v 0 1 0", "v 0 2 0")
            ),
        )
        .unwrap();
        cache.start_build();
        cache.load(&path, &part("a"), &policy, |_| ()).unwrap();
        cache.load(&path, &part("b"), &policy, |_| ()).unwrap();
        assert_eq!((cache.loaded(), cache.files_opened()), (2, 1));
    }

    #[test]
    fn a_missing_file_is_the_loader_s_error_and_is_not_cached() {
        let folder = tempfile::tempdir().unwrap();
        let mut cache = MeshCache::new();
        let missing = cache.load(
            &folder.path().join("none.obj"),
            &MeshSelector::Whole,
            &ReadPolicy::within(folder.path()),
            |_| (),
        );
        assert!(
            matches!(missing, Err(LoadError::NotFound { .. })),
            "{missing:?}"
        );
        assert!(cache.is_empty());
    }
}
