//! Reading the files a mesh is made of, within bounds: only regular files, only inside the folder
//! the caller allows, and no more bytes than the mesh's budget, checked before reading.

use std::io::Read;
use std::path::{Path, PathBuf};

use super::load::LoadError;

/// Default of [`MeshLimits::max_bytes`]: 256 MiB.
pub const DEFAULT_MAX_MESH_BYTES: u64 = 256 << 20;
/// Default of [`MeshLimits::max_triangles`]: two million.
pub const DEFAULT_MAX_TRIANGLES: usize = 2_000_000;

/// How much one mesh may take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshLimits {
    /// Most bytes read for one mesh: the mesh file and, for a `.gltf` file, its external buffer
    /// files together.
    pub max_bytes: u64,
    /// Most triangles in one mesh. For glTF every instance of every primitive counts (at least
    /// one each, so that empty primitives also add up); the vertices read may be at most three
    /// times as many.
    pub max_triangles: usize,
}

impl Default for MeshLimits {
    fn default() -> Self {
        MeshLimits {
            max_bytes: DEFAULT_MAX_MESH_BYTES,
            max_triangles: DEFAULT_MAX_TRIANGLES,
        }
    }
}

impl MeshLimits {
    /// Most vertices read for one mesh, before equal positions are merged.
    pub fn max_vertices(&self) -> usize {
        self.max_triangles.saturating_mul(3)
    }
}

/// Where the files of a mesh may be and how large it may be.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadPolicy {
    /// Every file read (the mesh and its glTF buffers) must be inside this folder once symbolic
    /// links are followed; `None` allows any folder.
    pub within: Option<PathBuf>,
    /// The size limits.
    pub limits: MeshLimits,
}

impl ReadPolicy {
    /// Files inside `folder` only, with the default limits.
    pub fn within(folder: &Path) -> ReadPolicy {
        ReadPolicy {
            within: Some(folder.to_path_buf()),
            limits: MeshLimits::default(),
        }
    }
}

/// Folders whose files are never read, whatever the policy: their "files" are windows on the
/// kernel or devices, not data (they report a size of 0 and can be endless or leak secrets).
const SYSTEM_FOLDERS: [&str; 3] = ["/proc", "/sys", "/dev"];

/// Reads the files of one mesh under a [`ReadPolicy`], counting the bytes against its budget.
pub(crate) struct FileReader<'p> {
    policy: &'p ReadPolicy,
    /// The allowed folder, canonical; `None` when any folder is allowed.
    root: Option<PathBuf>,
    /// Bytes read so far.
    used: u64,
}

impl<'p> FileReader<'p> {
    /// A reader with nothing read yet. The allowed folder must exist (else every read is
    /// refused as outside it).
    pub fn new(policy: &'p ReadPolicy) -> Self {
        let root = policy
            .within
            .as_ref()
            .map(|folder| folder.canonicalize().unwrap_or_else(|_| folder.clone()));
        FileReader {
            policy,
            root,
            used: 0,
        }
    }

    /// The limits of the policy.
    pub fn limits(&self) -> &MeshLimits {
        &self.policy.limits
    }

    /// Whether `path` may be read: it exists, is inside the allowed folder and is not a system
    /// file. Says nothing about its size or kind.
    pub fn allows(&self, path: &Path) -> bool {
        self.locate(path).is_ok()
    }

    /// The canonical form of `path`, or why it may not be read.
    fn locate(&self, path: &Path) -> Result<PathBuf, LoadError> {
        let canonical = path
            .canonicalize()
            .map_err(|source| io_error(path, source))?;
        if SYSTEM_FOLDERS
            .iter()
            .any(|folder| canonical.starts_with(folder))
        {
            return Err(LoadError::NotAFile {
                path: path.to_path_buf(),
            });
        }
        if let Some(root) = &self.root {
            if !canonical.starts_with(root) {
                return Err(LoadError::OutsideFolder {
                    path: path.to_path_buf(),
                    folder: root.clone(),
                });
            }
        }
        Ok(canonical)
    }

