//! Opening a file ballast reads: only a regular file, never blocking on a pipe, never reading
//! past a limit. A device such as `/dev/zero` would be read until memory runs out and a pipe would
//! block forever; both are refused here, whether named directly or through a link.

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;

/// Opens the regular file at `path` (links followed) for reading. Anything else (a folder, a
/// device, a pipe, a socket) is an error of kind [`io::ErrorKind::InvalidInput`]. Opening a pipe
/// does not wait for a writer: the file is opened without blocking, then its kind checked.
pub fn open_regular(path: &Path) -> io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // Reads of a regular file ignore the flag; opening a pipe returns at once with it.
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    let metadata = file.metadata()?;
    if !metadata.is_file() {
        let kind = if metadata.is_dir() {
            "a folder"
        } else {
            "not a regular file (a device, a pipe or a socket)"
        };
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} is {kind}", path.display()),
        ));
    }
    Ok(file)
}

/// The whole of the regular file at `path` ([`open_regular`]) when it holds at most `limit`
/// bytes; an error of kind [`io::ErrorKind::FileTooLarge`] otherwise. The size is checked before
/// reading, and the read stops past the limit should the file grow meanwhile.
pub fn read_limited(path: &Path, limit: u64) -> io::Result<Vec<u8>> {
    let file = open_regular(path)?;
    let length = file.metadata()?.len();
    let too_large = |length: u64| {
        io::Error::new(
            io::ErrorKind::FileTooLarge,
            format!(
                "{} is {length} bytes long or more; the most read is {limit} bytes",
                path.display()
            ),
        )
    };
    if length > limit {
        return Err(too_large(length));
    }
    let mut bytes = Vec::with_capacity(length as usize);
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

/// The BLAKE3 hash of the regular file at `path` ([`open_regular`]), read in pieces: memory
/// stays small whatever the file's size.
pub fn blake3_of(path: &Path) -> io::Result<blake3::Hash> {
    let mut hasher = blake3::Hasher::new();
    hasher.update_reader(open_regular(path)?)?;
    Ok(hasher.finalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_regular_files_within_the_limit_are_read() {
        let folder = tempfile::tempdir().unwrap();
        let file = folder.path().join("a.txt");
        std::fs::write(&file, "12345").unwrap();
        assert_eq!(read_limited(&file, 5).unwrap(), b"12345");
        let error = read_limited(&file, 4).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::FileTooLarge);
        assert_eq!(
            blake3_of(&file).unwrap(),
            blake3::hash(b"12345"),
            "hashed in pieces as in one"
        );
        let error = read_limited(folder.path(), 100).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
        #[cfg(unix)]
        {
            let error = read_limited(Path::new("/dev/zero"), 100).unwrap_err();
            assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
            let link = folder.path().join("zero");
            std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
            assert_eq!(
                blake3_of(&link).unwrap_err().kind(),
                io::ErrorKind::InvalidInput
            );
        }
    }

    #[cfg(unix)]
    #[test]
    fn a_pipe_is_refused_without_waiting_for_a_writer() {
        let folder = tempfile::tempdir().unwrap();
        let fifo = folder.path().join("fifo");
        let name = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: `name` is a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
        let error = open_regular(&fifo).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
    }
}
