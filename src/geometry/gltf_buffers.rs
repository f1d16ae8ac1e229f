//! The bytes of a glTF file's buffers: the GLB binary chunk, `data:` URIs (base64) and external
//! files relative to the glTF file; and, without reading them, which external files those are.

use std::path::{Path, PathBuf};

use base64::Engine;
use gltf::Document;

use super::load::LoadError;
use super::load_files::{FileReader, ReadPolicy};

/// Every buffer of `document`, in index order, each at least as long as it declares.
///
/// `blob` is the binary chunk of a GLB file; `base` the folder relative URIs resolve against.
/// Only `data:` URIs and relative paths are read: a URI with another scheme is an error, so
/// loading a mesh never reaches the network. Files are read through `reader`: only regular
/// files inside its folder, within its budget.
pub(crate) fn resolve_buffers(
    document: &Document,
    base: &Path,
    mut blob: Option<Vec<u8>>,
    reader: &mut FileReader,
) -> Result<Vec<Vec<u8>>, LoadError> {
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let index = buffer.index();
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                malformed(format!(
                    "buffer {index} refers to a missing GLB binary chunk"
                ))
            })?,
            gltf::buffer::Source::Uri(uri) => read_uri(uri, base, index, reader)?,
        };
        if data.len() < buffer.length() {
            return Err(malformed(format!(
                "buffer {index} holds {} bytes but declares {}",
                data.len(),
                buffer.length()
            )));
        }
        buffers.push(data);
    }
    Ok(buffers)
}

fn read_uri(
    uri: &str,
    base: &Path,
    index: usize,
    reader: &mut FileReader,
) -> Result<Vec<u8>, LoadError> {
    match BufferUri::parse(uri, base) {
        BufferUri::Data(data) => {
            let Some((_, payload)) = data.split_once(";base64,") else {
                return Err(malformed(format!(
                    "buffer {index} has a data URI that is not base64"
                )));
            };
            base64::engine::general_purpose::STANDARD
                .decode(payload)
                .map_err(|e| malformed(format!("buffer {index} has a bad base64 data URI: {e}")))
        }
        BufferUri::OtherScheme => Err(malformed(format!(
            "buffer {index} has a URI `{uri}` that is neither a data URI nor a relative path"
        ))),
        BufferUri::NotUtf8 => Err(malformed(format!(
            "buffer {index} has a URI that is not UTF-8 once decoded"
        ))),
        BufferUri::File(path) => reader.read(&path).map_err(|error| match error {
            LoadError::NotFound { .. } | LoadError::Io { .. } => {
                malformed(format!("cannot read buffer {index}: {error}"))
            }
            other => other,
        }),
    }
}

/// The external files the buffers of the mesh file at `path` are read from, in buffer order:
/// for a `.gltf` file (extension compared case-insensitively), every buffer URI that is a
/// relative path, percent-decoded and resolved against the file's folder, as the loader
/// resolves it. `data:` URIs and other schemes name no file. Only the JSON is parsed, and only
/// as far as the buffers' URIs; the buffers are not read.
///
/// Only files `policy` allows are listed, and the glTF file itself is read only when the policy
/// allows it. Empty for `.glb`, `.obj` and any other file, and when the file cannot be read or
/// parsed (a build reports why).
pub(crate) fn external_buffer_paths(path: &Path, policy: &ReadPolicy) -> Vec<PathBuf> {
    /// The part of a glTF document read here.
    #[derive(serde::Deserialize)]
    struct Buffers {
        #[serde(default)]
        buffers: Vec<Buffer>,
    }
    #[derive(serde::Deserialize)]
    struct Buffer {
        uri: Option<String>,
    }

    let is_gltf = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf"));
    if !is_gltf {
        return Vec::new();
    }
    let mut reader = FileReader::new(policy);
    let Ok(bytes) = reader.read(path) else {
        return Vec::new();
    };
    let Ok(document) = serde_json::from_slice::<Buffers>(&bytes) else {
        return Vec::new();
    };
    let base = path.parent().unwrap_or_else(|| Path::new("."));
    document
        .buffers
        .iter()
        .filter_map(
            |buffer| match BufferUri::parse(buffer.uri.as_deref()?, base) {
                BufferUri::File(path) if reader.allows(&path) => Some(path),
                _ => None,
            },
        )
        .collect()
}

