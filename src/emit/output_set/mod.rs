//! Replacing a set of files as one: after a kill at any point, the set is either all old or all
//! new once the next writer (or reader) has run [`finish_interrupted`].
//!
//! [`replace_set`] goes in four steps:
//! 1. every new file is written to a temporary sibling of its target and synced
//!    ([`write_temp`]); a failure here (a read-only folder, a full disk) removes those temporary
//!    files and leaves every old file as it was;
//! 2. the journal, naming each temporary file and its target, and the files of the previous set
//!    that the new one no longer has, is written atomically: the commit point;
//! 3. each temporary file is renamed over its target, in the set's order, then those files of the
//!    previous set are removed;
//! 4. the manifest, naming every file of the new set with the hash of what was written, replaces
//!    the old one, and the journal is removed.
//!
//! A kill before step 2 leaves the old set and some temporary files, which the next
//! [`replace_set`] removes ([`remove_stale_temps`]); a kill after it leaves a journal, which the
//! next [`finish_interrupted`] completes (renaming what is left, removing what is no longer in the
//! set, writing the manifest), so the set becomes the new one.
//!
//! Neither the journal nor the manifest is trusted: anyone who can write the folder can write
//! them. Every file they name is checked against the caller's [`Scope`] (the outputs the project
//! being built can have, never one of its inputs), and both are read only as regular files within
//! [`MAX_RECORD_BYTES`]. A file of the previous set is removed only when the manifest names it,
//! the scope allows it, it still holds exactly the bytes written then (its BLAKE3 hash), and no
//! file of the new set is it: a file ballast did not write, or that someone changed since, is
//! never removed. An interrupted replacement renames its temporary files only onto targets the
//! scope allows.

use std::collections::{BTreeMap, BTreeSet};
use std::ffi::OsString;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use super::atomic::{folder_of, sync_dir, write_atomic, write_temp, TempName};
use crate::file_identity::identity;
use crate::regular_file::{blake3_of, read_limited};

mod records;

pub use records::{manifest_path, MAX_RECORD_BYTES};
use records::{read_manifest, write_manifest, Journal, JournalEntry, WrittenFile, JOURNAL_FORMAT};

/// Which files named by a journal or manifest (an earlier build's record, not trusted) a set
/// may touch.
pub trait Scope {
    /// Whether finishing an interrupted replacement may rename a temporary file onto `target`.
    fn may_replace(&self, target: &Path) -> bool;
    /// Whether `path`, a file of the previous set that the new one does not write, may be
    /// removed (it is then removed only if it still holds what was written to it).
    fn may_remove(&self, path: &Path) -> bool;
}

