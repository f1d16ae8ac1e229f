//! 3MF loading: the core specification's objects, components and build items, and the
//! production extension's references to objects in other model parts of the archive (how
//! Bambu Studio and OrcaSlicer store their objects).
//!
//! The mesh is every `model` object the build places (or the build items whose object has the
//! name asked for), each with its build transform and the transforms of the components on the
//! way down, in millimetres: the root model's `unit` is honoured by scaling every coordinate
//! into millimetres as it is read. Objects of another type (`support`, `solidsupport`,
//! `surface`, `other`) are not part of the printed solid and are left out. Colours, materials,
//! slicer settings and thumbnails are not read.

use std::collections::{BTreeSet, HashMap, HashSet};
use std::io::{Cursor, Read};
use std::path::PathBuf;

use nalgebra::{Matrix4, Point3, Vector4};
use quick_xml::events::{BytesStart, Event};
use quick_xml::XmlVersion;

use super::load::{check_triangles, check_vertices, LoadError, MeshSelector, RawMesh};
use super::load_files::MeshLimits;

/// The relationship type of the root model part (3MF core specification).
const MODEL_RELATIONSHIP: &str = "http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel";
/// Where the root model part is when the package's relationships do not say.
const DEFAULT_MODEL: &str = "3D/3dmodel.model";
/// Components nested deeper than this are refused (the specification forbids cycles; this
/// bounds a file that has one anyway).
const MAX_DEPTH: usize = 32;

/// A 3MF package, its model parts parsed.
pub(crate) struct Package {
    /// Millimetres per unit of the root model.
    millimetres: f64,
    /// The root model part's name in the archive.
    root: String,
    /// Every model part read, by its name in the archive (no leading slash).
    parts: HashMap<String, ModelPart>,
}

/// One model part: its objects by id, and its build items (the root part's only count).
#[derive(Default)]
struct ModelPart {
    objects: HashMap<u64, Object>,
    items: Vec<Reference>,
}

/// An object of a model part.
#[derive(Default)]
struct Object {
    name: Option<String>,
    /// Whether its type is `model` (the default): part of the printed solid.
    printed: bool,
    positions: Vec<Point3<f64>>,
    triangles: Vec<[u32; 3]>,
    components: Vec<Reference>,
}

/// A build item or a component: an object (in `part`, or the referring part when `None`) and
/// the transform that places it.
struct Reference {
    object: u64,
    part: Option<String>,
    transform: Matrix4<f64>,
}

