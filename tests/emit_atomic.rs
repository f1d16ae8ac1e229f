//! Atomic writes: a reader sees the old file or the whole new one, never debris.

use std::fs;
use std::path::Path;

use ballast::emit::write_atomic;

fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<_> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn writing_replaces_the_content() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.glb");
    write_atomic(&path, b"first version, rather long").unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"first version, rather long");
    write_atomic(&path, b"second").unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"second");
    write_atomic(&path, b"").unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"");
    assert_eq!(entries(dir.path()), ["model.glb"]);
}

#[test]
fn missing_parent_directories_are_created() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("build").join("poses").join("report.json");
    write_atomic(&path, b"{}").unwrap();
    assert_eq!(fs::read(&path).unwrap(), b"{}");
    assert_eq!(entries(&dir.path().join("build/poses")), ["report.json"]);
}

#[test]
fn a_parent_that_is_a_file_fails_and_leaves_everything_alone() {
    let dir = tempfile::tempdir().unwrap();
    let blocker = dir.path().join("build");
    fs::write(&blocker, b"not a directory").unwrap();
    let err = write_atomic(&blocker.join("model.glb"), b"new").unwrap_err();
    assert_ne!(err.kind(), std::io::ErrorKind::NotFound, "{err}");
    assert_eq!(fs::read(&blocker).unwrap(), b"not a directory");
    assert_eq!(entries(dir.path()), ["build"]);
}

#[test]
fn a_failed_rename_keeps_the_old_target_and_removes_the_temporary_file() {
    // The target is a non-empty directory: the new bytes are written and synced, but the
    // rename over it fails, so the temporary file has to be cleaned up.
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("model.glb");
    fs::create_dir(&target).unwrap();
    fs::write(target.join("old"), b"old content").unwrap();
    write_atomic(&target, b"new content").unwrap_err();
    assert_eq!(fs::read(target.join("old")).unwrap(), b"old content");
    assert_eq!(entries(dir.path()), ["model.glb"]);
    assert_eq!(entries(&target), ["old"]);
}

#[test]
fn a_path_without_a_file_name_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let err = write_atomic(&dir.path().join(".."), b"x").unwrap_err();
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidInput);
    assert!(entries(dir.path()).is_empty());
}
