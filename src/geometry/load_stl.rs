//! STL loading, binary and ASCII.
//!
//! A file is binary when its length is exactly what the triangle count in its header says
//! (84 bytes of header and count, then 50 bytes a triangle), whatever its first bytes: many
//! binary files begin their 80-byte header with `solid`, the word an ASCII file starts with.
//! Any other file is read as ASCII. The facet normals are ignored: a triangle's orientation is
//! the order of its corners, as in every other format read here.

use nalgebra::Point3;

use super::load::{check_triangles, LoadError, MeshSelector, RawMesh};
use super::load_files::MeshLimits;

/// Bytes before the first binary triangle: the header and the triangle count.
const BINARY_HEADER: usize = 84;
/// Bytes of one binary triangle: normal, three corners (twelve `f32`) and an attribute word.
const BINARY_TRIANGLE: usize = 50;

/// One `solid … endsolid` block of an ASCII file (the whole file, unnamed, for a binary one).
pub(crate) struct Solid {
    /// The name after `solid`, trimmed; empty when there is none.
    pub name: String,
    /// Three corners per triangle, in file order.
    pub corners: Vec<Point3<f64>>,
}

/// The solids of STL file `bytes`, each triangle's corners as written, within `limits`.
pub(crate) fn parse_stl(bytes: &[u8], limits: &MeshLimits) -> Result<Vec<Solid>, LoadError> {
    if let Some(count) = binary_count(bytes) {
        check_triangles(count, limits)?;
        let corners = bytes[BINARY_HEADER..]
            .chunks_exact(BINARY_TRIANGLE)
            .flat_map(|triangle| {
                (0..3).map(move |corner| {
                    let at = 12 + 12 * corner;
                    let coordinate = |axis: usize| {
                        let start = at + 4 * axis;
                        let word = [
                            triangle[start],
                            triangle[start + 1],
                            triangle[start + 2],
                            triangle[start + 3],
                        ];
                        f64::from(f32::from_le_bytes(word))
                    };
                    Point3::new(coordinate(0), coordinate(1), coordinate(2))
                })
            })
            .collect();
        return Ok(vec![Solid {
            name: String::new(),
            corners,
        }]);
    }
    parse_ascii(bytes, limits)
}

/// The triangle count of a binary file whose length matches it; `None` for any other file.
fn binary_count(bytes: &[u8]) -> Option<usize> {
    let count = bytes.get(80..BINARY_HEADER)?;
    let count = u32::from_le_bytes([count[0], count[1], count[2], count[3]]) as usize;
    let expected = count
        .checked_mul(BINARY_TRIANGLE)?
        .checked_add(BINARY_HEADER)?;
    (expected == bytes.len()).then_some(count)
}

/// The solids of an ASCII file: `solid NAME`, then `facet … outer loop`, three `vertex X Y Z`,
/// `endloop`, `endfacet` per triangle, then `endsolid`. Words are matched case-insensitively;
/// a missing `endsolid` at the end of the file is tolerated, as slicers do.
fn parse_ascii(bytes: &[u8], limits: &MeshLimits) -> Result<Vec<Solid>, LoadError> {
    let text = std::str::from_utf8(bytes).map_err(|e| LoadError::Stl {
        message: format!(
            "neither a binary STL (its length is not the 84 + 50 × {} bytes its header promises) \
             nor ASCII text (invalid byte at offset {})",
            binary_promise(bytes).map_or_else(|| "n".to_string(), |n| n.to_string()),
            e.valid_up_to()
        ),
    })?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut solids: Vec<Solid> = Vec::new();
    let mut open: Option<Solid> = None;
    // Corners of the facet being read.
    let mut facet: Vec<Point3<f64>> = Vec::with_capacity(3);
    let mut triangles = 0usize;
    let error = |line: usize, message: String| LoadError::Stl {
        message: format!("line {line}: {message}"),
    };
    for (number, line) in text.lines().enumerate() {
        let line_number = number + 1;
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        match keyword.to_ascii_lowercase().as_str() {
            "solid" => {
                if open.is_some() {
                    return Err(error(
                        line_number,
                        "`solid` before the `endsolid` of the one above".to_string(),
                    ));
                }
                let name = line.trim_start()[keyword.len()..].trim().to_string();
                open = Some(Solid {
                    name,
                    corners: Vec::new(),
                });
            }
            "endsolid" => match open.take() {
                Some(solid) => solids.push(solid),
                None => {
                    return Err(error(
                        line_number,
                        "`endsolid` without a `solid`".to_string(),
                    ))
                }
            },
            "facet" => facet.clear(),
            "outer" | "endloop" => {}
            "vertex" => {
                let coordinates: Vec<&str> = words.collect();
                let parsed: Option<Vec<f64>> =
                    coordinates.iter().map(|word| word.parse().ok()).collect();
                match parsed.as_deref() {
                    Some(&[x, y, z]) => facet.push(Point3::new(x, y, z)),
                    _ => {
                        return Err(error(
                            line_number,
                            format!("`{}` is not a vertex of three numbers", line.trim()),
                        ))
                    }
                }
            }
            "endfacet" => {
                let Some(solid) = open.as_mut() else {
                    return Err(error(
                        line_number,
                        "a facet outside any `solid`".to_string(),
                    ));
                };
                if facet.len() != 3 {
                    return Err(error(
                        line_number,
                        format!("a facet has {} vertices, not 3", facet.len()),
                    ));
                }
                triangles += 1;
                check_triangles(triangles, limits)?;
                solid.corners.append(&mut facet);
            }
            _ => {
                return Err(error(
                    line_number,
                    format!("`{keyword}` is not a word of an ASCII STL file"),
                ))
            }
        }
    }
    solids.extend(open);
    if solids.is_empty() {
        return Err(LoadError::Stl {
            message: "no `solid` in the file".to_string(),
        });
    }
    Ok(solids)
}