impl Package {
    /// Opens the 3MF archive `bytes`, reading its model parts within `limits` (the bytes they
    /// inflate to count against [`MeshLimits::max_bytes`]).
    pub(crate) fn open(bytes: &[u8], limits: &MeshLimits) -> Result<Package, LoadError> {
        let mut archive =
            zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| LoadError::ThreeMf {
                message: format!("not a 3MF archive (a ZIP file): {e}"),
            })?;
        let mut budget = limits.max_bytes;
        let root = root_part(&mut archive, &mut budget)?;
        let mut parts = HashMap::new();
        let mut waiting = vec![root.clone()];
        let mut seen = HashSet::new();
        let mut millimetres = 1.0;
        while let Some(name) = waiting.pop() {
            if !seen.insert(name.clone()) {
                continue;
            }
            let text = read_member(&mut archive, &name, &mut budget)?;
            let (part, unit) = parse_model(&text, &name, limits)?;
            if name == root {
                millimetres = unit;
            }
            let referred = part
                .items
                .iter()
                .chain(part.objects.values().flat_map(|o| &o.components))
                .filter_map(|reference| reference.part.clone());
            waiting.extend(referred);
            parts.insert(name, part);
        }
        Ok(Package {
            millimetres,
            root,
            parts,
        })
    }

    /// The mesh `selector` picks: every build item, or the build items whose object has the
    /// name asked for, in millimetres.
    pub(crate) fn part(
        &self,
        selector: &MeshSelector,
        limits: &MeshLimits,
    ) -> Result<RawMesh, LoadError> {
        let root = &self.parts[&self.root];
        // A build item of an object that is not printed (a support) has no name to select.
        let name_of = |item: &Reference| {
            self.object(item, &self.root)
                .ok()
                .filter(|(object, _)| object.printed)
                .and_then(|(object, _)| object.name.clone())
        };
        let wanted = selector.part_name();
        let items: Vec<&Reference> = root
            .items
            .iter()
            .filter(|item| wanted.is_none_or(|name| name_of(item).as_deref() == Some(name)))
            .collect();
        if let Some(name) = wanted {
            if items.is_empty() {
                let available: BTreeSet<String> = root.items.iter().filter_map(name_of).collect();
                return Err(LoadError::UnknownPart {
                    name: name.to_string(),
                    available: available.into_iter().collect(),
                });
            }
        }
        let mut mesh = RawMesh {
            positions: Vec::new(),
            triangles: Vec::new(),
        };
        let unit = Matrix4::new_scaling(self.millimetres);
        for item in items {
            self.place(
                item,
                &self.root,
                unit * item.transform,
                0,
                &mut mesh,
                limits,
            )?;
        }
        Ok(mesh)
    }

    /// The object `reference` names, and the part it is in (`from` when it names none).
    fn object<'a>(
        &'a self,
        reference: &'a Reference,
        from: &'a str,
    ) -> Result<(&'a Object, &'a str), LoadError> {
        let part_name = reference.part.as_deref().unwrap_or(from);
        self.parts
            .get(part_name)
            .and_then(|part| part.objects.get(&reference.object))
            .map(|object| (object, part_name))
            .ok_or_else(|| LoadError::ThreeMf {
                message: format!(
                    "`{part_name}` has no object {} (a build item or component refers to it)",
                    reference.object
                ),
            })
    }

    /// Appends the object `reference` names, and its components, placed by `transform`.
    fn place(
        &self,
        reference: &Reference,
        from: &str,
        transform: Matrix4<f64>,
        depth: usize,
        mesh: &mut RawMesh,
        limits: &MeshLimits,
    ) -> Result<(), LoadError> {
        if depth > MAX_DEPTH {
            return Err(LoadError::ThreeMf {
                message: format!("components nest more than {MAX_DEPTH} deep (a cycle?)"),
            });
        }
        let (object, part) = self.object(reference, from)?;
        if object.printed && !object.triangles.is_empty() {
            check_triangles(mesh.triangles.len() + object.triangles.len(), limits)?;
            check_vertices(mesh.positions.len() + object.positions.len(), limits)?;
            let offset = mesh.positions.len() as u32;
            mesh.positions.extend(object.positions.iter().map(|p| {
                let placed = transform * Vector4::new(p.x, p.y, p.z, 1.0);
                Point3::new(placed.x, placed.y, placed.z)
            }));
            mesh.triangles
                .extend(object.triangles.iter().map(|t| t.map(|i| i + offset)));
        }
        if object.printed {
            for component in &object.components {
                let placed = transform * component.transform;
                self.place(component, part, placed, depth + 1, mesh, limits)?;
            }
        }
        Ok(())
    }
}

/// The root model part's name: the target of the package relationship of the 3MF model type,
/// else `3D/3dmodel.model`.
fn root_part(
    archive: &mut zip::ZipArchive<Cursor<&[u8]>>,
    budget: &mut u64,
) -> Result<String, LoadError> {
    let Ok(text) = read_member(archive, "_rels/.rels", budget) else {
        return Ok(DEFAULT_MODEL.to_string());
    };
    let mut reader = quick_xml::Reader::from_str(&text);
    loop {
        match reader.read_event() {
            Ok(Event::Start(e) | Event::Empty(e)) if e.local_name().as_ref() == b"Relationship" => {
                let attributes = attributes(&e)?;
                let kind = attributes.get("Type").map(String::as_str);
                if kind == Some(MODEL_RELATIONSHIP) {
                    if let Some(target) = attributes.get("Target") {
                        return Ok(target.trim_start_matches('/').to_string());
                    }
                }
            }
            Ok(Event::Eof) => return Ok(DEFAULT_MODEL.to_string()),
            Ok(_) => {}
            Err(e) => {
                return Err(LoadError::ThreeMf {
                    message: format!("_rels/.rels is not well-formed XML: {e}"),
                })
            }
        }
    }
}

