//! What each watched file held when the build that read it started, so that events which change
//! no byte (the second event of one save, a `touch`, an editor writing the same text again)
//! neither cancel a build nor start one.

use std::collections::BTreeMap;
use std::hash::{DefaultHasher, Hasher};
use std::path::{Path, PathBuf};

/// A hash of each recorded file's bytes (`None`: it could not be read).
#[derive(Debug, Default)]
pub struct Contents {
    hashes: BTreeMap<PathBuf, Option<u64>>,
}

impl Contents {
    /// Nothing recorded.
    pub fn new() -> Contents {
        Contents::default()
    }

    /// Records what each of `files` holds now.
    pub fn record<'a>(&mut self, files: impl IntoIterator<Item = &'a PathBuf>) {
        for file in files {
            self.hashes.insert(file.clone(), hash_of(file));
        }
    }

    /// The files among `files` whose bytes are not those recorded: changed, created, removed, or
    /// never recorded. A file unreadable both then and now has not changed.
    pub fn differing<'a>(&self, files: impl IntoIterator<Item = &'a PathBuf>) -> Vec<PathBuf> {
        files
            .into_iter()
            .filter(|file| self.hashes.get(*file) != Some(&hash_of(file)))
            .cloned()
            .collect()
    }
}

/// A hash of the bytes of `path`, or `None` when it cannot be read or is not a regular file (a
/// pipe would block the watcher, a device never end), read in pieces whatever its size.
fn hash_of(path: &Path) -> Option<u64> {
    let hash = crate::regular_file::blake3_of(path).ok()?;
    let mut hasher = DefaultHasher::new();
    hasher.write(hash.as_bytes());
    Some(hasher.finish())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_files_whose_bytes_changed_differ() {
        let folder = tempfile::tempdir().unwrap();
        let same = folder.path().join("same.kdl");
        let edited = folder.path().join("edited.kdl");
        let removed = folder.path().join("removed.obj");
        let missing = folder.path().join("missing.obj");
        let unrecorded = folder.path().join("new.obj");
        for file in [&same, &edited, &removed, &unrecorded] {
            std::fs::write(file, "v 0 0 0\n").unwrap();
        }
        let mut contents = Contents::new();
        contents.record([&same, &edited, &removed, &missing]);
        // Written again with the same bytes, edited, removed, still missing, never recorded.
        std::fs::write(&same, "v 0 0 0\n").unwrap();
        std::fs::write(&edited, "v 0 0 1\n").unwrap();
        std::fs::remove_file(&removed).unwrap();
        let all = [&same, &edited, &removed, &missing, &unrecorded];
        assert_eq!(
            contents.differing(all),
            vec![edited.clone(), removed.clone(), unrecorded.clone()]
        );
        contents.record([&edited]);
        assert_eq!(contents.differing([&edited]), Vec::<PathBuf>::new());
    }
}
