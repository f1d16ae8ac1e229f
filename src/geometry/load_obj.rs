//! Wavefront OBJ loading (via `tobj`).

use std::collections::BTreeSet;
use std::io::Cursor;

use nalgebra::Point3;

use super::load::{check_triangles, check_vertices, index_u32, LoadError, MeshSelector, RawMesh};
use super::load_files::MeshLimits;

/// Parses OBJ text into positions and triangles (polygons fanned into triangles).
///
/// Topology is on positions only: texture-coordinate and normal indices are discarded before
/// parsing, so UV or normal seams do not split vertices, and a malformed `vt`/`vn` reference can
/// not fail the load. Material libraries are never read. `p` and `l` elements are ignored.
///
/// `Whole` merges every object; a name selector merges every object (or group) with that name.
/// A leading byte-order mark is skipped. Faces with fewer than three vertices are left out; their
/// 1-based line numbers are returned beside the mesh. The vertex and triangle counts are checked
/// against `limits` before the text is parsed.
pub(crate) fn parse_obj(
    bytes: &[u8],
    selector: &MeshSelector,
    limits: &MeshLimits,
) -> Result<(RawMesh, Vec<usize>), LoadError> {
    let text = std::str::from_utf8(bytes).map_err(|e| LoadError::Obj {
        message: format!(
            "not UTF-8 text (invalid byte at offset {})",
            e.valid_up_to()
        ),
    })?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let Cleaned {
        text: cleaned,
        short_faces,
    } = positions_only(text, limits)?;
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _materials) = tobj::load_obj_buf(&mut Cursor::new(cleaned), &options, |_| {
        Ok(Default::default())
    })
    .map_err(|e| LoadError::Obj {
        message: e.to_string(),
    })?;

    let wanted = selector.part_name();
    if let Some(name) = wanted {
        if !models.iter().any(|m| m.name == name) {
            let available: BTreeSet<String> = models.iter().map(|m| m.name.clone()).collect();
            return Err(LoadError::UnknownPart {
                name: name.to_string(),
                available: available.into_iter().collect(),
            });
        }
    }

    let too_many = || LoadError::Obj {
        message: "too many vertices for 32-bit indices".to_string(),
    };
    let mut raw = RawMesh {
        positions: Vec::new(),
        triangles: Vec::new(),
    };
    for model in models.iter().filter(|m| wanted.is_none_or(|n| m.name == n)) {
        let mesh = &model.mesh;
        let offset = index_u32(raw.positions.len(), too_many)?;
        let count = index_u32(mesh.positions.len() / 3, too_many)?;
        offset.checked_add(count).ok_or_else(too_many)?;
        raw.positions.extend(
            mesh.positions
                .chunks_exact(3)
                .map(|c| Point3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2]))),
        );
        if mesh.indices.len() % 3 != 0 {
            return Err(LoadError::Obj {
                message: format!("object `{}` has an incomplete triangle", model.name),
            });
        }
        for t in mesh.indices.chunks_exact(3) {
            if let Some(&bad) = t.iter().find(|&&i| i >= count) {
                return Err(LoadError::Obj {
                    message: format!("object `{}` refers to vertex {bad} of {count}", model.name),
                });
            }
            raw.triangles
                .push([t[0] + offset, t[1] + offset, t[2] + offset]);
        }
    }
    Ok((raw, short_faces))
}

/// OBJ text cut down for `tobj`, and the faces left out.
struct Cleaned {
    text: String,
    /// 1-based line numbers of the faces with fewer than three vertices.
    short_faces: Vec<usize>,
}