/// Replaces the files `files` (path, new bytes), in that order, as one set, with the journal at
/// `journal` (and the manifest at [`manifest_path`]): first finishes an interrupted replacement
/// recorded there and removes temporary files that earlier writers of these targets (or of the
/// previous set's) left, then the four steps of the module's documentation. Files of the previous
/// set that this one does not have are removed where `scope` allows; returns them. An error
/// before the commit point leaves every old file as it was; an error renaming leaves the
/// journal, so the next call finishes the set.
pub fn replace_set(
    journal: &Path,
    files: &[(PathBuf, Vec<u8>)],
    scope: &dyn Scope,
) -> io::Result<Vec<PathBuf>> {
    finish_interrupted(journal, scope)?;
    let targets: Vec<PathBuf> = files
        .iter()
        .map(|(path, _)| std::path::absolute(path))
        .collect::<io::Result<_>>()?;
    let journal = std::path::absolute(journal)?;
    let manifest = manifest_path(&journal);
    let previous: Vec<(PathBuf, Option<String>)> = read_manifest(&manifest)
        .into_iter()
        .filter(|(path, _)| scope.may_remove(path))
        .collect();
    remove_stale_temps(
        targets
            .iter()
            .chain([&journal, &manifest])
            .chain(previous.iter().map(|(path, _)| path)),
    );
    check_targets(&targets)?;
    let remove: Vec<WrittenFile> = previous
        .into_iter()
        .filter(|(path, hash)| {
            !targets
                .iter()
                .any(|target| target == path || same_file(target, path))
                && still_written(path, hash.as_deref())
        })
        .map(|(path, blake3)| {
            Ok(WrittenFile {
                path: utf8(&path)?.to_owned(),
                blake3,
            })
        })
        .collect::<io::Result<_>>()?;

    let written: Vec<WrittenFile> = targets
        .iter()
        .zip(files)
        .map(|(target, (_, bytes))| {
            Ok(WrittenFile {
                path: utf8(target)?.to_owned(),
                blake3: Some(blake3::hash(bytes).to_hex().to_string()),
            })
        })
        .collect::<io::Result<_>>()?;

    let mut temps: Vec<PathBuf> = Vec::with_capacity(files.len());
    let committed = (|| {
        for (target, (_, bytes)) in targets.iter().zip(files) {
            temps.push(write_temp(target, bytes)?);
        }
        let entries = written
            .iter()
            .zip(&temps)
            .map(|(file, temp)| {
                Ok(JournalEntry {
                    target: file.path.clone(),
                    temp: utf8(Path::new(temp.file_name().unwrap_or_default()))?.to_owned(),
                    blake3: file.blake3.clone(),
                })
            })
            .collect::<io::Result<Vec<_>>>()?;
        let text = serde_json::to_string_pretty(&Journal {
            ballast_output_set: JOURNAL_FORMAT,
            files: entries,
            remove: remove.clone(),
        })
        .map_err(io::Error::other)?;
        write_atomic(&journal, text.as_bytes())
    })();
    if let Err(error) = committed {
        for temp in &temps {
            let _ = fs::remove_file(temp);
        }
        return Err(error);
    }
    complete(&journal, targets.iter().zip(&temps), &remove, &written)
}

/// Completes the replacement recorded in the journal at `journal`, if there is one: renames each
/// temporary file still there over its target, removes the previous set's files it names that
/// still hold what was written to them, writes the manifest, then removes the journal. A journal
/// that does not read as one (not written by ballast, not a regular file, larger than
/// [`MAX_RECORD_BYTES`]) is removed unread; an entry whose target `scope` does not allow, or
/// whose temporary file is not ballast's temporary file of that very target, is skipped, and so
/// is a file to remove that `scope` does not allow.
pub fn finish_interrupted(journal: &Path, scope: &dyn Scope) -> io::Result<()> {
    let journal = &std::path::absolute(journal)?;
    let text = match read_limited(journal, MAX_RECORD_BYTES) {
        Ok(text) => text,
        Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(()),
        Err(error)
            if matches!(
                error.kind(),
                io::ErrorKind::InvalidInput | io::ErrorKind::FileTooLarge
            ) =>
        {
            return remove_journal(journal)
        }
        Err(error) => return Err(error),
    };
    let Some(read) = serde_json::from_slice::<Journal>(&text)
        .ok()
        .filter(|read| read.ballast_output_set == JOURNAL_FORMAT)
    else {
        return remove_journal(journal);
    };
    let pairs: Vec<(PathBuf, PathBuf)> = read
        .files
        .iter()
        .filter_map(|entry| {
            let target = PathBuf::from(&entry.target);
            let name = TempName::parse(entry.temp.as_ref())?;
            (target.is_absolute()
                && Some(name.target.as_os_str()) == target.file_name()
                && scope.may_replace(&target))
            .then(|| (folder_of(&target).join(&entry.temp), target))
        })
        .collect();
    let written: Vec<WrittenFile> = read
        .files
        .iter()
        .filter(|entry| scope.may_replace(Path::new(&entry.target)))
        .map(|entry| WrittenFile {
            path: entry.target.clone(),
            blake3: entry.blake3.clone(),
        })
        .collect();
    let remove: Vec<WrittenFile> = read
        .remove
        .into_iter()
        .filter(|file| {
            Path::new(&file.path).is_absolute() && scope.may_remove(Path::new(&file.path))
        })
        .collect();
    complete(
        journal,
        pairs.iter().map(|(temp, target)| (target, temp)),
        &remove,
        &written,
    )?;
    Ok(())
}

