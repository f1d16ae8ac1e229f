//! Atomic file replacement: readers see either the old file or the complete new one; and the
//! temporary files it goes through, named so that only ballast's own are ever cleaned up.
//!
//! A temporary file is a hidden sibling of its target, `.<target name>.ballast-<pid>-<n>.tmp`:
//! the writer's process id and a counter of that process. [`TempName::parse`] recognises exactly
//! that form, and [`TempName::is_stale`] says whether its writer is gone.

use std::ffi::{OsStr, OsString};
use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, SystemTime};

/// Distinguishes temporary files of concurrent writes within one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// A temporary file whose writer cannot be asked whether it still runs (no `/proc`) is stale
/// once this old.
pub const STALE_TEMP_AGE: Duration = Duration::from_secs(3600);

/// Writes `bytes` to `path` atomically: a temporary file in the same directory, fsync, then rename over `path`.
/// Creates the parent directory if missing. On failure the old file (if any) is untouched and no temporary file is left behind.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let temp = write_temp(path, bytes)?;
    if let Err(error) = fs::rename(&temp, path) {
        // The temporary file is ours and must not outlive the failure; a failure to remove it
        // matters less than the error that got us here.
        let _ = fs::remove_file(&temp);
        return Err(error);
    }
    sync_dir(&folder_of(path));
    Ok(())
}

/// Writes `bytes` to a new temporary sibling of `path` (creating the folder if missing) and
/// syncs it to disk; returns the temporary file's path. The caller renames it over `path`. On
/// failure nothing is left behind.
pub fn write_temp(path: &Path, bytes: &[u8]) -> io::Result<PathBuf> {
    let file_name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("`{}` does not name a file", path.display()),
        )
    })?;
    let parent = folder_of(path);
    fs::create_dir_all(&parent)?;
    let (temp_path, mut file) = create_temp(&parent, file_name)?;
    let result = file.write_all(bytes).and_then(|()| file.sync_all());
    drop(file);
    if let Err(error) = result {
        let _ = fs::remove_file(&temp_path);
        return Err(error);
    }
    Ok(temp_path)
}

/// The folder `path` is in (`.` for a bare file name).
pub fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Creates a new, empty temporary file next to the target, never reusing an existing name.
fn create_temp(dir: &Path, file_name: &OsStr) -> io::Result<(PathBuf, File)> {
    loop {
        let name = TempName {
            target: file_name.to_os_string(),
            pid: std::process::id(),
            n: COUNTER.fetch_add(1, Ordering::Relaxed),
        };
        let temp_path = dir.join(name.file_name());
        match OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp_path)
        {
            Ok(file) => return Ok((temp_path, file)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

/// The parts of a temporary file's name: `.<target>.ballast-<pid>-<n>.tmp`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TempName {
    /// The file name of the file it replaces.
    pub target: OsString,
    /// The process that wrote it.
    pub pid: u32,
    /// That process's counter.
    pub n: u64,
}

impl TempName {
    /// The file name.
    pub fn file_name(&self) -> OsString {
        let mut name = OsString::from(".");
        name.push(&self.target);
        name.push(format!(".ballast-{}-{}.tmp", self.pid, self.n));
        name
    }

    /// The parts of `name` when it is exactly a temporary file name ballast makes, else `None`.
    pub fn parse(name: &OsStr) -> Option<TempName> {
        let name = name.to_str()?;
        let rest = name.strip_prefix('.')?.strip_suffix(".tmp")?;
        let (target, numbers) = rest.rsplit_once(".ballast-")?;
        let (pid, n) = numbers.split_once('-')?;
        let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
        if target.is_empty() || !digits(pid) || !digits(n) {
            return None;
        }
        Some(TempName {
            target: target.into(),
            pid: pid.parse().ok()?,
            n: n.parse().ok()?,
        })
    }

    /// Whether the temporary file at `path` (of this name) was left by a writer that is gone: a
    /// process other than this one that no longer runs (where `/proc` says so), or, where that
    /// cannot be known, a file older than [`STALE_TEMP_AGE`].
    pub fn is_stale(&self, path: &Path) -> bool {
        if self.pid == std::process::id() {
            return false;
        }
        let proc = Path::new("/proc");
        if proc.join("self").exists() {
            return !proc.join(self.pid.to_string()).exists();
        }
        fs::symlink_metadata(path)
            .and_then(|metadata| metadata.modified())
            .ok()
            .and_then(|modified| SystemTime::now().duration_since(modified).ok())
            .is_some_and(|age| age > STALE_TEMP_AGE)
    }
}

/// Makes renames in `dir` durable where the platform allows syncing a directory.
pub fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = File::open(dir) {
        // The new content is already in place; this only hardens it against power loss.
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_are_hidden_siblings_that_parse_back() {
        let dir = tempfile::tempdir().unwrap();
        let (path, file) = create_temp(dir.path(), OsStr::new("out.glb")).unwrap();
        drop(file);
        let name = path.file_name().unwrap();
        let text = name.to_string_lossy().into_owned();
        assert!(
            text.starts_with(".out.glb.ballast-") && text.ends_with(".tmp"),
            "{text}"
        );
        assert_eq!(path.parent(), Some(dir.path()));
        let parsed = TempName::parse(name).unwrap();
        assert_eq!(parsed.target, "out.glb");
        assert_eq!(parsed.pid, std::process::id());
        assert_eq!(parsed.file_name(), name);
        // This process is running: its file is not stale.
        assert!(!parsed.is_stale(&path));
    }

    #[test]
    fn only_ballast_temporary_names_parse() {
        for other in [
            ".out.glb.tmp",
            ".out.glb.123.4.tmp",
            "out.glb.ballast-1-2.tmp",
            ".out.glb.ballast-1-2.tmp~",
            ".out.glb.ballast-x-2.tmp",
            ".out.glb.ballast-1-.tmp",
            "..ballast-1-2.tmp",
            ".notes.tmp",
        ] {
            assert_eq!(TempName::parse(OsStr::new(other)), None, "{other}");
        }
        assert_eq!(
            TempName::parse(OsStr::new(".a.ballast-b.ballast-12-3.tmp")),
            Some(TempName {
                target: "a.ballast-b".into(),
                pid: 12,
                n: 3
            })
        );
    }

    #[test]
    fn a_dead_writer_leaves_a_stale_file() {
        if !Path::new("/proc/self").exists() {
            return;
        }
        let dir = tempfile::tempdir().unwrap();
        // A child that has exited and been waited for no longer runs.
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        let name = TempName {
            target: "model.glb".into(),
            pid,
            n: 0,
        };
        let path = dir.path().join(name.file_name());
        fs::write(&path, b"partial").unwrap();
        assert!(name.is_stale(&path));
    }
}
