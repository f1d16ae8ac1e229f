//! Binary STL: the part's solid ([`solid_mesh`]) as one triangle soup in bed coordinates.
//!
//! Written by hand (80-byte header, count, 50 bytes per triangle): the format is a dozen lines
//! and needs no crate.

use super::{solid_mesh, BedPart};

/// The binary STL of `part`: the outer surface and each void as an inward-facing shell, mm.
pub fn write_stl(part: &BedPart) -> Vec<u8> {
    let mesh = solid_mesh(part);
    let mut bytes = Vec::with_capacity(84 + 50 * mesh.triangles.len());
    // A binary header must not start with "solid", which marks ASCII STL.
    let mut header = format!("ballast part {}", part.name).into_bytes();
    header.resize(80, b' ');
    bytes.extend_from_slice(&header);
    let count = u32::try_from(mesh.triangles.len()).expect("fewer than 2^32 triangles");
    bytes.extend_from_slice(&count.to_le_bytes());
    for triangle in &mesh.triangles {
        let [a, b, c] = triangle.map(|i| mesh.positions[i as usize]);
        let normal = (b - a).cross(&(c - a));
        let normal = normal.try_normalize(0.0).unwrap_or(normal);
        for value in normal
            .iter()
            .chain(a.coords.iter())
            .chain(b.coords.iter())
            .chain(c.coords.iter())
        {
            bytes.extend_from_slice(&(*value as f32).to_le_bytes());
        }
        bytes.extend_from_slice(&0u16.to_le_bytes());
    }
    bytes
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::super::test_parts::{box_with_two_capsules, capsule_volume};
    use super::*;

    /// The triangles of a binary STL, each vertex as its three `f32` bit patterns.
    fn read(bytes: &[u8]) -> Vec<[[u32; 3]; 3]> {
        let count = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
        assert_eq!(bytes.len(), 84 + 50 * count);
        (0..count)
            .map(|t| {
                let at = |k: usize| {
                    let o = 84 + 50 * t + 4 * k;
                    u32::from_le_bytes(bytes[o..o + 4].try_into().unwrap())
                };
                [0, 1, 2].map(|v| [0, 1, 2].map(|k| at(3 + 3 * v + k)))
            })
            .collect()
    }

    #[test]
    fn the_stl_is_closed_consistently_oriented_and_holds_body_minus_voids() {
        let part = box_with_two_capsules();
        let bytes = write_stl(&part);
        assert!(!bytes.starts_with(b"solid"));
        let triangles = read(&bytes);

        // Vertices welded by their exact bits: every directed edge once, its reverse once.
        let mut edges = BTreeMap::new();
        for t in &triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "edge {a:?}-{b:?} used {n} times");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a:?}-{b:?} has no twin");
        }

        // Divergence theorem over the file's own numbers.
        let volume: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| {
                    nalgebra::Vector3::from(v.map(|bits| f64::from(f32::from_bits(bits))))
                });
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum();
        let voids: f64 = part.voids.iter().map(capsule_volume).sum();
        let expected = 40.0 * 30.0 * 20.0 - voids;
        // The tessellated capsules are inscribed: a little smaller than the true ones.
        assert!(
            (volume - expected).abs() < 0.02 * voids,
            "volume {volume} vs {expected} (voids {voids})"
        );
        assert!(
            volume > expected,
            "inscribed voids remove less than the true ones"
        );
    }

    #[test]
    fn the_stl_is_deterministic_and_names_the_part() {
        let part = box_with_two_capsules();
        let bytes = write_stl(&part);
        assert_eq!(bytes, write_stl(&part));
        assert!(bytes.starts_with(b"ballast part block "));
        // Each normal is the unit normal of its triangle's winding.
        let first = &bytes[84..84 + 48];
        let f = |k: usize| f32::from_le_bytes(first[4 * k..4 * k + 4].try_into().unwrap());
        let normal = nalgebra::Vector3::new(f(0), f(1), f(2));
        assert!((normal.norm() - 1.0).abs() < 1e-6);
    }
}
