//! The watched set: which files a project depends on, which folders to watch for them, and which
//! file-system events concern them.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use notify::event::{AccessKind, AccessMode};
use notify::EventKind;

use crate::compile::lexical;
use crate::file_identity::identity;
use crate::geometry::{external_buffer_paths, FileReader, ReadPolicy};
use crate::spec::model::Project;

/// The files a build of the project at `project_path` reads: the project file itself, every
/// component's mesh and, for a `.gltf` mesh, the external files its buffers are read from (only
/// the mesh itself when it cannot be read), each as a [`watch_key`]. Only files in folders
/// `policy` lets a build read are listed (a mesh that does not exist yet is, and so is one that
/// is now a link to a device). Sorted and without duplicates.
pub fn referenced_files(
    project_path: &Path,
    project: Option<&Project>,
    policy: &ReadPolicy,
) -> BTreeSet<PathBuf> {
    let mut files = BTreeSet::new();
    files.insert(watch_key(project_path));
    let reader = FileReader::new(policy);
    if let Some(project) = project {
        // A rig's thousands of parts are one file: it is looked at once.
        let mut seen = BTreeSet::new();
        for component in &project.components {
            let mesh = &component.mesh.value;
            // Judged by its folder: a mesh replaced by a link to a device stays watched, so
            // putting the real file back is seen.
            let folder = match mesh.parent() {
                Some(folder) if !folder.as_os_str().is_empty() => folder,
                _ => Path::new("."),
            };
            if !seen.insert(mesh) || (folder.exists() && !reader.allows(folder)) {
                continue;
            }
            files.insert(watch_key(mesh));
            files.extend(
                external_buffer_paths(mesh, policy)
                    .iter()
                    .map(|path| watch_key(path)),
            );
        }
    }
    files
}

/// The folders to watch (non-recursively) to see every change to `files`: their parents. Watching
/// the folder rather than the file keeps the watch alive when an editor replaces the file by
/// renaming another over it, or deletes and re-creates it.
pub fn watched_folders(files: &BTreeSet<PathBuf>) -> BTreeSet<PathBuf> {
    files
        .iter()
        .filter_map(|file| file.parent().map(Path::to_path_buf))
        .collect()
}

/// The form of `path` that events are compared in: absolute, with `.` and `..` resolved, its folder
/// canonical (symbolic links followed) when it exists. Event paths are the watched folder joined
/// with the file name, so they compare equal to this.
pub fn watch_key(path: &Path) -> PathBuf {
    let absolute = lexical(path);
    match (absolute.parent(), absolute.file_name()) {
        (Some(folder), Some(name)) => match folder.canonicalize() {
            Ok(folder) => folder.join(name),
            Err(_) => absolute,
        },
        _ => absolute,
    }
}

/// Whether an event of this kind can mean a file's content changed. Reads are left out: a build
/// reads the watched files, and reacting to its own `Access(Open)` or read-only `Access(Close)`
/// events would rebuild forever.
pub fn is_change(kind: &EventKind) -> bool {
    matches!(
        kind,
        EventKind::Create(_)
            | EventKind::Modify(_)
            | EventKind::Remove(_)
            | EventKind::Access(AccessKind::Close(AccessMode::Write))
            | EventKind::Any
    )
}

/// The watched files among `paths` (an event's paths: both ends of a rename), and every watched
/// file in a folder that is one of `paths` (the folder itself removed, renamed or created again).
pub fn touched<'a>(
    paths: impl IntoIterator<Item = &'a PathBuf>,
    files: &BTreeSet<PathBuf>,
) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for path in paths {
        if files.contains(path) {
            found.push(path.clone());
        }
        found.extend(
            files
                .iter()
                .filter(|file| file.parent() == Some(path.as_path()))
                .cloned(),
        );
    }
    found
}

/// The folders to watch so that each of `folders` is seen to be removed and created again: their
/// parents (a folder's own watch ends with it). Those already among `folders` are left out.
pub fn anchor_folders(folders: &BTreeSet<PathBuf>) -> BTreeSet<PathBuf> {
    folders
        .iter()
        .filter_map(|folder| folder.parent().map(Path::to_path_buf))
        .filter(|parent| !folders.contains(parent))
        .collect()
}