/// What a buffer URI refers to.
enum BufferUri<'a> {
    /// A `data:` URI: the text after `data:`.
    Data(&'a str),
    /// A relative path, percent-decoded and joined to the glTF file's folder.
    File(PathBuf),
    /// A relative path that is not UTF-8 once percent-decoded.
    NotUtf8,
    /// A URI with another scheme (`https:`, `file:`, ...), which is never read.
    OtherScheme,
}

impl<'a> BufferUri<'a> {
    /// Classifies `uri`, resolving a relative path against `base`.
    fn parse(uri: &'a str, base: &Path) -> Self {
        if let Some(data) = uri.strip_prefix("data:") {
            return BufferUri::Data(data);
        }
        if uri.contains(':') {
            return BufferUri::OtherScheme;
        }
        match String::from_utf8(percent_decode(uri)) {
            Ok(decoded) => BufferUri::File(base.join(decoded)),
            Err(_) => BufferUri::NotUtf8,
        }
    }
}

/// Decodes `%XX` escapes; anything else, including a malformed escape, is kept as it is.
fn percent_decode(s: &str) -> Vec<u8> {
    let hex = |c: u8| (c as char).to_digit(16).map(|d| d as u8);
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let (Some(h), Some(l)) = (hex(bytes[i + 1]), hex(bytes[i + 2])) {
                out.push(h << 4 | l);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    out
}

fn malformed(message: String) -> LoadError {
    LoadError::Gltf { message }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn anywhere() -> ReadPolicy {
        ReadPolicy {
            within: None,
            ..ReadPolicy::within(Path::new("."))
        }
    }

    #[test]
    fn external_buffers_are_the_relative_uris_decoded() {
        let outer = tempfile::tempdir().unwrap();
        let folder = outer.path().join("meshes");
        std::fs::create_dir(&folder).unwrap();
        std::fs::write(folder.join("a b.bin"), [0; 4]).unwrap();
        std::fs::write(outer.path().join("d.bin"), [0; 4]).unwrap();
        let gltf = folder.join("mesh.GLTF");
        let json = r#"{"asset": {"version": "2.0"}, "buffers": [
            {"uri": "a%20b.bin", "byteLength": 4},
            {"uri": "data:application/octet-stream;base64,AAAAAA==", "byteLength": 4},
            {"uri": "https://example.com/c.bin", "byteLength": 4},
            {"uri": "../d.bin", "byteLength": 4},
            {"byteLength": 4}
        ]}"#;
        std::fs::write(&gltf, json).unwrap();
        assert_eq!(
            external_buffer_paths(&gltf, &anywhere()),
            vec![folder.join("a b.bin"), folder.join("../d.bin")]
        );
        // Inside the folder only: `../d.bin` is left out.
        assert_eq!(
            external_buffer_paths(&gltf, &ReadPolicy::within(&folder)),
            vec![folder.join("a b.bin")]
        );
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn system_files_are_not_external_buffers() {
        let folder = tempfile::tempdir().unwrap();
        let gltf = folder.path().join("mesh.gltf");
        let json = r#"{"asset": {"version": "2.0"}, "buffers": [
            {"uri": "/dev/zero", "byteLength": 4},
            {"uri": "/proc/self/environ", "byteLength": 4}
        ]}"#;
        std::fs::write(&gltf, json).unwrap();
        assert!(external_buffer_paths(&gltf, &anywhere()).is_empty());
    }

    #[test]
    fn no_external_buffers_without_a_readable_gltf() {
        let folder = tempfile::tempdir().unwrap();
        let policy = ReadPolicy::within(folder.path());
        assert!(external_buffer_paths(&folder.path().join("missing.gltf"), &policy).is_empty());
        let broken = folder.path().join("broken.gltf");
        std::fs::write(&broken, "{ not json").unwrap();
        assert!(external_buffer_paths(&broken, &policy).is_empty());
        let glb = folder.path().join("mesh.glb");
        std::fs::write(&glb, r#"{"buffers": [{"uri": "a.bin"}]}"#).unwrap();
        assert!(external_buffer_paths(&glb, &policy).is_empty());
    }
}
