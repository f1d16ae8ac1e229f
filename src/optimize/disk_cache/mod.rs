//! The optimizer's precomputation kept on disk between processes: each mesh's distance grid and
//! skeleton, so a fresh `ballast build` of an unchanged mesh samples nothing (`docs/cache.md`).
//!
//! One file per mesh and grid spacing, in `<root>/v<FORMAT>/` ([`DiskCache::FORMAT`]), named
//! `<content hash>-<cell bits>.bin` (16 hexadecimal digits each). The file is little-endian:
//!
//! | field | bytes |
//! | --- | --- |
//! | magic `BALLASTC` | 8 |
//! | [`DiskCache::FORMAT`] | u32 |
//! | crate version, length-prefixed | u32 + text |
//! | key: content hash, cell bits, vertex count, triangle count | 4 × u64 |
//! | grid: origin (3 × f64 bits), cell (f64 bits), dims (3 × u64), every value's bits | … |
//! | skeleton: 0 (none) or 1 (stored) | u8 |
//! | if stored: fallback, 0 or 1 | u8 |
//! | if stored: segment count, then each segment's `from`, `to`, radius | u64 + 7 × u64 each |
//! | FNV-1a 64 of every byte before it | u64 |
//!
//! Reading checks all of it; anything unexpected is a miss, and the file is removed. The cache
//! never fails a build: every IO error is a miss or a store not made.

use std::fs::{self, File};
use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use nalgebra::Point3;

use super::grids::{content_hash, fnv1a};
use crate::emit::write_atomic;
use crate::geometry::{DistanceGrid, Skeleton, SkeletonSegment, TriMesh};

/// The first bytes of every cache file.
const MAGIC: &[u8; 8] = b"BALLASTC";

/// The crate version written into every file: another version's files are misses.
const VERSION: &str = env!("CARGO_PKG_VERSION");