/// What tells a folder from another made later at the same path: its device and inode (on Unix;
/// elsewhere only whether it exists). `None` when there is no folder there.
pub fn folder_identity(path: &Path) -> Option<(u64, u64)> {
    let metadata = std::fs::metadata(path).ok().filter(|m| m.is_dir())?;
    Some(identity(&metadata).unwrap_or((0, 0)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use notify::event::{CreateKind, DataChange, ModifyKind, RemoveKind, RenameMode};

    #[test]
    fn keys_resolve_dots_and_relative_paths() {
        let folder = tempfile::tempdir().unwrap();
        let inner = folder.path().join("a");
        std::fs::create_dir(&inner).unwrap();
        let direct = watch_key(&inner.join("x.obj"));
        let dotted = watch_key(&folder.path().join("a/./../a/x.obj"));
        assert_eq!(direct, dotted);
        assert!(direct.is_absolute());
        assert_eq!(
            direct,
            folder.path().canonicalize().unwrap().join("a/x.obj")
        );
    }

    #[test]
    fn a_gltf_mesh_brings_its_external_buffers_and_not_its_data_uris() {
        let folder = tempfile::tempdir().unwrap();
        let meshes = folder.path().join("meshes");
        std::fs::create_dir(&meshes).unwrap();
        let json = r#"{"asset": {"version": "2.0"}, "buffers": [
            {"uri": "a.bin", "byteLength": 4},
            {"uri": "data:application/octet-stream;base64,AAAAAA==", "byteLength": 4}
        ]}"#;
        std::fs::write(meshes.join("m.gltf"), json).unwrap();
        let project_path = folder.path().join("model.kdl");
        let source = "component \"M\" mesh=\"meshes/m.gltf\"\npose \"up\" { stand }\n";
        std::fs::write(&project_path, source).unwrap();
        let project = crate::spec::parse_project(source, &project_path)
            .project
            .unwrap();
        std::fs::write(meshes.join("a.bin"), [0; 4]).unwrap();
        let policy = ReadPolicy::within(folder.path());
        let files: Vec<PathBuf> = referenced_files(&project_path, Some(&project), &policy)
            .into_iter()
            .collect();
        let root = folder.path().canonicalize().unwrap();
        assert_eq!(
            files,
            vec![
                root.join("meshes/a.bin"),
                root.join("meshes/m.gltf"),
                root.join("model.kdl"),
            ]
        );
    }

    #[test]
    fn a_missing_gltf_mesh_is_listed_alone() {
        let folder = tempfile::tempdir().unwrap();
        let project_path = folder.path().join("model.kdl");
        let source = "component \"M\" mesh=\"m.gltf\"\npose \"up\" { stand }\n";
        let project = crate::spec::parse_project(source, &project_path)
            .project
            .unwrap();
        let root = folder.path().canonicalize().unwrap();
        let policy = ReadPolicy::within(folder.path());
        let files: Vec<PathBuf> = referenced_files(&project_path, Some(&project), &policy)
            .into_iter()
            .collect();
        assert_eq!(files, vec![root.join("m.gltf"), root.join("model.kdl")]);
    }

    #[test]
    fn a_missing_folder_still_gives_an_absolute_key() {
        let key = watch_key(Path::new("no/such/folder/model.kdl"));
        assert!(key.is_absolute());
        assert!(key.ends_with("no/such/folder/model.kdl"));
    }

    #[test]
    fn folders_are_the_parents_without_duplicates() {
        let files: BTreeSet<PathBuf> = ["/p/model.kdl", "/p/meshes/a.obj", "/p/meshes/b.obj"]
            .iter()
            .map(PathBuf::from)
            .collect();
        let folders: Vec<PathBuf> = watched_folders(&files).into_iter().collect();
        assert_eq!(
            folders,
            vec![PathBuf::from("/p"), PathBuf::from("/p/meshes")]
        );
    }

    #[test]
    fn reads_are_not_changes() {
        assert!(!is_change(&EventKind::Access(AccessKind::Open(
            AccessMode::Any
        ))));
        assert!(!is_change(&EventKind::Access(AccessKind::Close(
            AccessMode::Read
        ))));
        assert!(is_change(&EventKind::Access(AccessKind::Close(
            AccessMode::Write
        ))));
        assert!(is_change(&EventKind::Create(CreateKind::File)));
        assert!(is_change(&EventKind::Remove(RemoveKind::File)));
        assert!(is_change(&EventKind::Modify(ModifyKind::Data(
            DataChange::Content
        ))));
        assert!(is_change(&EventKind::Modify(ModifyKind::Name(
            RenameMode::Both
        ))));
    }

    #[test]
    fn only_watched_paths_are_touched() {
        let files: BTreeSet<PathBuf> = ["/p/model.kdl"].iter().map(PathBuf::from).collect();
        // A rename over the project file names the temp file and the project file.
        let rename = [
            PathBuf::from("/p/.model.kdl.tmp"),
            PathBuf::from("/p/model.kdl"),
        ];
        assert_eq!(
            touched(&rename, &files),
            vec![PathBuf::from("/p/model.kdl")]
        );
        let output = [PathBuf::from("/p/model.solution.kdl")];
        assert!(touched(&output, &files).is_empty());
        // The folder itself removed or made again touches every file in it, and only those.
        let folder = [PathBuf::from("/p")];
        assert_eq!(
            touched(&folder, &files),
            vec![PathBuf::from("/p/model.kdl")]
        );
        assert!(touched(&[PathBuf::from("/")], &files).is_empty());
    }
}