/// Rewrites OBJ text so that `tobj` sees positions, faces and object/group names only: `vt` and
/// `vn` lines are dropped, each face corner `v/vt/vn` is cut down to `v`, and faces with fewer than
/// three corners are dropped (and listed). Fails when the vertices or the triangles the faces fan
/// into pass `limits`.
fn positions_only(text: &str, limits: &MeshLimits) -> Result<Cleaned, LoadError> {
    let mut out = String::with_capacity(text.len());
    let mut short_faces = Vec::new();
    let (mut vertices, mut triangles) = (0usize, 0usize);
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("vt") | Some("vn") | Some("mtllib") | Some("usemtl") => continue,
            Some("f") => {
                let corners: Vec<&str> = words.collect();
                if corners.len() < 3 {
                    short_faces.push(number + 1);
                    continue;
                }
                triangles += corners.len() - 2;
                check_triangles(triangles, limits)?;
                out.push('f');
                for corner in corners {
                    let v = corner.split('/').next().unwrap_or_default();
                    if v.is_empty() {
                        return Err(LoadError::Obj {
                            message: format!(
                                "line {}: face corner `{corner}` has no vertex index",
                                number + 1
                            ),
                        });
                    }
                    out.push(' ');
                    out.push_str(v);
                }
            }
            Some("v") => {
                vertices += 1;
                check_vertices(vertices, limits)?;
                out.push_str(line);
            }
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    Ok(Cleaned {
        text: out,
        short_faces,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str, selector: &MeshSelector) -> Result<RawMesh, LoadError> {
        parse_obj(text.as_bytes(), selector, &MeshLimits::default()).map(|(raw, _)| raw)
    }

    const TWO_OBJECTS: &str = "\
o first
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
vt 0 0
vn 0 0 1
f 1/1/1 2/1/1 3/1/1
f 1//1 4//1 2//1
o second
v 5 5 5
v 6 5 5
v 5 6 5
v 6 6 5
f -4 -3 -2 -1
";

    #[test]
    fn whole_merges_objects_and_fans_quads() {
        let raw = parse(TWO_OBJECTS, &MeshSelector::Whole).unwrap();
        assert_eq!(raw.positions.len(), 8);
        assert_eq!(
            raw.triangles,
            vec![[0, 1, 2], [0, 3, 1], [4, 5, 6], [4, 6, 7]]
        );
    }

    #[test]
    fn selects_object_by_name() {
        let raw = parse(TWO_OBJECTS, &MeshSelector::ObjObject("second".into())).unwrap();
        assert_eq!(raw.positions[0], Point3::new(5.0, 5.0, 5.0));
        assert_eq!(raw.triangles.len(), 2);
    }

    #[test]
    fn unknown_object_lists_names() {
        match parse(TWO_OBJECTS, &MeshSelector::ObjObject("third".into())) {
            Err(LoadError::UnknownPart { name, available }) => {
                assert_eq!(name, "third");
                assert_eq!(available, vec!["first".to_string(), "second".to_string()]);
            }
            other => panic!("expected UnknownPart, got {:?}", other.map(|r| r.triangles)),
        }
    }

    #[test]
    fn bad_indices_are_errors_not_panics() {
        for text in [
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf /1 /2 /3\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n",
            "v 0 0\n",
            "v 0 0 0 0\n",
        ] {
            assert!(parse(text, &MeshSelector::Whole).is_err(), "{text:?}");
        }
    }

    #[test]
    fn texture_and_normal_indices_are_ignored() {
        // Out-of-range `vt`/`vn` references do not matter: only positions are kept.
        for text in [
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/0/0 2/0/0 3/0/0\n",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-9 2/-9 3/99\n",
        ] {
            let raw = parse(text, &MeshSelector::Whole).unwrap();
            assert_eq!(raw.triangles, vec![[0, 1, 2]], "{text:?}");
        }
    }

    #[test]
    fn garbage_bytes_are_errors() {
        assert!(parse_obj(
            &[0xff, 0xfe, 0x00, 0x80],
            &MeshSelector::Whole,
            &MeshLimits::default()
        )
        .is_err());
    }

    #[test]
    fn missing_material_library_is_fine() {
        let text = "mtllib nowhere.mtl\nusemtl skin\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        assert_eq!(
            parse(text, &MeshSelector::Whole).unwrap().triangles.len(),
            1
        );
    }

    #[test]
    fn a_byte_order_mark_is_skipped() {
        let raw = parse(
            "\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            &MeshSelector::Whole,
        )
        .unwrap();
        assert_eq!(raw.positions.len(), 3);
        assert_eq!(raw.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn short_faces_are_left_out_and_listed() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nf 1 2 3\nf 3\nf\n";
        let (raw, short) = parse_obj(
            text.as_bytes(),
            &MeshSelector::Whole,
            &MeshLimits::default(),
        )
        .unwrap();
        assert_eq!(raw.triangles, vec![[0, 1, 2]]);
        assert_eq!(short, vec![4, 6, 7]);
    }

    #[test]
    fn counts_past_the_limits_are_refused_before_parsing() {
        let limits = MeshLimits {
            max_triangles: 2,
            ..MeshLimits::default()
        };
        let quads = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 3 4\n";
        assert!(matches!(
            parse_obj(quads.as_bytes(), &MeshSelector::Whole, &limits),
            Err(LoadError::TooMany {
                what: "triangles",
                limit: 2
            })
        ));
        let points = "v 0 0 0\n".repeat(7);
        assert!(matches!(
            parse_obj(points.as_bytes(), &MeshSelector::Whole, &limits),
            Err(LoadError::TooMany {
                what: "vertices",
                limit: 6
            })
        ));
    }
}