/// Steps 3 and 4: renames each temporary file over its target (one already gone was renamed by a
/// finisher running at the same time), removes the files of `remove` that still hold what was
/// written to them, syncs the folders, writes the manifest of the set `written`, then removes the
/// journal; returns the files removed. On the first failure to rename the journal stays, so the
/// set is finished later.
fn complete<'a>(
    journal: &Path,
    pairs: impl Iterator<Item = (&'a PathBuf, &'a PathBuf)>,
    remove: &[WrittenFile],
    written: &[WrittenFile],
) -> io::Result<Vec<PathBuf>> {
    let mut folders = BTreeSet::new();
    for (target, temp) in pairs {
        match fs::rename(temp, target) {
            Ok(()) => {}
            Err(error) if error.kind() == io::ErrorKind::NotFound && !temp.exists() => {}
            Err(error) => {
                return Err(io::Error::new(
                    error.kind(),
                    format!(
                        "{error} (replacing {}; the next build finishes replacing the outputs)",
                        target.display()
                    ),
                ))
            }
        }
        folders.insert(folder_of(target));
    }
    let mut removed = Vec::new();
    for file in remove {
        let path = PathBuf::from(&file.path);
        if still_written(&path, file.blake3.as_deref()) && fs::remove_file(&path).is_ok() {
            folders.insert(folder_of(&path));
            removed.push(path);
        }
    }
    for folder in &folders {
        sync_dir(folder);
    }
    write_manifest(&manifest_path(journal), written)?;
    remove_journal(journal)?;
    Ok(removed)
}

/// Whether `path` is a regular file (not a link, not a folder) that holds exactly the bytes of
/// hash `blake3`; never when the hash is not known.
fn still_written(path: &Path, blake3: Option<&str>) -> bool {
    let Some(expected) = blake3 else {
        return false;
    };
    if !fs::symlink_metadata(path).is_ok_and(|metadata| metadata.is_file()) {
        return false;
    }
    blake3_of(path).is_ok_and(|hash| hash.to_hex().as_str() == expected)
}

/// Whether `a` and `b` are one existing file (a link or another spelling of one path included:
/// the same device and inode on Unix).
pub fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(first), Ok(second)) = (fs::metadata(a), fs::metadata(b)) else {
        return false;
    };
    match (identity(&first), identity(&second)) {
        (Some(first), Some(second)) => first == second,
        _ => matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b),
    }
}

fn remove_journal(journal: &Path) -> io::Result<()> {
    match fs::remove_file(journal) {
        Ok(()) => {
            sync_dir(&folder_of(journal));
            Ok(())
        }
        Err(error) if error.kind() == io::ErrorKind::NotFound => Ok(()),
        Err(error) => Err(error),
    }
}

/// Removes, in the folder of each of `targets`, the temporary files ballast's writers of that
/// target left behind when they were killed ([`TempName::is_stale`]). Nothing else is touched:
/// not another program's files, not a temporary file of another name, not one whose writer still
/// runs. Errors are ignored: a file left behind is removed by a later build.
pub fn remove_stale_temps<'a>(targets: impl Iterator<Item = &'a PathBuf>) {
    let mut names: BTreeMap<PathBuf, BTreeSet<OsString>> = BTreeMap::new();
    for target in targets {
        if let Some(name) = target.file_name() {
            names
                .entry(folder_of(target))
                .or_default()
                .insert(name.to_os_string());
        }
    }
    for (folder, names) in names {
        let Ok(entries) = fs::read_dir(&folder) else {
            continue;
        };
        for entry in entries.flatten() {
            let Some(temp) = TempName::parse(&entry.file_name()) else {
                continue;
            };
            let path = entry.path();
            let is_file = entry.file_type().is_ok_and(|kind| kind.is_file());
            if is_file && names.contains(&temp.target) && temp.is_stale(&path) {
                let _ = fs::remove_file(&path);
            }
        }
    }
}

