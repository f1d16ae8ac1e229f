//! The optimizer's precomputation kept on disk between processes: each mesh's distance grid and
//! skeleton, so a fresh `ballast build` of an unchanged mesh samples nothing (`docs/cache.md`).
//!
//! One file per mesh and grid spacing, in `<root>/ballast-v<FORMAT>/` ([`DiskCache::FORMAT`]),
//! named `<BLAKE3 of the mesh>-<cell bits>.bin` (64 and 16 hexadecimal digits), laid out as
//! [`format`] says and sealed with a BLAKE3 hash keyed with the cache's secret ([`secret`]).
//!
//! Reading checks all of it; anything unexpected (another key, another version, a damaged or
//! forged file) is a miss, and the file is removed. The cache never fails a build: every IO
//! error is a miss or a store not made. It only ever removes its own files ([`evict`]).

mod evict;
mod format;
mod secret;

use std::fs::{self, File};
use std::io;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

use self::format::{decode, encode, Key};
use crate::emit::write_atomic;
use crate::geometry::{DistanceGrid, Skeleton, TriMesh};

/// Distance grids and skeletons stored in a folder, shared by every ballast process that uses it.
/// Least recently used files are removed when the folder grows past its bound.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DiskCache {
    root: PathBuf,
    limit: u64,
}

impl DiskCache {
    /// The file format and the meaning of its content. Bump it whenever [`DistanceGrid::new`] or
    /// [`Skeleton::from_grid`] would give different values for the same input, so files written
    /// before are no longer read (and are removed).
    pub const FORMAT: u32 = format::FORMAT;

    /// The default bound on the files of one format folder: 512 MB.
    pub const DEFAULT_LIMIT: u64 = 512 * 1024 * 1024;

    /// The cache in folder `root` (created on the first store), bounded to
    /// [`DEFAULT_LIMIT`](Self::DEFAULT_LIMIT).
    pub fn at(root: impl Into<PathBuf>) -> DiskCache {
        DiskCache {
            root: root.into(),
            limit: DiskCache::DEFAULT_LIMIT,
        }
    }

    /// The same cache bounded to `bytes`: after a store, the least recently used files go until
    /// the rest total at most that.
    pub fn with_limit(self, bytes: u64) -> DiskCache {
        DiskCache {
            limit: bytes,
            ..self
        }
    }

    /// The folder given at [`at`](Self::at).
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// Where the command line keeps its cache: `BALLAST_CACHE_DIR` when set (empty or `off`:
    /// no cache), else the platform's cache folder: `$XDG_CACHE_HOME/ballast` or
    /// `$HOME/.cache/ballast` on Linux and other Unix systems, `$HOME/Library/Caches/ballast` on
    /// macOS, `%LOCALAPPDATA%\ballast\cache` on Windows. `None` when nothing applies.
    pub fn default_location() -> Option<PathBuf> {
        location_from(|name| std::env::var_os(name).map(PathBuf::from))
    }

    /// The grid (and the skeleton, when one was stored) of `mesh` at node spacing `cell`, or
    /// `None` when the cache does not hold them. A file that cannot be read back exactly (another
    /// version, damaged, truncated, not sealed with this cache's secret) is a miss and is
    /// removed. A hit marks the file as used now.
    pub fn load(&self, mesh: &TriMesh, cell: f64) -> Option<(DistanceGrid, Option<Skeleton>)> {
        let key = Key::of(mesh, cell);
        let path = self.path(&key);
        let secret = secret::read_secret(&self.root)?;
        // A regular file within the cache's size: a pipe or a link to a device is a miss.
        let bytes = crate::regular_file::read_limited(&path, self.limit).ok()?;
        match decode(&bytes, &key, &secret, mesh) {
            Some(found) => {
                // Only for eviction: a file that cannot be touched is still a hit.
                let _ = File::options()
                    .write(true)
                    .open(&path)
                    .and_then(|file| file.set_modified(SystemTime::now()));
                Some(found)
            }
            None => {
                let _ = fs::remove_file(&path);
                None
            }
        }
    }

