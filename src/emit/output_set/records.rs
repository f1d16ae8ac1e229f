//! The records of an output set: the journal (the commit point of a replacement, naming each
//! temporary file and its target and the previous set's files to remove) and the manifest (the
//! files of the set last written, with the hash of what was written). Both are JSON, read only
//! as regular files within [`MAX_RECORD_BYTES`], and trusted for nothing: the caller checks every
//! file they name.

use std::io;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::emit::atomic::{folder_of, write_atomic};
use crate::regular_file::read_limited;

/// The most bytes of a journal or manifest read: one names every output of a build, a few
/// hundred bytes each.
pub const MAX_RECORD_BYTES: u64 = 16 << 20;

/// The journal's format number.
pub(super) const JOURNAL_FORMAT: u32 = 1;

/// The manifest's format number.
pub(super) const MANIFEST_FORMAT: u32 = 1;

/// What the journal holds: each temporary file (by name, in its target's folder) and its target,
/// and the files of the previous set to remove.
#[derive(Debug, Serialize, Deserialize)]
pub(super) struct Journal {
    /// [`JOURNAL_FORMAT`].
    pub(super) ballast_output_set: u32,
    /// In the order they are renamed.
    pub(super) files: Vec<JournalEntry>,
    /// Files of the previous set that the new one does not have, each with the hash of the bytes
    /// the previous set wrote to it.
    #[serde(default)]
    pub(super) remove: Vec<WrittenFile>,
}

/// One file of the set.
#[derive(Debug, Serialize, Deserialize)]
pub(super) struct JournalEntry {
    /// The target, absolute.
    pub(super) target: String,
    /// The temporary file's name, a sibling of the target.
    pub(super) temp: String,
    /// The BLAKE3 hash of the new bytes, hexadecimal (absent in a journal of an older ballast).
    #[serde(default)]
    pub(super) blake3: Option<String>,
}

/// What the manifest holds: the files of the set last written.
#[derive(Debug, Serialize, Deserialize)]
pub(super) struct Manifest {
    /// [`MANIFEST_FORMAT`].
    pub(super) ballast_output_manifest: u32,
    /// In the set's order.
    pub(super) files: Vec<WrittenFile>,
}

/// A file ballast wrote and what it wrote to it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(super) struct WrittenFile {
    /// The file: relative to the manifest's folder in a manifest (so that a copied folder's
    /// manifest names the copy's files), absolute in a journal or outside that folder.
    pub(super) path: String,
    /// The BLAKE3 hash of the bytes written, hexadecimal; `None` when not known, and then the file
    /// is never removed.
    pub(super) blake3: Option<String>,
}

/// The manifest beside `journal`: named like it, with `.manifest` appended. Unlike the journal it
/// stays between builds.
pub fn manifest_path(journal: &Path) -> PathBuf {
    let mut name = journal.file_name().unwrap_or_default().to_os_string();
    name.push(".manifest");
    journal.with_file_name(name)
}

/// The files the manifest at `path` names, absolute, with their hashes; none when there is no
/// manifest or it does not read as one.
pub(super) fn read_manifest(path: &Path) -> Vec<(PathBuf, Option<String>)> {
    let Some(manifest) = read_limited(path, MAX_RECORD_BYTES)
        .ok()
        .and_then(|text| serde_json::from_slice::<Manifest>(&text).ok())
        .filter(|manifest| manifest.ballast_output_manifest == MANIFEST_FORMAT)
    else {
        return Vec::new();
    };
    let folder = folder_of(path);
    manifest
        .files
        .into_iter()
        .map(|file| (folder.join(&file.path), file.blake3))
        .collect()
}

/// Writes the manifest at `path` naming `files` (absolute paths), relative to its folder where
/// they are inside it.
pub(super) fn write_manifest(path: &Path, files: &[WrittenFile]) -> io::Result<()> {
    let folder = folder_of(path);
    let files = files
        .iter()
        .map(|file| WrittenFile {
            path: Path::new(&file.path).strip_prefix(&folder).map_or_else(
                |_| file.path.clone(),
                |relative| relative.to_string_lossy().into_owned(),
            ),
            blake3: file.blake3.clone(),
        })
        .collect();
    let text = serde_json::to_string_pretty(&Manifest {
        ballast_output_manifest: MANIFEST_FORMAT,
        files,
    })
    .map_err(io::Error::other)?;
    write_atomic(path, text.as_bytes())
}
