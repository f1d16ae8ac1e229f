//! The bytes of a cache file (`docs/cache.md`); little-endian:
//!
//! | field | bytes |
//! | --- | --- |
//! | magic `BALLASTC` | 8 |
//! | [`FORMAT`] | u32 |
//! | crate version, length-prefixed | u32 + text |
//! | key: BLAKE3 of the mesh, cell bits, vertex count, triangle count | 32 + 3 × u64 |
//! | grid: origin (3 × f64 bits), cell (f64 bits), dims (3 × u64), every value's bits (NaN for a node left for its first read) | … |
//! | skeleton: 0 (none) or 1 (stored) | u8 |
//! | if stored: fallback, 0 or 1 | u8 |
//! | if stored: segment count, then each segment's `from`, `to`, radius | u64 + 7 × u64 each |
//! | BLAKE3 keyed with the cache's secret, of every byte before it | 32 |
//!
//! Reading checks all of it: the keyed hash first, so a file not written with this cache's
//! secret is a miss before any of it is interpreted.

use nalgebra::Point3;

use super::secret::SECRET_BYTES;
use crate::geometry::{DistanceGrid, Skeleton, SkeletonSegment, TriMesh};

/// The first bytes of every cache file: the marker that a file is the cache's.
pub const MAGIC: &[u8; 8] = b"BALLASTC";

/// The file format and the meaning of its content. Bump it whenever [`DistanceGrid::new`] or
/// [`Skeleton::from_grid`] would give different values for the same input, or stored values
/// change meaning (3: NaN for a node of a deferred block), so files written before are no longer
/// read (and are removed).
pub const FORMAT: u32 = 3;

/// The crate version written into every file: another version's files are misses.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The length of the keyed hash that ends every file.
pub const SEAL_BYTES: usize = 32;

/// What a file must be about: the mesh (a BLAKE3 hash of its coordinates and triangles, and its
/// sizes) and the grid spacing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Key {
    /// BLAKE3 of the mesh.
    pub mesh: [u8; 32],
    /// The spacing's bits.
    pub cell: u64,
    /// The mesh's vertex count.
    pub vertices: u64,
    /// The mesh's triangle count.
    pub triangles: u64,
}

impl Key {
    /// The key of `mesh` at node spacing `cell`.
    pub fn of(mesh: &TriMesh, cell: f64) -> Key {
        let mut hasher = blake3::Hasher::new();
        hasher.update(&(mesh.positions.len() as u64).to_le_bytes());
        for p in &mesh.positions {
            for c in p.iter() {
                hasher.update(&c.to_bits().to_le_bytes());
            }
        }
        hasher.update(&(mesh.triangles.len() as u64).to_le_bytes());
        for triangle in &mesh.triangles {
            for &index in triangle {
                hasher.update(&(index as u64).to_le_bytes());
            }
        }
        Key {
            mesh: *hasher.finalize().as_bytes(),
            cell: cell.to_bits(),
            vertices: mesh.positions.len() as u64,
            triangles: mesh.triangles.len() as u64,
        }
    }

    /// The file name: the mesh hash and the spacing's bits in hexadecimal.
    pub fn file_name(&self) -> String {
        let mesh: String = self.mesh.iter().map(|b| format!("{b:02x}")).collect();
        format!("{mesh}-{:016x}.bin", self.cell)
    }
}

/// The bytes of a cache file, sealed with `secret`.
pub fn encode(
    key: &Key,
    secret: &[u8; SECRET_BYTES],
    grid: &DistanceGrid,
    skeleton: Option<&Skeleton>,
) -> Vec<u8> {
    let mut out = Vec::with_capacity(160 + 8 * grid.stored_values().len());
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT.to_le_bytes());
    out.extend_from_slice(&(VERSION.len() as u32).to_le_bytes());
    out.extend_from_slice(VERSION.as_bytes());
    out.extend_from_slice(&key.mesh);
    for word in [key.cell, key.vertices, key.triangles] {
        put_u64(&mut out, word);
    }
    put_point(&mut out, &grid.origin());
    put_f64(&mut out, grid.cell());
    for n in grid.dims() {
        put_u64(&mut out, n as u64);
    }
    for &value in grid.stored_values() {
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
    let seal = seal(secret, &out);
    out.extend_from_slice(&seal);
    out
}

/// The keyed hash of `body`.
pub fn seal(secret: &[u8; SECRET_BYTES], body: &[u8]) -> [u8; SEAL_BYTES] {
    *blake3::keyed_hash(secret, body).as_bytes()
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

/// The grid and skeleton in `bytes`, or `None` unless the seal is `secret`'s, every check passes
/// and the file is about `key`, which is `mesh`'s (the grid computes its deferred blocks from it).
pub fn decode(
    bytes: &[u8],
    key: &Key,
    secret: &[u8; SECRET_BYTES],
    mesh: &TriMesh,
) -> Option<(DistanceGrid, Option<Skeleton>)> {
    let (body, sealed) = bytes.split_at_checked(bytes.len().checked_sub(SEAL_BYTES)?)?;
    // blake3's `Hash` compares in constant time.
    if blake3::keyed_hash(secret, body) != blake3::Hash::from_bytes(sealed.try_into().ok()?) {
        return None;
    }
    let mut reader = Reader { bytes: body };
    if reader.take(MAGIC.len())? != MAGIC || reader.u32()? != FORMAT {
        return None;
    }
    let version_len = reader.u32()? as usize;
    if reader.take(version_len)? != VERSION.as_bytes() {
        return None;
    }
    let found = Key {
        mesh: reader.take(32)?.try_into().ok()?,
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
    let grid = DistanceGrid::from_parts(origin, cell, dims, values, mesh)?;
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
