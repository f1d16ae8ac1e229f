//! Reading a project or solution file from disk: only a regular file, and only when it is within
//! [`MAX_SOURCE_BYTES`], checked before a byte is read (a device such as `/dev/zero` or a pipe
//! would otherwise be read forever).

use std::io::Read;
use std::path::Path;

use super::codes::{FILE_NOT_REGULAR, FILE_TOO_LARGE, FILE_UNREADABLE, SOLUTION_UNREADABLE};
use super::syntax::{MAX_SOURCE_BYTES, TOO_LARGE_HELP};
use crate::diagnostic::Problem;

/// Reads the text of the project or solution file at `path` (`what` names it in messages:
/// "project file", "solution file"). `Ok(None)` when there is no file there; a problem when it
/// is not a regular file, is larger than [`MAX_SOURCE_BYTES`], or cannot be read as UTF-8 text
/// (that one [`FILE_UNREADABLE`]).
pub fn read_source(path: &Path, what: &str) -> Result<Option<String>, Box<Problem>> {
    read_coded(path, what, FILE_UNREADABLE)
}

/// [`read_source`] for the solution file at `path`: a file that cannot be read as UTF-8 text is
/// [`SOLUTION_UNREADABLE`], so that it is told from an unreadable project file.
pub fn read_solution_source(path: &Path) -> Result<Option<String>, Box<Problem>> {
    read_coded(path, "solution file", SOLUTION_UNREADABLE)
}

/// [`read_source`], a file that cannot be read being the problem `unreadable_code`.
fn read_coded(
    path: &Path,
    what: &str,
    unreadable_code: &'static str,
) -> Result<Option<String>, Box<Problem>> {
    let unreadable = |error: std::io::Error| {
        Box::new(Problem::error(
            unreadable_code,
            format!("cannot read the {what} {}: {error}", path.display()),
        ))
    };
    // `metadata` follows links and never blocks, unlike opening a pipe.
    let metadata = match std::fs::metadata(path) {
        Ok(metadata) => metadata,
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(error) => return Err(unreadable(error)),
    };
    check_metadata(&metadata, path, what)?;
    // Opened without blocking: a pipe put there since the first look is refused, not waited on.
    let file = crate::regular_file::open_regular(path).map_err(unreadable)?;
    // The file may have been replaced between the two looks.
    check_metadata(&file.metadata().map_err(unreadable)?, path, what)?;
    let mut text = String::new();
    file.take(MAX_SOURCE_BYTES as u64 + 1)
        .read_to_string(&mut text)
        .map_err(unreadable)?;
    if text.len() > MAX_SOURCE_BYTES {
        return Err(too_large(path, what, text.len() as u64));
    }
    Ok(Some(text))
}

/// Refuses anything but a regular file within the size limit.
fn check_metadata(
    metadata: &std::fs::Metadata,
    path: &Path,
    what: &str,
) -> Result<(), Box<Problem>> {
    if !metadata.is_file() {
        let kind = if metadata.is_dir() {
            "a folder"
        } else {
            "not a regular file (a device, a pipe or a socket)"
        };
        return Err(Box::new(
            Problem::error(
                FILE_NOT_REGULAR,
                format!("the {what} {} is {kind}", path.display()),
            )
            .with_help("ballast reads project and solution files only from regular files"),
        ));
    }
    if metadata.len() > MAX_SOURCE_BYTES as u64 {
        return Err(too_large(path, what, metadata.len()));
    }
    Ok(())
}

/// The problem for a file of `length` bytes, over the limit.
fn too_large(path: &Path, what: &str, length: u64) -> Box<Problem> {
    Box::new(
        Problem::error(
            FILE_TOO_LARGE,
            format!(
                "the {what} {} is {length} bytes long or more; the most ballast reads is \
             {MAX_SOURCE_BYTES} bytes",
                path.display()
            ),
        )
        .with_help(TOO_LARGE_HELP),
    )
}