    /// Stores the grid of `mesh` at node spacing `cell` and its skeleton, if any, replacing what
    /// was there (atomically: a reader sees the old file or the new one), then removes the least
    /// recently used files past the bound and the folders of other formats. Callers may ignore
    /// the error: a cache that cannot be written only makes the next build slower.
    pub fn store(
        &self,
        mesh: &TriMesh,
        cell: f64,
        grid: &DistanceGrid,
        skeleton: Option<&Skeleton>,
    ) -> io::Result<()> {
        let key = Key::of(mesh, cell);
        fs::create_dir_all(&self.root)?;
        let secret = secret::secret(&self.root).ok_or_else(|| {
            io::Error::other(format!(
                "no usable key in {} (made by this user, readable by no one else)",
                self.root.display()
            ))
        })?;
        write_atomic(&self.path(&key), &encode(&key, &secret, grid, skeleton))?;
        evict::evict(&self.root, self.limit);
        Ok(())
    }

    /// The folder of this format's files.
    fn folder(&self) -> PathBuf {
        self.root.join(evict::format_folder(DiskCache::FORMAT))
    }

    /// The file of the mesh and spacing `key` is about.
    fn path(&self, key: &Key) -> PathBuf {
        self.folder().join(key.file_name())
    }
}

/// [`DiskCache::default_location`] with the environment read through `var`.
fn location_from(var: impl Fn(&str) -> Option<PathBuf>) -> Option<PathBuf> {
    let set = |name: &str| var(name).filter(|value| !value.as_os_str().is_empty());
    if let Some(value) = var("BALLAST_CACHE_DIR") {
        let off = value.as_os_str().is_empty() || value.as_os_str() == "off";
        return (!off).then_some(value);
    }
    if cfg!(windows) {
        return set("LOCALAPPDATA").map(|base| base.join("ballast").join("cache"));
    }
    if cfg!(target_os = "macos") {
        return set("HOME").map(|home| home.join("Library").join("Caches").join("ballast"));
    }
    let xdg = set("XDG_CACHE_HOME").filter(|path| path.is_absolute());
    xdg.or_else(|| set("HOME").map(|home| home.join(".cache")))
        .map(|base| base.join("ballast"))
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use nalgebra::Point3;

    use super::format::{seal, FORMAT, MAGIC, SEAL_BYTES, VERSION};
    use super::*;
    use crate::emit::atomic::TempName;
    use crate::optimize::test_meshes::cube;

    const CELL: f64 = 0.25;

    fn bits(values: &[f64]) -> Vec<u64> {
        values.iter().map(|v| v.to_bits()).collect()
    }

    fn point_bits(p: &Point3<f64>) -> [u64; 3] {
        [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
    }

    fn assert_same_grid(a: &DistanceGrid, b: &DistanceGrid) {
        assert_eq!(point_bits(&a.origin()), point_bits(&b.origin()));
        assert_eq!(a.cell().to_bits(), b.cell().to_bits());
        assert_eq!(a.dims(), b.dims());
        assert_eq!(bits(a.stored_values()), bits(b.stored_values()));
        // The deferred nodes too, computed from the mesh on the grid read back.
        let [nx, ny, nz] = a.dims();
        for index in
            (0..nz).flat_map(|k| (0..ny).flat_map(move |j| (0..nx).map(move |i| [i, j, k])))
        {
            let value = |grid: &DistanceGrid| grid.node_value(index).map(f64::to_bits);
            assert_eq!(value(a), value(b), "node {index:?}");
        }
    }

    /// A cache in a fresh folder holding the cube's grid and skeleton; the path of its file.
    fn stored() -> (tempfile::TempDir, DiskCache, PathBuf) {
        let folder = tempfile::tempdir().unwrap();
        let cache = DiskCache::at(folder.path());
        let mesh = cube(1.0, 0.0);
        let grid = DistanceGrid::new(&mesh, CELL);
        let skeleton = Skeleton::from_grid(&mesh, &grid);
        cache.store(&mesh, CELL, &grid, Some(&skeleton)).unwrap();
        let path = cache.path(&Key::of(&mesh, CELL));
        assert!(path.is_file());
        (folder, cache, path)
    }

    /// `bytes` sealed again with the secret of the cache in `root`, as a file crafted by someone
    /// holding it would be: the checks after the seal must catch what is wrong.
    fn resealed(root: &Path, mut bytes: Vec<u8>) -> Vec<u8> {
        let secret = secret::read_secret(root).unwrap();
        let body = bytes.len() - SEAL_BYTES;
        let sealed = seal(&secret, &bytes[..body]);
        bytes[body..].copy_from_slice(&sealed);
        bytes
    }

    #[test]
    fn a_grid_and_its_skeleton_read_back_bit_for_bit() {
        let folder = tempfile::tempdir().unwrap();
        let cache = DiskCache::at(folder.path());
        let mesh = cube(1.0, 0.0);
        let grid = DistanceGrid::new(&mesh, CELL);
        assert!(grid.deferred_nodes() > 0);
        let skeleton = Skeleton::from_grid(&mesh, &grid);
        assert!(cache.load(&mesh, CELL).is_none());

        cache.store(&mesh, CELL, &grid, None).unwrap();
        let (read, none) = cache.load(&mesh, CELL).unwrap();
        assert_same_grid(&grid, &read);
        assert!(none.is_none());

        cache.store(&mesh, CELL, &grid, Some(&skeleton)).unwrap();
        let (read, read_skeleton) = cache.load(&mesh, CELL).unwrap();
        assert_same_grid(&grid, &read);
        let read_skeleton = read_skeleton.unwrap();
        assert!(!skeleton.segments.is_empty());
        assert_eq!(read_skeleton.fallback, skeleton.fallback);
        assert_eq!(read_skeleton.segments.len(), skeleton.segments.len());
        for (a, b) in read_skeleton.segments.iter().zip(&skeleton.segments) {
            assert_eq!(point_bits(&a.from), point_bits(&b.from));
            assert_eq!(point_bits(&a.to), point_bits(&b.to));
            assert_eq!(a.radius.to_bits(), b.radius.to_bits());
        }

        // Another mesh, or another spacing, is another entry.
        assert!(cache.load(&cube(1.0, 0.5), CELL).is_none());
        assert!(cache.load(&mesh, 0.3).is_none());

        // An empty grid too.
        let empty = TriMesh {
            positions: Vec::new(),
            triangles: Vec::new(),
        };
        let nothing = DistanceGrid::new(&empty, CELL);
        cache.store(&empty, CELL, &nothing, None).unwrap();
        assert_same_grid(&nothing, &cache.load(&empty, CELL).unwrap().0);
    }

    #[test]
    fn a_truncated_file_is_a_miss_and_is_removed() {
        let (_folder, cache, path) = stored();
        let bytes = fs::read(&path).unwrap();
        let mesh = cube(1.0, 0.0);
        for len in (0..bytes.len()).step_by(61).chain([bytes.len() - 1]) {
            fs::write(&path, &bytes[..len]).unwrap();
            assert!(cache.load(&mesh, CELL).is_none(), "{len} bytes");
            assert!(!path.exists(), "{len} bytes");
        }
    }

    #[test]
    fn a_flipped_byte_is_a_miss() {
        let (_folder, cache, path) = stored();
        let bytes = fs::read(&path).unwrap();
        let mesh = cube(1.0, 0.0);
        for at in (0..bytes.len()).step_by(37).chain([bytes.len() - 1]) {
            let mut damaged = bytes.clone();
            damaged[at] ^= 0x10;
            fs::write(&path, &damaged).unwrap();
            assert!(cache.load(&mesh, CELL).is_none(), "byte {at}");
        }
        fs::write(&path, &bytes).unwrap();
        assert!(cache.load(&mesh, CELL).is_some());
    }

    #[test]
    fn crafted_sizes_that_pass_the_seal_are_misses_without_panicking() {
        let (folder, cache, path) = stored();
        let bytes = fs::read(&path).unwrap();
        let mesh = cube(1.0, 0.0);
        let key = Key::of(&mesh, CELL);
        let secret = secret::read_secret(folder.path()).unwrap();
        assert!(decode(&bytes, &key, &secret, &mesh).is_some());
        let header = MAGIC.len() + 4 + 4 + VERSION.len();
        let dims_at = header + 32 + 3 * 8 + 4 * 8;
        let count: usize = DistanceGrid::new(&mesh, CELL).dims().iter().product();
        let flag_at = dims_at + 3 * 8 + 8 * count;
        let mut crafted = Vec::new();
        // Huge version length, huge or overflowing dims, dims inconsistent with the values, a bad
        // skeleton flag, a bad fallback byte, a huge segment count.
        for (at, value) in [
            (MAGIC.len() + 4, &u32::MAX.to_le_bytes()[..]),
            (dims_at, &u64::MAX.to_le_bytes()[..]),
            (dims_at + 8, &(u64::MAX / 2).to_le_bytes()[..]),
            (dims_at + 16, &1u64.to_le_bytes()[..]),
            (dims_at, &0u64.to_le_bytes()[..]),
            (flag_at, &[2u8][..]),
            (flag_at + 1, &[7u8][..]),
            (flag_at + 2, &u64::MAX.to_le_bytes()[..]),
            (flag_at + 2, &1000u64.to_le_bytes()[..]),
        ] {
            let mut bytes = bytes.clone();
            bytes[at..at + value.len()].copy_from_slice(value);
            crafted.push(resealed(folder.path(), bytes));
        }
        // A grid too small for the interpolant: 3 nodes along every axis, values to match.
        let mut small = bytes[..dims_at].to_vec();
        for _ in 0..3 {
            small.extend_from_slice(&3u64.to_le_bytes());
        }
        small.extend(std::iter::repeat_n(0u8, 27 * 8 + 1 + SEAL_BYTES));
        crafted.push(resealed(folder.path(), small));
        for (index, bytes) in crafted.into_iter().enumerate() {
            assert!(
                decode(&bytes, &key, &secret, &mesh).is_none(),
                "case {index}"
            );
            fs::write(&path, &bytes).unwrap();
            assert!(cache.load(&mesh, CELL).is_none(), "case {index}");
        }
    }

    #[test]
    fn another_version_or_format_is_a_miss() {
        let (folder, cache, path) = stored();
        let bytes = fs::read(&path).unwrap();
        let mesh = cube(1.0, 0.0);

        // Another crate version, same length or not.
        let at = MAGIC.len() + 4;
        for other in ["9.9.9-other", "0.0.0"] {
            let mut changed = bytes[..at].to_vec();
            changed.extend_from_slice(&(other.len() as u32).to_le_bytes());
            changed.extend_from_slice(other.as_bytes());
            changed.extend_from_slice(&bytes[at + 4 + VERSION.len()..]);
            fs::write(&path, resealed(folder.path(), changed)).unwrap();
            assert!(cache.load(&mesh, CELL).is_none(), "{other}");
            assert!(!path.exists());
        }

        // Another format number in the file: an older one or a newer one.
        for other in [FORMAT - 1, FORMAT + 1] {
            let mut changed = bytes.clone();
            changed[MAGIC.len()..MAGIC.len() + 4].copy_from_slice(&other.to_le_bytes());
            fs::write(&path, resealed(folder.path(), changed)).unwrap();
            assert!(cache.load(&mesh, CELL).is_none(), "{other}");
        }
    }

    #[test]
    fn a_forged_or_foreign_file_is_a_miss() {
        let (folder, cache, path) = stored();
        let bytes = fs::read(&path).unwrap();
        let mesh = cube(1.0, 0.0);
        let body = bytes.len() - SEAL_BYTES;
        // Every grid value changed and the file sealed again without the secret: with an
        // unkeyed hash of the body (what a forger can compute), or another secret.
        let mut forged = bytes[..body].to_vec();
        let values_at = MAGIC.len() + 4 + 4 + VERSION.len() + 32 + 3 * 8 + 7 * 8;
        for byte in &mut forged[values_at..values_at + 800] {
            *byte = 0;
        }
        let unkeyed = *blake3::hash(&forged).as_bytes();
        let other_secret = seal(&[9u8; 32], &forged);
        for seal in [unkeyed, other_secret] {
            let mut file = forged.clone();
            file.extend_from_slice(&seal);
            fs::write(&path, &file).unwrap();
            assert!(cache.load(&mesh, CELL).is_none());
            assert!(!path.exists());
        }
        // A genuine file of another cache folder (its own secret), copied in.
        let other = tempfile::tempdir().unwrap();
        let foreign = DiskCache::at(other.path());
        let grid = DistanceGrid::new(&mesh, CELL);
        foreign.store(&mesh, CELL, &grid, None).unwrap();
        assert!(foreign.load(&mesh, CELL).is_some());
        fs::copy(foreign.path(&Key::of(&mesh, CELL)), &path).unwrap();
        assert!(cache.load(&mesh, CELL).is_none());
        // Without its key file the cache reads nothing, and a store makes a new key.
        fs::write(&path, &bytes).unwrap();
        assert!(cache.load(&mesh, CELL).is_some());
        fs::remove_file(secret::secret_path(folder.path())).unwrap();
        assert!(cache.load(&mesh, CELL).is_none());
        cache.store(&mesh, CELL, &grid, None).unwrap();
        assert!(cache.load(&mesh, CELL).is_some());
    }

    #[test]
    fn only_the_caches_own_files_are_ever_removed() {
        let (folder, cache, path) = stored();
        let root = folder.path();
        let bytes = fs::read(&path).unwrap();
        let mesh = cube(1.0, 0.0);
        let dead_pid = u32::MAX - 1;
        let temp = |dir: &Path, target: &str| {
            let name = TempName {
                target: target.into(),
                pid: dead_pid,
                n: 0,
            };
            let path = dir.join(name.file_name());
            fs::write(&path, b"partial").unwrap();
            File::options()
                .write(true)
                .open(&path)
                .unwrap()
                .set_modified(SystemTime::now() - Duration::from_secs(7200))
                .unwrap();
            path
        };
        let cache_name = path.file_name().unwrap().to_str().unwrap().to_owned();
        // The user's folders named like format folders, with their own files, hidden `.tmp`
        // files old enough to look stale, and a file of the cache's name that is not the cache's.
        let mut kept = Vec::new();
        for user in ["v2", "v10", "ballast-v7"] {
            let dir = root.join(user);
            fs::create_dir_all(dir.join("deep")).unwrap();
            fs::write(dir.join("deep").join("photo.jpg"), b"user").unwrap();
            fs::write(dir.join("notes.txt"), b"user").unwrap();
            kept.push(dir.join("deep").join("photo.jpg"));
            kept.push(dir.join("notes.txt"));
            kept.push(temp(&dir, "notes.txt"));
            fs::write(dir.join(&cache_name), b"not the cache's bytes").unwrap();
            kept.push(dir.join(&cache_name));
        }
        let hidden = root.join(".draft.tmp");
        fs::write(&hidden, b"user").unwrap();
        kept.push(hidden);
        kept.push(temp(root, "notes.txt"));
        let current = cache.folder();
        kept.push(temp(&current, "notes.txt"));
        let user_in_current = current.join("mine.bin");
        fs::write(&user_in_current, b"user").unwrap();
        kept.push(user_in_current);

        // What the cache did write: an old format's folder with its files, a temporary file of a
        // killed store, and one of the user's folders that also holds a cache file.
        let old = root.join("v1");
        fs::create_dir_all(&old).unwrap();
        let old_file = old.join("0123456789abcdef-3fd0000000000000.bin");
        fs::write(&old_file, &bytes).unwrap();
        let stale = temp(&current, &cache_name);
        let mixed = root
            .join("v2")
            .join("fedcba9876543210-3fd0000000000000.bin");
        fs::write(&mixed, &bytes).unwrap();

        // A bound so small every cache file goes.
        let tight = cache.clone().with_limit(0);
        tight
            .store(&mesh, CELL, &DistanceGrid::new(&mesh, CELL), None)
            .unwrap();
        for path in &kept {
            assert!(path.exists(), "{} was removed", path.display());
        }
        assert!(!old.exists(), "the old format's emptied folder stays");
        assert!(!stale.exists());
        assert!(!mixed.exists());
        assert!(root.join("v2").is_dir());
        assert!(!path.exists());
        assert!(secret::read_secret(root).is_some());
    }

    #[test]
    fn past_the_bound_the_least_recently_used_files_go() {
        let folder = tempfile::tempdir().unwrap();
        let meshes: Vec<TriMesh> = (0..3).map(|i| cube(1.0, i as f64 * 10.0)).collect();
        let grids: Vec<DistanceGrid> = meshes.iter().map(|m| DistanceGrid::new(m, CELL)).collect();
        let unbounded = DiskCache::at(folder.path());
        unbounded.store(&meshes[0], CELL, &grids[0], None).unwrap();
        let size = fs::metadata(unbounded.path(&Key::of(&meshes[0], CELL)))
            .unwrap()
            .len();
        // Room for two files.
        let cache = unbounded.with_limit(2 * size + size / 2);
        cache.store(&meshes[1], CELL, &grids[1], None).unwrap();
        let age = |mesh: &TriMesh, seconds: u64| {
            File::options()
                .write(true)
                .open(cache.path(&Key::of(mesh, CELL)))
                .unwrap()
                .set_modified(SystemTime::now() - Duration::from_secs(seconds))
                .unwrap();
        };
        age(&meshes[0], 2000);
        age(&meshes[1], 1000);
        // Reading the older one makes it the most recently used.
        assert!(cache.load(&meshes[0], CELL).is_some());
        cache.store(&meshes[2], CELL, &grids[2], None).unwrap();
        assert!(cache.path(&Key::of(&meshes[0], CELL)).exists());
        assert!(!cache.path(&Key::of(&meshes[1], CELL)).exists());
        assert!(cache.path(&Key::of(&meshes[2], CELL)).exists());
    }

    /// An environment of `pairs`.
    fn env<'a>(pairs: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<PathBuf> + 'a {
        move |name| {
            pairs
                .iter()
                .find(|(key, _)| *key == name)
                .map(|(_, value)| PathBuf::from(value))
        }
    }

    #[test]
    fn the_default_location_follows_the_environment() {
        let home = [
            ("HOME", "/home/me"),
            ("LOCALAPPDATA", "C:\\Users\\me\\AppData\\Local"),
        ];
        assert_eq!(
            location_from(env(&[
                ("BALLAST_CACHE_DIR", "/tmp/c"),
                ("HOME", "/home/me")
            ])),
            Some(PathBuf::from("/tmp/c"))
        );
        assert_eq!(
            location_from(env(&[("BALLAST_CACHE_DIR", "off"), ("HOME", "/home/me")])),
            None
        );
        assert_eq!(
            location_from(env(&[("BALLAST_CACHE_DIR", ""), ("HOME", "/home/me")])),
            None
        );
        assert_eq!(location_from(env(&[])), None);
        let plain = location_from(env(&home)).unwrap();
        if cfg!(windows) {
            assert_eq!(
                plain,
                Path::new("C:\\Users\\me\\AppData\\Local")
                    .join("ballast")
                    .join("cache")
            );
        } else if cfg!(target_os = "macos") {
            assert_eq!(plain, Path::new("/home/me/Library/Caches/ballast"));
        } else {
            assert_eq!(plain, Path::new("/home/me/.cache/ballast"));
            assert_eq!(
                location_from(env(&[("XDG_CACHE_HOME", "/xdg"), ("HOME", "/home/me")])),
                Some(PathBuf::from("/xdg/ballast"))
            );
            // A relative XDG_CACHE_HOME is ignored, as the XDG specification says.
            assert_eq!(
                location_from(env(&[("XDG_CACHE_HOME", "rel"), ("HOME", "/home/me")])),
                Some(PathBuf::from("/home/me/.cache/ballast"))
            );
            assert_eq!(location_from(env(&[("HOME", "")])), None);
        }
    }
}