/// The triangle count a binary header states, when the file is long enough to hold one.
fn binary_promise(bytes: &[u8]) -> Option<u32> {
    let count = bytes.get(80..BINARY_HEADER)?;
    Some(u32::from_le_bytes([count[0], count[1], count[2], count[3]]))
}

/// The part of `solids` that `selector` picks: every solid, or those with the name asked for
/// (merged), as positions and triangles (three new corners each, welded later).
pub(crate) fn select(solids: &[Solid], selector: &MeshSelector) -> Result<RawMesh, LoadError> {
    let wanted = selector.part_name();
    if let Some(name) = wanted {
        if !solids.iter().any(|solid| solid.name == name) {
            let mut available: Vec<String> = solids
                .iter()
                .map(|solid| solid.name.clone())
                .filter(|name| !name.is_empty())
                .collect();
            available.sort();
            available.dedup();
            return Err(LoadError::UnknownPart {
                name: name.to_string(),
                available,
            });
        }
    }
    let positions: Vec<Point3<f64>> = solids
        .iter()
        .filter(|solid| wanted.is_none_or(|name| solid.name == name))
        .flat_map(|solid| solid.corners.iter().copied())
        .collect();
    let count = u32::try_from(positions.len()).map_err(|_| LoadError::Stl {
        message: "too many vertices for 32-bit indices".to_string(),
    })?;
    let triangles = (0..count / 3)
        .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
        .collect();
    Ok(RawMesh {
        positions,
        triangles,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binary(triangles: &[[[f32; 3]; 3]], header: &[u8]) -> Vec<u8> {
        let mut bytes = vec![b' '; 80];
        bytes[..header.len()].copy_from_slice(header);
        bytes.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
        for triangle in triangles {
            bytes.extend_from_slice(&[0u8; 12]);
            for corner in triangle {
                for c in corner {
                    bytes.extend_from_slice(&c.to_le_bytes());
                }
            }
            bytes.extend_from_slice(&[0u8; 2]);
        }
        bytes
    }

    const TRIANGLE: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.5, 0.0]];

    #[test]
    fn a_binary_file_whose_header_starts_with_solid_is_read_as_binary() {
        let bytes = binary(&[TRIANGLE, TRIANGLE], b"solid made by a CAD program");
        let solids = parse_stl(&bytes, &MeshLimits::default()).unwrap();
        assert_eq!(solids.len(), 1);
        assert_eq!(solids[0].corners.len(), 6);
        assert_eq!(solids[0].corners[2], Point3::new(0.0, 1.5, 0.0));
    }

    #[test]
    fn ascii_solids_are_named_and_selected() {
        let text = "solid left\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid left\nSOLID right\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 2 0 0\nVERTEX 3 0 0\nVERTEX 2 1 0e0\nENDLOOP\nENDFACET\n";
        let solids = parse_stl(text.as_bytes(), &MeshLimits::default()).unwrap();
        let names: Vec<&str> = solids.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["left", "right"]);
        let right = select(&solids, &MeshSelector::ObjObject("right".into())).unwrap();
        assert_eq!(right.positions[0], Point3::new(2.0, 0.0, 0.0));
        assert_eq!(right.triangles, vec![[0, 1, 2]]);
        let whole = select(&solids, &MeshSelector::Whole).unwrap();
        assert_eq!(whole.triangles.len(), 2);
        match select(&solids, &MeshSelector::ObjObject("middle".into())) {
            Err(LoadError::UnknownPart { available, .. }) => {
                assert_eq!(available, ["left", "right"])
            }
            other => panic!("expected an unknown part, got {:?}", other.err()),
        }
    }

    #[test]
    fn broken_files_are_errors_with_the_line() {
        let limits = MeshLimits::default();
        let two_corners = "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid a\n";
        let message = parse_stl(two_corners.as_bytes(), &limits)
            .err()
            .unwrap()
            .to_string();
        assert!(
            message.contains("line 7") && message.contains("2 vertices"),
            "{message}"
        );
        let bad_number = "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 x\n";
        let message = parse_stl(bad_number.as_bytes(), &limits)
            .err()
            .unwrap()
            .to_string();
        assert!(message.contains("line 4"), "{message}");
        // A binary file cut short is not ASCII either.
        let mut cut = binary(&[TRIANGLE, TRIANGLE], b"");
        cut.truncate(cut.len() - 7);
        cut[90] = 0xff;
        let message = parse_stl(&cut, &limits).err().unwrap().to_string();
        assert!(message.contains("84 + 50 × 2"), "{message}");
        assert!(parse_stl(b"", &limits).is_err());
    }

    #[test]
    fn the_triangle_limit_holds_before_reading() {
        let limits = MeshLimits {
            max_triangles: 1,
            ..MeshLimits::default()
        };
        let bytes = binary(&[TRIANGLE, TRIANGLE], b"");
        assert!(matches!(
            parse_stl(&bytes, &limits),
            Err(LoadError::TooMany { .. })
        ));
    }
}
