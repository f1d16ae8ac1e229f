//! PLY loading (the Stanford polygon format of scans): ASCII and binary, either byte order.
//!
//! Of the elements, `vertex` (its `x`, `y`, `z` properties) and `face` (its `vertex_indices`
//! or `vertex_index` list, polygons fanned into triangles) are read; every other element and
//! property (normals, colours, texture coordinates, edges) is skipped by its declared type.

use nalgebra::Point3;

use super::load::{check_triangles, check_vertices, LoadError, RawMesh};
use super::load_files::MeshLimits;

/// How the body of the file is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Ascii,
    LittleEndian,
    BigEndian,
}

/// A scalar type of the header.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn named(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

/// A property of an element: one scalar, or a list (its count's type and its items' type).
#[derive(Debug, Clone)]
struct Property {
    name: String,
    kind: Kind,
}

#[derive(Debug, Clone, Copy)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// An element of the header: its name, how many, and its properties in order.
#[derive(Debug, Clone)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Reads the numbers of the body, in either encoding.
struct Body<'a> {
    bytes: &'a [u8],
    at: usize,
    encoding: Encoding,
}

impl Body<'_> {
    fn error(&self, what: &str) -> LoadError {
        LoadError::Ply {
            message: format!("the body ends or breaks off while reading {what}"),
        }
    }

    /// The next number, as a float.
    fn number(&mut self, scalar: Scalar, what: &str) -> Result<f64, LoadError> {
        if self.encoding == Encoding::Ascii {
            let rest = &self.bytes[self.at..];
            let start = rest
                .iter()
                .position(|b| !b.is_ascii_whitespace())
                .ok_or_else(|| self.error(what))?;
            let length = rest[start..]
                .iter()
                .position(|b| b.is_ascii_whitespace())
                .unwrap_or(rest.len() - start);
            let word = &rest[start..start + length];
            self.at += start + length;
            return std::str::from_utf8(word)
                .ok()
                .and_then(|w| w.parse::<f64>().ok())
                .ok_or_else(|| LoadError::Ply {
                    message: format!(
                        "`{}` is not a number (in {what})",
                        String::from_utf8_lossy(word)
                    ),
                });
        }
        let size = scalar.size();
        let bytes = self
            .bytes
            .get(self.at..self.at + size)
            .ok_or_else(|| self.error(what))?;
        self.at += size;
        let mut word = [0u8; 8];
        word[..size].copy_from_slice(bytes);
        if self.encoding == Encoding::BigEndian {
            word[..size].reverse();
        }
        let [a, b, c, d, ..] = word;
        Ok(match scalar {
            Scalar::I8 => f64::from(a as i8),
            Scalar::U8 => f64::from(a),
            Scalar::I16 => f64::from(i16::from_le_bytes([a, b])),
            Scalar::U16 => f64::from(u16::from_le_bytes([a, b])),
            Scalar::I32 => f64::from(i32::from_le_bytes([a, b, c, d])),
            Scalar::U32 => f64::from(u32::from_le_bytes([a, b, c, d])),
            Scalar::F32 => f64::from(f32::from_le_bytes([a, b, c, d])),
            Scalar::F64 => f64::from_le_bytes(word),
        })
    }
}

/// Parses PLY file `bytes` into positions and triangles, within `limits`.
pub(crate) fn parse_ply(bytes: &[u8], limits: &MeshLimits) -> Result<RawMesh, LoadError> {
    let error = |message: String| LoadError::Ply { message };
    let end = find(bytes, b"end_header")
        .ok_or_else(|| error("no `end_header` line: not a PLY file".to_string()))?;
    let header = std::str::from_utf8(&bytes[..end])
        .map_err(|_| error("the header is not text".to_string()))?;
    // The body starts after the end of the `end_header` line.
    let body_start = bytes[end..]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(bytes.len(), |n| end + n + 1);
    let mut lines = header.lines().map(str::trim);
    if lines.next() != Some("ply") {
        return Err(error("the file does not begin with `ply`".to_string()));
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    for line in lines {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["format", format, _version] => {
                encoding = Some(match *format {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::LittleEndian,
                    "binary_big_endian" => Encoding::BigEndian,
                    other => return Err(error(format!("unknown format `{other}`"))),
                });
            }
            ["element", name, count] => {
                let count = count
                    .parse()
                    .map_err(|_| error(format!("element `{name}` has count `{count}`")))?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            ["property", "list", count, item, name] => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| error("a property before any element".to_string()))?;
                let (Some(count), Some(item)) = (Scalar::named(count), Scalar::named(item)) else {
                    return Err(error(format!("property `{name}` has an unknown type")));
                };
                element.properties.push(Property {
                    name: name.to_string(),
                    kind: Kind::List { count, item },
                });
            }
            ["property", scalar, name] => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| error("a property before any element".to_string()))?;
                let scalar = Scalar::named(scalar).ok_or_else(|| {
                    error(format!("property `{name}` has unknown type `{scalar}`"))
                })?;
                element.properties.push(Property {
                    name: name.to_string(),
                    kind: Kind::Scalar(scalar),
                });
            }
            [] | ["comment", ..] | ["obj_info", ..] => {}
            _ => return Err(error(format!("unknown header line `{line}`"))),
        }
    }
    let encoding = encoding.ok_or_else(|| error("no `format` line".to_string()))?;
    let mut body = Body {
        bytes,
        at: body_start,
        encoding,
    };
    let mut raw = RawMesh {
        positions: Vec::new(),
        triangles: Vec::new(),
    };
    for element in &elements {
        match element.name.as_str() {
            "vertex" => {
                check_vertices(element.count, limits)?;
                let axis = |name: &str| element.properties.iter().position(|p| p.name == name);
                let (Some(x), Some(y), Some(z)) = (axis("x"), axis("y"), axis("z")) else {
                    return Err(error("the vertices have no x, y and z".to_string()));
                };
                raw.positions.reserve(element.count);
                let mut values = vec![0.0; element.properties.len()];
                for _ in 0..element.count {
                    for (value, property) in values.iter_mut().zip(&element.properties) {
                        *value = read_property(&mut body, property, "a vertex")?.unwrap_or(0.0);
                    }
                    raw.positions
                        .push(Point3::new(values[x], values[y], values[z]));
                }
            }
            "face" => {
                let list = element.properties.iter().position(|p| {
                    matches!(p.kind, Kind::List { .. })
                        && matches!(p.name.as_str(), "vertex_indices" | "vertex_index")
                });
                let Some(list) = list else {
                    return Err(error("the faces have no vertex_indices list".to_string()));
                };
                let count = raw.positions.len();
                for face in 0..element.count {
                    for (k, property) in element.properties.iter().enumerate() {
                        if k != list {
                            read_property(&mut body, property, "a face")?;
                            continue;
                        }
                        let Kind::List {
                            count: counted,
                            item,
                        } = property.kind
                        else {
                            continue;
                        };
                        let corners = body.number(counted, "a face")?;
                        if !(0.0..=1e6).contains(&corners) {
                            return Err(error(format!("face {face} has {corners} corners")));
                        }
                        let mut indices = Vec::with_capacity(corners as usize);
                        for _ in 0..corners as usize {
                            let index = body.number(item, "a face")?;
                            if !(index >= 0.0 && index < count as f64 && index.fract() == 0.0) {
                                return Err(error(format!(
                                    "face {face} refers to vertex {index} of {count}"
                                )));
                            }
                            indices.push(index as u32);
                        }
                        for i in 1..indices.len().saturating_sub(1) {
                            raw.triangles.push([indices[0], indices[i], indices[i + 1]]);
                        }
                        check_triangles(raw.triangles.len(), limits)?;
                    }
                }
            }
            _ => {
                for _ in 0..element.count {
                    for property in &element.properties {
                        read_property(&mut body, property, &element.name)?;
                    }
                }
            }
        }
    }
    Ok(raw)
}

