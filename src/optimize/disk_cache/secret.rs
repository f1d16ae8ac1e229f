//! The cache's secret: 32 random bytes in `<root>/ballast-cache.key`, readable by its owner only.
//! Every cache file ends with a BLAKE3 hash keyed with it, so a file written without it (by
//! another user, another machine, or by hand) is a miss.

use std::fs;
use std::io::{self, Read};
use std::path::{Path, PathBuf};

use crate::emit::atomic::write_temp;

/// The key's length.
pub const SECRET_BYTES: usize = 32;

/// The key file in the cache folder `root`.
pub fn secret_path(root: &Path) -> PathBuf {
    root.join("ballast-cache.key")
}

/// The key in `root`, when there is a usable one: a plain file (not a link) of exactly
/// [`SECRET_BYTES`] bytes that no one but its owner may read or write.
pub fn read_secret(root: &Path) -> Option<[u8; SECRET_BYTES]> {
    let path = secret_path(root);
    let metadata = fs::symlink_metadata(&path).ok()?;
    if !metadata.is_file() || metadata.len() != SECRET_BYTES as u64 || !private(&metadata) {
        return None;
    }
    let mut secret = [0u8; SECRET_BYTES];
    fs::File::open(&path).ok()?.read_exact(&mut secret).ok()?;
    Some(secret)
}

/// The key in `root`, made (from the operating system's random numbers) when there is no key
/// file yet. `None` when a key file is there but not usable ([`read_secret`]), or none can be made.
pub fn secret(root: &Path) -> Option<[u8; SECRET_BYTES]> {
    if let Some(secret) = read_secret(root) {
        return Some(secret);
    }
    let path = secret_path(root);
    if fs::symlink_metadata(&path).is_ok() {
        return None;
    }
    create(&path).ok()?;
    read_secret(root)
}

/// Writes a new key to `path` unless one appeared meanwhile (another process made it first).
fn create(path: &Path) -> io::Result<()> {
    let mut secret = [0u8; SECRET_BYTES];
    getrandom::fill(&mut secret).map_err(|error| io::Error::other(error.to_string()))?;
    let temp = write_temp(path, &secret)?;
    let made = restrict(&temp).and_then(|()| fs::hard_link(&temp, path));
    let _ = fs::remove_file(&temp);
    match made {
        Err(error) if error.kind() == io::ErrorKind::AlreadyExists => Ok(()),
        other => other,
    }
}

#[cfg(unix)]
fn restrict(path: &Path) -> io::Result<()> {
    use std::os::unix::fs::PermissionsExt;
    fs::set_permissions(path, fs::Permissions::from_mode(0o600))
}

#[cfg(not(unix))]
fn restrict(_: &Path) -> io::Result<()> {
    Ok(())
}

#[cfg(unix)]
fn private(metadata: &fs::Metadata) -> bool {
    use std::os::unix::fs::PermissionsExt;
    metadata.permissions().mode() & 0o077 == 0
}

#[cfg(not(unix))]
fn private(_: &fs::Metadata) -> bool {
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_key_is_made_once_and_kept() {
        let root = tempfile::tempdir().unwrap();
        assert_eq!(read_secret(root.path()), None);
        let first = secret(root.path()).unwrap();
        assert_eq!(secret(root.path()), Some(first));
        assert_eq!(read_secret(root.path()), Some(first));
        assert_ne!(first, [0u8; SECRET_BYTES]);
        let other = tempfile::tempdir().unwrap();
        assert_ne!(secret(other.path()), Some(first));
    }

    #[test]
    fn a_key_others_may_read_or_of_the_wrong_size_is_not_used() {
        let root = tempfile::tempdir().unwrap();
        let path = secret_path(root.path());
        fs::write(&path, b"short").unwrap();
        assert_eq!(secret(root.path()), None);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            fs::write(&path, [7u8; SECRET_BYTES]).unwrap();
            fs::set_permissions(&path, fs::Permissions::from_mode(0o644)).unwrap();
            assert_eq!(secret(root.path()), None);
            fs::set_permissions(&path, fs::Permissions::from_mode(0o600)).unwrap();
            assert_eq!(secret(root.path()), Some([7u8; SECRET_BYTES]));
        }
    }
}
