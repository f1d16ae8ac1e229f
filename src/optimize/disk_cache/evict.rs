//! What the cache removes, and how it knows a file is its own: a name it gives
//! (`<hex>-<hex>.bin`, or ballast's temporary file of such a name) in a folder it names
//! (`ballast-v<N>`, or `v<N>` of the first format) and, for a cache file, the magic bytes it
//! starts with. Nothing else under the cache folder is ever removed: not a user's folder, not a
//! file of another name, not a folder that still holds anything.

use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

use super::format::{FORMAT, MAGIC};
use crate::emit::atomic::TempName;

/// The folder of format `format`'s files.
pub fn format_folder(format: u32) -> String {
    format!("ballast-v{format}")
}

/// Removes the files of other formats (then their folders, once empty), temporary files that
/// writers killed mid-write left, and the least recently used files of this format until the
/// rest total at most `limit` bytes. Errors are ignored.
pub fn evict(root: &Path, limit: u64) {
    let current = format_folder(FORMAT);
    if let Ok(entries) = fs::read_dir(root) {
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(name) = name.to_str() else { continue };
            let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
            if is_dir && name != current && is_format_folder(name) {
                remove_other_format(&entry.path());
            }
        }
    }
    let folder = root.join(current);
    let Ok(entries) = fs::read_dir(&folder) else {
        return;
    };
    let mut files = Vec::new();
    for entry in entries.flatten() {
        let Ok(metadata) = entry.metadata() else {
            continue;
        };
        if !metadata.is_file() {
            continue;
        }
        let path = entry.path();
        if let Some(temp) = own_temp(&entry.file_name()) {
            if temp.is_stale(&path) {
                let _ = fs::remove_file(&path);
            }
        } else if is_cache_name(&entry.file_name().to_string_lossy()) && has_magic(&path) {
            let modified = metadata.modified().unwrap_or(SystemTime::UNIX_EPOCH);
            files.push((modified, path, metadata.len()));
        }
    }
    let mut total: u64 = files.iter().map(|(_, _, len)| len).sum();
    if total <= limit {
        return;
    }
    files.sort();
    for (_, path, len) in files {
        if total <= limit {
            break;
        }
        if fs::remove_file(&path).is_ok() {
            total -= len;
        }
    }
}

/// Removes the cache's own files from `folder`, a folder of another format, and the folder
/// itself when that left it empty.
fn remove_other_format(folder: &Path) {
    let Ok(entries) = fs::read_dir(folder) else {
        return;
    };
    let mut removed = false;
    for entry in entries.flatten() {
        if !entry.file_type().is_ok_and(|t| t.is_file()) {
            continue;
        }
        let path: PathBuf = entry.path();
        let name = entry.file_name();
        let own = match own_temp(&name) {
            Some(temp) => temp.is_stale(&path),
            None => is_cache_name(&name.to_string_lossy()) && has_magic(&path),
        };
        if own && fs::remove_file(&path).is_ok() {
            removed = true;
        }
    }
    if removed {
        // Fails, as it should, when anything else is left in it.
        let _ = fs::remove_dir(folder);
    }
}

/// `ballast-v<N>`, or `v<N>`, the first format's folder.
fn is_format_folder(name: &str) -> bool {
    let digits = name
        .strip_prefix("ballast-v")
        .or_else(|| name.strip_prefix('v'));
    digits.is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
}

/// `<hex>-<16 hex>.bin` with 16 (the first format) or 64 hexadecimal digits first.
fn is_cache_name(name: &str) -> bool {
    let Some((mesh, cell)) = name
        .strip_suffix(".bin")
        .and_then(|stem| stem.split_once('-'))
    else {
        return false;
    };
    let hex = |s: &str, len: usize| s.len() == len && s.bytes().all(|b| b.is_ascii_hexdigit());
    (hex(mesh, 16) || hex(mesh, 64)) && hex(cell, 16)
}

/// Ballast's temporary file of a cache file.
fn own_temp(name: &std::ffi::OsStr) -> Option<TempName> {
    TempName::parse(name).filter(|temp| is_cache_name(&temp.target.to_string_lossy()))
}

/// Whether the file at `path` starts with the cache's magic bytes.
fn has_magic(path: &Path) -> bool {
    let mut start = [0u8; 8];
    crate::regular_file::open_regular(path)
        .and_then(|mut file| file.read_exact(&mut start))
        .is_ok()
        && &start == MAGIC
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_the_cache_gives_are_recognised_and_no_others() {
        let short = format!("{}-{}.bin", "0123456789abcdef", "3fd0000000000000");
        let long = format!("{}-{}.bin", "ab".repeat(32), "3fd0000000000000");
        assert!(is_cache_name(&short) && is_cache_name(&long));
        for other in [
            "notes.bin",
            "0123456789abcdef.bin",
            "0123456789abcdef-3fd0000000000000.txt",
            "0123456789abcdeg-3fd0000000000000.bin",
            "0123456789abcdef-3fd00000000000000.bin",
        ] {
            assert!(!is_cache_name(other), "{other}");
        }
        for folder in ["v1", "v10", "ballast-v1", "ballast-v2"] {
            assert!(is_format_folder(folder), "{folder}");
        }
        for folder in ["v", "vx", "v2b", "ballast-v", "notes", "ballast-vx"] {
            assert!(!is_format_folder(folder), "{folder}");
        }
    }
}