/// Temporary files left by an interrupted write are removed once this old.
const STALE_TEMP: Duration = Duration::from_secs(3600);

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
    /// before are no longer read (and their folder is removed).
    pub const FORMAT: u32 = 1;

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
    /// version, damaged, truncated) is a miss and is removed. A hit marks the file as used now.
    pub fn load(&self, mesh: &TriMesh, cell: f64) -> Option<(DistanceGrid, Option<Skeleton>)> {
        let key = Key::of(mesh, cell);
        let path = self.path(&key);
        let bytes = fs::read(&path).ok()?;
        match decode(&bytes, &key) {
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
        write_atomic(&self.path(&key), &encode(&key, grid, skeleton))?;
        self.evict();
        Ok(())
    }

    /// The folder of this format's files.
    fn folder(&self) -> PathBuf {
        self.root.join(format!("v{}", DiskCache::FORMAT))
    }

    /// The file of the mesh and spacing `key` is about.
    fn path(&self, key: &Key) -> PathBuf {
        self.folder()
            .join(format!("{:016x}-{:016x}.bin", key.hash, key.cell))
    }

    /// Removes the folders of other formats, temporary files left by interrupted writes, and the
    /// least recently used files until the rest fit the bound. Errors are ignored.
    fn evict(&self) {
        if let Ok(entries) = fs::read_dir(&self.root) {
            for entry in entries.flatten() {
                let name = entry.file_name();
                let Some(name) = name.to_str() else { continue };
                let other_format = name.strip_prefix('v').is_some_and(|digits| {
                    !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
                }) && name != format!("v{}", DiskCache::FORMAT);
                if other_format && entry.file_type().is_ok_and(|t| t.is_dir()) {
                    let _ = fs::remove_dir_all(entry.path());
                }
            }
        }
        let Ok(entries) = fs::read_dir(self.folder()) else {
            return;
        };
        let now = SystemTime::now();
        let mut files = Vec::new();
        for entry in entries.flatten() {
            let Ok(metadata) = entry.metadata() else {
                continue;
            };
            if !metadata.is_file() {
                continue;
            }
            let name = entry.file_name();
            let name = name.to_string_lossy();
            let modified = metadata.modified().unwrap_or(SystemTime::UNIX_EPOCH);
            if name.starts_with('.') && name.ends_with(".tmp") {
                let age = now.duration_since(modified).unwrap_or_default();
                if age > STALE_TEMP {
                    let _ = fs::remove_file(entry.path());
                }
            } else if name.ends_with(".bin") {
                files.push((modified, entry.path(), metadata.len()));
            }
        }
        let mut total: u64 = files.iter().map(|(_, _, len)| len).sum();
        if total <= self.limit {
            return;
        }
        files.sort();
        for (_, path, len) in files {
            if total <= self.limit {
                break;
            }
            if fs::remove_file(&path).is_ok() {
                total -= len;
            }
        }
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

/// What a file must be about: the mesh (its content hash and sizes) and the grid spacing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Key {
    hash: u64,
    cell: u64,
    vertices: u64,
    triangles: u64,
}

impl Key {
    fn of(mesh: &TriMesh, cell: f64) -> Key {
        Key {
            hash: content_hash(mesh),
            cell: cell.to_bits(),
            vertices: mesh.positions.len() as u64,
            triangles: mesh.triangles.len() as u64,
        }
    }
}

/// The bytes of a cache file.
fn encode(key: &Key, grid: &DistanceGrid, skeleton: Option<&Skeleton>) -> Vec<u8> {
    let mut out = Vec::with_capacity(128 + 8 * grid.values().len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&DiskCache::FORMAT.to_le_bytes());
    out.extend_from_slice(&(VERSION.len() as u32).to_le_bytes());
    out.extend_from_slice(VERSION.as_bytes());
    for word in [key.hash, key.cell, key.vertices, key.triangles] {
        put_u64(&mut out, word);
    }
    put_point(&mut out, &grid.origin());
    put_f64(&mut out, grid.cell());
    for n in grid.dims() {
        put_u64(&mut out, n as u64);
    }
    for &value in grid.values() {
        put_f64(&mut out, value);
    }
    match skeleton {
        None => out.push(0),
        Some(skeleton) => {
            out.push(1);
            out.push(u8::from(skeleton.fallback));
            put_u64(&mut out, skeleton.segments.len() as u64);
            for segment in &skeleton.segments {
                put_point(&mut out, &segment.from);
                put_point(&mut out, &segment.to);
                put_f64(&mut out, segment.radius);
            }
        }
    }
    let checksum = fnv1a(&out);
    put_u64(&mut out, checksum);
    out
}

fn put_u64(out: &mut Vec<u8>, word: u64) {
    out.extend_from_slice(&word.to_le_bytes());
}

fn put_f64(out: &mut Vec<u8>, value: f64) {
    put_u64(out, value.to_bits());
}

fn put_point(out: &mut Vec<u8>, point: &Point3<f64>) {
    for &c in point.iter() {
        put_f64(out, c);
    }
}

/// The grid and skeleton in `bytes`, or `None` unless every check passes and the file is about
/// `key`.
fn decode(bytes: &[u8], key: &Key) -> Option<(DistanceGrid, Option<Skeleton>)> {
    let (body, checksum) = bytes.split_at_checked(bytes.len().checked_sub(8)?)?;
    if fnv1a(body) != u64::from_le_bytes(checksum.try_into().ok()?) {
        return None;
    }
    let mut reader = Reader { bytes: body };
    if reader.take(MAGIC.len())? != MAGIC || reader.u32()? != DiskCache::FORMAT {
        return None;
    }
    let version_len = reader.u32()? as usize;
    if reader.take(version_len)? != VERSION.as_bytes() {
        return None;
    }
    let found = Key {
        hash: reader.u64()?,
        cell: reader.u64()?,
        vertices: reader.u64()?,
        triangles: reader.u64()?,
    };
    if found != *key {
        return None;
    }
    let origin = reader.point()?;
    let cell = reader.f64()?;
    if cell.to_bits() != key.cell {
        return None;
    }
    let mut dims = [0usize; 3];
    for n in &mut dims {
        *n = usize::try_from(reader.u64()?).ok()?;
    }
    let count = dims
        .iter()
        .try_fold(1usize, |count, &n| count.checked_mul(n))?;
    // Checked against what is left before anything is allocated.
    if count.checked_mul(8)? > reader.bytes.len() {
        return None;
    }
    let values = (0..count)
        .map(|_| reader.f64())
        .collect::<Option<Vec<f64>>>()?;
    let grid = DistanceGrid::from_parts(origin, cell, dims, values)?;
    let skeleton = match reader.u8()? {
        0 => None,
        1 => {
            let fallback = match reader.u8()? {
                0 => false,
                1 => true,
                _ => return None,
            };
            let segments = usize::try_from(reader.u64()?).ok()?;
            if segments.checked_mul(7 * 8)? != reader.bytes.len() {
                return None;
            }
            let segments = (0..segments)
                .map(|_| {
                    Some(SkeletonSegment {
                        from: reader.point()?,
                        to: reader.point()?,
                        radius: reader.f64()?,
                    })
                })
                .collect::<Option<Vec<_>>>()?;
            Some(Skeleton { segments, fallback })
        }
        _ => return None,
    };
    reader.bytes.is_empty().then_some((grid, skeleton))
}

/// Reads fields from the front of a byte slice; every read checks that the bytes are there.
struct Reader<'a> {
    bytes: &'a [u8],
}