/// Refuses a set that names one target twice or a target that is a folder, before anything is
/// written, since renaming onto it would fail half-way.
fn check_targets(targets: &[PathBuf]) -> io::Result<()> {
    let mut seen = BTreeSet::new();
    for target in targets {
        if !seen.insert(target) {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{} is written twice", target.display()),
            ));
        }
        if fs::symlink_metadata(target).is_ok_and(|metadata| metadata.is_dir()) {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{} is a folder", target.display()),
            ));
        }
    }
    Ok(())
}

fn utf8(path: &Path) -> io::Result<&str> {
    path.to_str().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} is not UTF-8", path.display()),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every file inside a folder, except those listed.
    struct Within<'a> {
        folder: &'a Path,
        except: Vec<PathBuf>,
    }

    impl Scope for Within<'_> {
        fn may_replace(&self, target: &Path) -> bool {
            target.starts_with(self.folder) && !self.except.iter().any(|e| e == target)
        }
        fn may_remove(&self, path: &Path) -> bool {
            self.may_replace(path)
        }
    }

    fn within(folder: &Path) -> Within<'_> {
        Within {
            folder,
            except: Vec::new(),
        }
    }

    fn set(dir: &Path, content: &str) -> Vec<(PathBuf, Vec<u8>)> {
        ["a.glb", "sub/b.json", "c.kdl"]
            .iter()
            .map(|name| (dir.join(name), format!("{content} {name}").into_bytes()))
            .collect()
    }

    fn read(files: &[(PathBuf, Vec<u8>)]) -> Vec<Option<Vec<u8>>> {
        files.iter().map(|(path, _)| fs::read(path).ok()).collect()
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_set_replaces_every_file_and_leaves_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let journal = dir.path().join(".journal");
        let old = set(dir.path(), "old");
        replace_set(&journal, &old, &within(dir.path())).unwrap();
        let new = set(dir.path(), "new");
        replace_set(&journal, &new, &within(dir.path())).unwrap();
        let expected: Vec<_> = new.iter().map(|(_, b)| Some(b.clone())).collect();
        assert_eq!(read(&new), expected);
        assert_eq!(
            names(dir.path()),
            [".journal.manifest", "a.glb", "c.kdl", "sub"]
        );
        assert_eq!(names(&dir.path().join("sub")), ["b.json"]);
    }

    #[test]
    fn files_the_new_set_lacks_are_removed_unless_protected_or_changed() {
        let dir = tempfile::tempdir().unwrap();
        let journal = dir.path().join(".journal");
        let old = set(dir.path(), "old");
        replace_set(&journal, &old, &within(dir.path())).unwrap();
        // The new set has only `a.glb`; `sub/b.json` is protected (an input), `c.kdl` not.
        let new = vec![old[0].clone()];
        let b = old[1].0.clone();
        let scope = Within {
            folder: dir.path(),
            except: vec![b.clone()],
        };
        let removed = replace_set(&journal, &new, &scope).unwrap();
        assert_eq!(removed, [std::path::absolute(&old[2].0).unwrap()]);
        assert!(!old[2].0.exists() && b.exists());
        // Still in the manifest? No: the manifest names the set last written, `a.glb` alone, so
        // `sub/b.json` is not ballast's to remove any more.
        let removed = replace_set(&journal, &new, &within(dir.path())).unwrap();
        assert!(removed.is_empty() && b.exists());
        // A file of the set changed since it was written is not removed.
        replace_set(&journal, &old, &within(dir.path())).unwrap();
        fs::write(&old[2].0, "edited").unwrap();
        let removed = replace_set(&journal, &new, &within(dir.path())).unwrap();
        assert_eq!(removed, [std::path::absolute(&old[1].0).unwrap()]);
        assert_eq!(fs::read(&old[2].0).unwrap(), b"edited");
    }

    #[test]
    fn a_journal_left_by_a_kill_is_finished_and_a_foreign_one_is_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let journal = dir.path().join(".journal");
        let old = set(dir.path(), "old");
        replace_set(&journal, &old, &within(dir.path())).unwrap();
        // What a kill after the commit point, with the first file renamed, leaves.
        let new = set(dir.path(), "new");
        let temps: Vec<PathBuf> = new.iter().map(|(p, b)| write_temp(p, b).unwrap()).collect();
        let entries: Vec<JournalEntry> = new
            .iter()
            .zip(&temps)
            .map(|((target, _), temp)| JournalEntry {
                target: target.to_str().unwrap().into(),
                temp: temp.file_name().unwrap().to_str().unwrap().into(),
                blake3: None,
            })
            .collect();
        let text = serde_json::to_string(&Journal {
            ballast_output_set: JOURNAL_FORMAT,
            files: entries,
            remove: Vec::new(),
        })
        .unwrap();
        fs::write(&journal, text).unwrap();
        fs::rename(&temps[0], &new[0].0).unwrap();
        finish_interrupted(&journal, &within(dir.path())).unwrap();
        let expected: Vec<_> = new.iter().map(|(_, b)| Some(b.clone())).collect();
        assert_eq!(read(&new), expected);
        assert!(!journal.exists());

        // A journal naming a file that is not ballast's temporary file of that target moves
        // nothing.
        fs::write(dir.path().join("mine.txt"), "user").unwrap();
        let forged = format!(
            r#"{{"ballast_output_set":1,"files":[{{"target":"{}","temp":"mine.txt"}}]}}"#,
            new[0].0.display()
        );
        fs::write(&journal, forged).unwrap();
        finish_interrupted(&journal, &within(dir.path())).unwrap();
        assert_eq!(fs::read(&new[0].0).unwrap(), new[0].1);
        assert!(dir.path().join("mine.txt").exists());
        fs::write(&journal, "not json").unwrap();
        finish_interrupted(&journal, &within(dir.path())).unwrap();
        assert!(!journal.exists());
    }

    #[test]
    fn a_failure_before_the_commit_replaces_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let journal = dir.path().join(".journal");
        let old = set(dir.path(), "old");
        replace_set(&journal, &old, &within(dir.path())).unwrap();
        let before = read(&old);
        // The last target is a folder: refused before anything is written.
        let mut new = set(dir.path(), "new");
        fs::create_dir_all(dir.path().join("d")).unwrap();
        new.push((dir.path().join("d"), b"x".to_vec()));
        assert!(replace_set(&journal, &new, &within(dir.path())).is_err());
        assert_eq!(read(&old), before);
        // A file where a folder should be: fails while writing, after the first temporary file.
        let mut new = set(dir.path(), "new");
        new.push((dir.path().join("a.glb").join("inner"), b"x".to_vec()));
        assert!(replace_set(&journal, &new, &within(dir.path())).is_err());
        assert_eq!(read(&old), before);
        assert_eq!(
            names(dir.path()),
            [".journal.manifest", "a.glb", "c.kdl", "d", "sub"]
        );
    }

    #[test]
    fn only_stale_temporary_files_of_the_targets_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("model.glb");
        let mine = |name: &str, pid: u32| {
            let name = TempName {
                target: name.into(),
                pid,
                n: 7,
            };
            let path = dir.path().join(name.file_name());
            fs::write(&path, "partial").unwrap();
            path
        };
        // A process id no process has (beyond the kernel's limit).
        let dead = mine("model.glb", u32::MAX - 1);
        let live = mine("model.glb", std::process::id());
        let other_target = mine("notes.md", u32::MAX - 1);
        let user = dir.path().join(".model.glb.tmp");
        fs::write(&user, "user").unwrap();
        remove_stale_temps([&target].into_iter());
        if Path::new("/proc/self").exists() {
            assert!(!dead.exists());
        }
        assert!(live.exists());
        assert!(other_target.exists());
        assert!(user.exists());
    }
}