    /// The whole of the regular file at `path`, when the policy allows it and it fits in what is
    /// left of the budget. The size is checked before reading, and the read stops at the budget
    /// in case the file grows meanwhile.
    pub fn read(&mut self, path: &Path) -> Result<Vec<u8>, LoadError> {
        let canonical = self.locate(path)?;
        let file = crate::regular_file::open_regular(&canonical).map_err(|source| {
            if source.kind() == std::io::ErrorKind::InvalidInput {
                LoadError::NotAFile {
                    path: path.to_path_buf(),
                }
            } else {
                io_error(path, source)
            }
        })?;
        let metadata = file.metadata().map_err(|source| io_error(path, source))?;
        let left = self.policy.limits.max_bytes.saturating_sub(self.used);
        let too_large = || LoadError::TooLarge {
            path: path.to_path_buf(),
            limit: self.policy.limits.max_bytes,
        };
        if metadata.len() > left {
            return Err(too_large());
        }
        let mut bytes = Vec::with_capacity(metadata.len() as usize);
        file.take(left.saturating_add(1))
            .read_to_end(&mut bytes)
            .map_err(|source| io_error(path, source))?;
        if bytes.len() as u64 > left {
            return Err(too_large());
        }
        self.used += bytes.len() as u64;
        Ok(bytes)
    }
}

fn io_error(path: &Path, source: std::io::Error) -> LoadError {
    if source.kind() == std::io::ErrorKind::NotFound {
        LoadError::NotFound {
            path: path.to_path_buf(),
        }
    } else {
        LoadError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limited(folder: &Path, max_bytes: u64) -> ReadPolicy {
        ReadPolicy {
            within: Some(folder.to_path_buf()),
            limits: MeshLimits {
                max_bytes,
                ..MeshLimits::default()
            },
        }
    }

    #[test]
    fn reads_inside_and_refuses_outside_the_folder() {
        let outer = tempfile::tempdir().unwrap();
        let inner = outer.path().join("project");
        std::fs::create_dir(&inner).unwrap();
        std::fs::write(inner.join("a.bin"), b"abcd").unwrap();
        std::fs::write(outer.path().join("b.bin"), b"efgh").unwrap();
        let policy = ReadPolicy::within(&inner);
        let mut reader = FileReader::new(&policy);
        assert_eq!(reader.read(&inner.join("a.bin")).unwrap(), b"abcd");
        for path in [inner.join("../b.bin"), outer.path().join("b.bin")] {
            assert!(
                matches!(reader.read(&path), Err(LoadError::OutsideFolder { .. })),
                "{}",
                path.display()
            );
        }
        assert!(matches!(
            reader.read(&inner.join("none.bin")),
            Err(LoadError::NotFound { .. })
        ));
    }

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_out_of_the_folder_is_outside() {
        let outer = tempfile::tempdir().unwrap();
        let inner = outer.path().join("project");
        std::fs::create_dir(&inner).unwrap();
        std::fs::write(outer.path().join("secret"), b"x").unwrap();
        std::os::unix::fs::symlink(outer.path().join("secret"), inner.join("link.bin")).unwrap();
        let policy = ReadPolicy::within(&inner);
        assert!(matches!(
            FileReader::new(&policy).read(&inner.join("link.bin")),
            Err(LoadError::OutsideFolder { .. })
        ));
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn system_files_are_never_read_even_when_anywhere_is_allowed() {
        let policy = ReadPolicy {
            within: None,
            limits: MeshLimits::default(),
        };
        let mut reader = FileReader::new(&policy);
        for path in ["/dev/zero", "/proc/self/environ", "/dev/null"] {
            assert!(
                matches!(
                    reader.read(Path::new(path)),
                    Err(LoadError::NotAFile { .. })
                ),
                "{path}"
            );
        }
    }

    #[test]
    fn a_folder_is_not_a_file() {
        let folder = tempfile::tempdir().unwrap();
        std::fs::create_dir(folder.path().join("sub.obj")).unwrap();
        let policy = ReadPolicy::within(folder.path());
        assert!(matches!(
            FileReader::new(&policy).read(&folder.path().join("sub.obj")),
            Err(LoadError::NotAFile { .. })
        ));
    }

    #[test]
    fn the_budget_covers_every_file_of_a_mesh() {
        let folder = tempfile::tempdir().unwrap();
        std::fs::write(folder.path().join("a"), [0u8; 6]).unwrap();
        std::fs::write(folder.path().join("b"), [0u8; 5]).unwrap();
        let policy = limited(folder.path(), 10);
        let mut reader = FileReader::new(&policy);
        assert_eq!(reader.read(&folder.path().join("a")).unwrap().len(), 6);
        assert!(matches!(
            reader.read(&folder.path().join("b")),
            Err(LoadError::TooLarge { limit: 10, .. })
        ));
    }
}