impl<'a> Reader<'a> {
    fn take(&mut self, len: usize) -> Option<&'a [u8]> {
        let (taken, rest) = self.bytes.split_at_checked(len)?;
        self.bytes = rest;
        Some(taken)
    }

    fn u8(&mut self) -> Option<u8> {
        Some(self.take(1)?[0])
    }

    fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes(self.take(4)?.try_into().ok()?))
    }

    fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.take(8)?.try_into().ok()?))
    }

    fn f64(&mut self) -> Option<f64> {
        Some(f64::from_bits(self.u64()?))
    }

    fn point(&mut self) -> Option<Point3<f64>> {
        Some(Point3::new(self.f64()?, self.f64()?, self.f64()?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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
        assert_eq!(bits(a.values()), bits(b.values()));
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

    /// `bytes` with the checksum recomputed, as a file crafted to pass it would be.
    fn resealed(mut bytes: Vec<u8>) -> Vec<u8> {
        let body = bytes.len() - 8;
        let checksum = fnv1a(&bytes[..body]);
        bytes[body..].copy_from_slice(&checksum.to_le_bytes());
        bytes
    }

    #[test]
    fn a_grid_and_its_skeleton_read_back_bit_for_bit() {
        let folder = tempfile::tempdir().unwrap();
        let cache = DiskCache::at(folder.path());
        let mesh = cube(1.0, 0.0);
        let grid = DistanceGrid::new(&mesh, CELL);
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
    fn crafted_sizes_that_pass_the_checksum_are_misses_without_panicking() {
        let (_folder, cache, path) = stored();
        let bytes = fs::read(&path).unwrap();
        let mesh = cube(1.0, 0.0);
        let key = Key::of(&mesh, CELL);
        assert!(decode(&bytes, &key).is_some());
        let header = MAGIC.len() + 4 + 4 + VERSION.len();
        let dims_at = header + 4 * 8 + 4 * 8;
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
            crafted.push(resealed(bytes));
        }
        // A grid too small for the interpolant: 3 nodes along every axis, values to match.
        let mut small = bytes[..dims_at].to_vec();
        for _ in 0..3 {
            small.extend_from_slice(&3u64.to_le_bytes());
        }
        small.extend(std::iter::repeat_n(0u8, 27 * 8 + 1 + 8));
        crafted.push(resealed(small));
        for (index, bytes) in crafted.into_iter().enumerate() {
            assert!(decode(&bytes, &key).is_none(), "case {index}");
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
            fs::write(&path, resealed(changed)).unwrap();
            assert!(cache.load(&mesh, CELL).is_none(), "{other}");
            assert!(!path.exists());
        }

        // Another format number in the file.
        let mut changed = bytes.clone();
        changed[MAGIC.len()..MAGIC.len() + 4].copy_from_slice(&2u32.to_le_bytes());
        fs::write(&path, resealed(changed)).unwrap();
        assert!(cache.load(&mesh, CELL).is_none());

        // A file in another format's folder is not looked at, and that folder goes on the next
        // store; nothing else under the root is touched.
        let other = folder.path().join("v2");
        fs::create_dir_all(&other).unwrap();
        fs::write(other.join(path.file_name().unwrap()), &bytes).unwrap();
        assert!(cache.load(&mesh, CELL).is_none());
        for kept in ["v", "vx", "v2b", "notes"] {
            fs::create_dir_all(folder.path().join(kept)).unwrap();
        }
        fs::write(folder.path().join("v3"), b"a file, not a folder").unwrap();
        let grid = DistanceGrid::new(&mesh, CELL);
        cache.store(&mesh, CELL, &grid, None).unwrap();
        assert!(!other.exists());
        for kept in ["v", "vx", "v2b", "notes", "v3", "v1"] {
            assert!(folder.path().join(kept).exists(), "{kept}");
        }
        assert!(cache.load(&mesh, CELL).is_some());
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
