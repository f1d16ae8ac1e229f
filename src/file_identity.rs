//! Which file a path names: its device and inode, so that two paths to one file (through a link,
//! `..` or a bind mount) are known to be one.

use std::fs::Metadata;

/// The device and inode of the file `metadata` describes; `None` on a platform without them.
pub fn identity(metadata: &Metadata) -> Option<(u64, u64)> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        Some((metadata.dev(), metadata.ino()))
    }
    #[cfg(not(unix))]
    {
        let _ = metadata;
        None
    }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn a_link_and_its_target_are_one_file_and_two_files_are_two() {
        let folder = tempfile::tempdir().unwrap();
        let first = folder.path().join("a");
        let second = folder.path().join("b");
        std::fs::write(&first, "a").unwrap();
        std::fs::write(&second, "b").unwrap();
        let link = folder.path().join("link");
        std::os::unix::fs::symlink(&first, &link).unwrap();
        let of = |path: &std::path::Path| identity(&std::fs::metadata(path).unwrap());
        assert_eq!(of(&first), of(&link));
        assert_ne!(of(&first), of(&second));
    }
}