/// The text of archive member `name` (no leading slash; matched case-insensitively, as the
/// package format's part names are), its inflated bytes taken from `budget`.
fn read_member(
    archive: &mut zip::ZipArchive<Cursor<&[u8]>>,
    name: &str,
    budget: &mut u64,
) -> Result<String, LoadError> {
    let stored = archive
        .file_names()
        .find(|stored| stored.trim_start_matches('/').eq_ignore_ascii_case(name))
        .map(str::to_string)
        .ok_or_else(|| LoadError::ThreeMf {
            message: format!("the archive has no `{name}`"),
        })?;
    let member = archive.by_name(&stored).map_err(|e| LoadError::ThreeMf {
        message: format!("cannot read `{name}` from the archive: {e}"),
    })?;
    let too_large = || LoadError::TooLarge {
        path: PathBuf::from(name),
        limit: *budget,
    };
    if member.size() > *budget {
        return Err(too_large());
    }
    // The size a member declares is not trusted: no more than the budget is ever inflated.
    let mut bytes = Vec::new();
    member
        .take(*budget + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| LoadError::ThreeMf {
            message: format!("cannot inflate `{name}`: {e}"),
        })?;
    if bytes.len() as u64 > *budget {
        return Err(too_large());
    }
    *budget -= bytes.len() as u64;
    String::from_utf8(bytes).map_err(|e| LoadError::ThreeMf {
        message: format!(
            "`{name}` is not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        ),
    })
}

/// The attributes of `element` by local name (namespace prefixes dropped).
fn attributes(element: &BytesStart) -> Result<HashMap<String, String>, LoadError> {
    let mut found = HashMap::new();
    for attribute in element.attributes() {
        let attribute = attribute.map_err(|e| LoadError::ThreeMf {
            message: format!("a malformed attribute: {e}"),
        })?;
        let key = String::from_utf8_lossy(attribute.key.local_name().as_ref()).into_owned();
        let value = attribute
            .normalized_value(XmlVersion::Implicit1_0)
            .map_err(|e| LoadError::ThreeMf {
                message: format!("attribute `{key}`: {e}"),
            })?;
        found.insert(key, value.into_owned());
    }
    Ok(found)
}

/// Millimetres per unit of a 3MF `unit` attribute.
fn millimetres_per(unit: &str) -> Option<f64> {
    Some(match unit {
        "micron" => 0.001,
        "millimeter" => 1.0,
        "centimeter" => 10.0,
        "inch" => 25.4,
        "foot" => 304.8,
        "meter" => 1000.0,
        _ => return None,
    })
}

/// Parses model part `name`: its objects and build items, and its unit in millimetres.
fn parse_model(text: &str, name: &str, limits: &MeshLimits) -> Result<(ModelPart, f64), LoadError> {
    let error = |message: String| LoadError::ThreeMf {
        message: format!("`{name}`: {message}"),
    };
    let mut reader = quick_xml::Reader::from_str(text);
    let mut part = ModelPart::default();
    let mut unit = 1.0;
    // The object being read, with its id.
    let mut current: Option<(u64, Object)> = None;
    let (mut vertices, mut triangles) = (0usize, 0usize);
    loop {
        let event = reader
            .read_event()
            .map_err(|e| error(format!("not well-formed XML: {e}")))?;
        let (element, closes) = match &event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(e) if e.local_name().as_ref() == b"object" => {
                if let Some((id, object)) = current.take() {
                    part.objects.insert(id, object);
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let number = |attributes: &HashMap<String, String>, key: &str| -> Result<f64, LoadError> {
            let value = attributes
                .get(key)
                .ok_or_else(|| error(format!("a `{key}` attribute is missing")))?;
            value
                .trim()
                .parse::<f64>()
                .map_err(|_| error(format!("`{key}=\"{value}\"` is not a number")))
        };
        let index = |attributes: &HashMap<String, String>, key: &str| -> Result<u64, LoadError> {
            let value = attributes
                .get(key)
                .ok_or_else(|| error(format!("a `{key}` attribute is missing")))?;
            value
                .trim()
                .parse::<u64>()
                .map_err(|_| error(format!("`{key}=\"{value}\"` is not an index")))
        };
        match element.local_name().as_ref() {
            b"model" => {
                let attributes = attributes(element)?;
                if let Some(written) = attributes.get("unit") {
                    unit = millimetres_per(written)
                        .ok_or_else(|| error(format!("unknown unit `{written}`")))?;
                }
            }
            b"object" => {
                let attributes = attributes(element)?;
                let id = index(&attributes, "id")?;
                let kind = attributes.get("type").map_or("model", String::as_str);
                let object = Object {
                    name: attributes.get("name").cloned(),
                    printed: kind == "model",
                    ..Object::default()
                };
                if closes {
                    part.objects.insert(id, object);
                } else {
                    current = Some((id, object));
                }
            }
            b"vertex" => {
                let Some((_, object)) = current.as_mut() else {
                    return Err(error("a vertex outside any object".to_string()));
                };
                vertices += 1;
                check_vertices(vertices, limits)?;
                let attributes = attributes(element)?;
                let point = Point3::new(
                    number(&attributes, "x")?,
                    number(&attributes, "y")?,
                    number(&attributes, "z")?,
                );
                object.positions.push(point);
            }
            b"triangle" => {
                let Some((id, object)) = current.as_mut() else {
                    return Err(error("a triangle outside any object".to_string()));
                };
                triangles += 1;
                check_triangles(triangles, limits)?;
                let attributes = attributes(element)?;
                let count = object.positions.len() as u64;
                let mut corners = [0u32; 3];
                for (corner, key) in corners.iter_mut().zip(["v1", "v2", "v3"]) {
                    let vertex = index(&attributes, key)?;
                    if vertex >= count {
                        return Err(error(format!(
                            "object {id}: a triangle refers to vertex {vertex} of {count}"
                        )));
                    }
                    *corner = vertex as u32;
                }
                object.triangles.push(corners);
            }
            b"component" => {
                let Some((_, object)) = current.as_mut() else {
                    return Err(error("a component outside any object".to_string()));
                };
                let attributes = attributes(element)?;
                object.components.push(reference(&attributes, &error)?);
            }
            b"item" => {
                let attributes = attributes(element)?;
                part.items.push(reference(&attributes, &error)?);
            }
            _ => {}
        }
    }
    Ok((part, unit))
}

/// A build item or component from its attributes: `objectid`, the optional `transform` and
/// the production extension's `path`.
fn reference(
    attributes: &HashMap<String, String>,
    error: &impl Fn(String) -> LoadError,
) -> Result<Reference, LoadError> {
    let id = attributes
        .get("objectid")
        .ok_or_else(|| error("an `objectid` attribute is missing".to_string()))?;
    let object = id
        .trim()
        .parse()
        .map_err(|_| error(format!("`objectid=\"{id}\"` is not an index")))?;
    let transform = match attributes.get("transform") {
        Some(written) => transform(written)
            .ok_or_else(|| error(format!("`transform=\"{written}\"` is not 12 numbers")))?,
        None => Matrix4::identity(),
    };
    let part = attributes
        .get("path")
        .map(|path| path.trim_start_matches('/').to_string());
    Ok(Reference {
        object,
        part,
        transform,
    })
}

/// The matrix of a 3MF transform, `m00 m01 m02 m10 m11 m12 m20 m21 m22 m30 m31 m32`: a row
/// vector `(x, y, z, 1)` times the 4 × 3 matrix of those rows, here as the 4 × 4 matrix that
/// takes a column vector.
fn transform(written: &str) -> Option<Matrix4<f64>> {
    let values: Vec<f64> = written
        .split_whitespace()
        .map(|word| word.parse().ok())
        .collect::<Option<_>>()?;
    let m: [f64; 12] = values.try_into().ok()?;
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    Some(Matrix4::new(
        m[0], m[3], m[6], m[9], m[1], m[4], m[7], m[10], m[2], m[5], m[8], m[11], 0.0, 0.0, 0.0,
        1.0,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_transform_takes_row_vectors() {
        // A quarter turn about z, then a move by (10, 20, 30).
        let m = transform("0 1 0 -1 0 0 0 0 1 10 20 30").unwrap();
        let p = m * Vector4::new(1.0, 0.0, 0.0, 1.0);
        assert_eq!((p.x, p.y, p.z), (10.0, 21.0, 30.0));
        assert!(transform("1 0 0").is_none());
        assert!(transform("1 0 0 0 1 0 0 0 1 0 0 inf").is_none());
    }

    #[test]
    fn units_are_millimetres_per_unit() {
        assert_eq!(millimetres_per("meter"), Some(1000.0));
        assert_eq!(millimetres_per("inch"), Some(25.4));
        assert_eq!(millimetres_per("furlong"), None);
    }
}
