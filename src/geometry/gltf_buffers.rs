//! The bytes of a glTF file's buffers: the GLB binary chunk, `data:` URIs (base64) and external
//! files relative to the glTF file.

use std::path::Path;

use base64::Engine;
use gltf::Document;

use super::load::LoadError;

/// Every buffer of `document`, in index order, each at least as long as it declares.
///
/// `blob` is the binary chunk of a GLB file; `base` the folder relative URIs resolve against.
/// Only `data:` URIs and relative paths are read: a URI with another scheme is an error, so
/// loading a mesh never reaches the network.
pub(crate) fn resolve_buffers(
    document: &Document,
    base: &Path,
    mut blob: Option<Vec<u8>>,
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
            gltf::buffer::Source::Uri(uri) => read_uri(uri, base, index)?,
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

fn read_uri(uri: &str, base: &Path, index: usize) -> Result<Vec<u8>, LoadError> {
    if let Some(data) = uri.strip_prefix("data:") {
        let Some((_, payload)) = data.split_once(";base64,") else {
            return Err(malformed(format!(
                "buffer {index} has a data URI that is not base64"
            )));
        };
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| malformed(format!("buffer {index} has a bad base64 data URI: {e}")));
    }
    if uri.contains(':') {
        return Err(malformed(format!(
            "buffer {index} has a URI `{uri}` that is neither a data URI nor a relative path"
        )));
    }
    let decoded = String::from_utf8(percent_decode(uri)).map_err(|_| {
        malformed(format!(
            "buffer {index} has a URI that is not UTF-8 once decoded"
        ))
    })?;
    let path = base.join(decoded);
    std::fs::read(&path).map_err(|source| {
        malformed(format!(
            "cannot read buffer {index} from {}: {source}",
            path.display()
        ))
    })
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