/// Reads one property: a scalar's value, or a list skipped (`None`).
fn read_property(
    body: &mut Body,
    property: &Property,
    what: &str,
) -> Result<Option<f64>, LoadError> {
    match property.kind {
        Kind::Scalar(scalar) => body.number(scalar, what).map(Some),
        Kind::List { count, item } => {
            let n = body.number(count, what)?;
            if !(0.0..=1e6).contains(&n) {
                return Err(LoadError::Ply {
                    message: format!("a list of {n} items in {what}"),
                });
            }
            for _ in 0..n as usize {
                body.number(item, what)?;
            }
            Ok(None)
        }
    }
}

/// Where `needle` first occurs in `haystack`.
fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack
        .windows(needle.len())
        .position(|window| window == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE_ASCII: &str = "ply\nformat ascii 1.0\ncomment a unit square, two ways\n\
        element vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
        property uchar red\nelement face 1\nproperty list uchar int vertex_indices\n\
        end_header\n0 0 0 255\n1 0 0 0\n1 1 0 0\n0 1 0 0\n4 0 1 2 3\n";

    #[test]
    fn ascii_polygons_are_fanned_and_other_properties_skipped() {
        let raw = parse_ply(SQUARE_ASCII.as_bytes(), &MeshLimits::default()).unwrap();
        assert_eq!(raw.positions[2], Point3::new(1.0, 1.0, 0.0));
        assert_eq!(raw.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn binary_files_of_either_byte_order_read_alike() {
        for (format, big) in [("binary_little_endian", false), ("binary_big_endian", true)] {
            let mut bytes = format!(
                "ply\nformat {format} 1.0\nelement vertex 3\nproperty double x\n\
                 property double y\nproperty double z\nelement face 1\n\
                 property list uchar uint vertex_indices\nend_header\n"
            )
            .into_bytes();
            for v in [[0.0f64, 0.0, 0.0], [2.5, 0.0, 0.0], [0.0, 1.0, -3.0]] {
                for c in v {
                    let word = if big {
                        c.to_be_bytes()
                    } else {
                        c.to_le_bytes()
                    };
                    bytes.extend_from_slice(&word);
                }
            }
            bytes.push(3);
            for i in [0u32, 1, 2] {
                let word = if big {
                    i.to_be_bytes()
                } else {
                    i.to_le_bytes()
                };
                bytes.extend_from_slice(&word);
            }
            let raw = parse_ply(&bytes, &MeshLimits::default()).unwrap();
            assert_eq!(raw.positions[2], Point3::new(0.0, 1.0, -3.0), "{format}");
            assert_eq!(raw.triangles, vec![[0, 1, 2]], "{format}");
        }
    }

    #[test]
    fn broken_files_are_errors() {
        let limits = MeshLimits::default();
        let cut = &SQUARE_ASCII[..SQUARE_ASCII.len() - 4];
        assert!(parse_ply(cut.as_bytes(), &limits).is_err());
        let out_of_range = SQUARE_ASCII.replace("4 0 1 2 3", "3 0 1 7");
        let message = parse_ply(out_of_range.as_bytes(), &limits)
            .err()
            .unwrap()
            .to_string();
        assert!(message.contains("vertex 7 of 4"), "{message}");
        assert!(parse_ply(b"solid x\n", &limits).is_err());
        let too_many = MeshLimits {
            max_triangles: 1,
            ..MeshLimits::default()
        };
        assert!(matches!(
            parse_ply(SQUARE_ASCII.as_bytes(), &too_many),
            Err(LoadError::TooMany { .. })
        ));
    }
}
