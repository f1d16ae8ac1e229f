//! Where a build may write: never over a file it reads (the project, a mesh, a glTF buffer),
//! never one file twice, and inside the project's folder unless the user asked otherwise.
//!
//! Checked by [`check_output_paths`] before anything is computed, with the span of the `output`
//! child that named the path (or of the mesh a default path would overwrite); [`write_outputs`]
//! checks the files it is about to write against the inputs once more.
//!
//! [`write_outputs`]: super::write_outputs

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};

use miette::SourceSpan;

use super::{calibration_path, output_path};
use crate::diagnostic::Problem;
use crate::emit::output_set::same_file;
use crate::emit::print_files::file_name;
use crate::file_identity::identity;
use crate::geometry::{external_buffer_paths, ReadPolicy};
use crate::spec::model::Project;

/// An output path is a file the build reads: the project, a mesh or a glTF buffer.
pub const OVERWRITES_INPUT: &str = "ballast::output::overwrites_input";
/// Two outputs are one file.
pub const DUPLICATE_OUTPUT: &str = "ballast::output::duplicate";
/// An output path leaves the project's folder (absolute, or through `..`) without
/// `--write-outside`.
pub const OUTSIDE_PROJECT: &str = "ballast::output::outside_project";

/// The outputs of a build killed while it replaced them could not be finished (a warning: the
/// next build writes them all anew).
pub const INTERRUPTED_OUTPUTS: &str = "ballast::output::interrupted";

/// Where outputs may go, beyond what the project file says.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct WriteOptions {
    /// Accept output paths outside the project file's folder (`--write-outside`).
    pub outside_project: bool,
}

/// One file a build writes, and the `output` child that places it.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputTarget {
    /// Where it is written.
    pub path: PathBuf,
    /// The child of `output` that names it: `gltf`, `report`, `solution`, `stl`, `prusa`, `sheet`.
    pub node: &'static str,
}

/// Every file a build of `project` writes (the solution file only when it optimizes), in the
/// order [`write_outputs`](super::write_outputs) replaces them.
pub fn output_targets(project: &Project, out_dir: Option<&Path>) -> Vec<OutputTarget> {
    let output = &project.output;
    let target = |path: PathBuf, node| OutputTarget { path, node };
    let mut targets = vec![
        target(output_path(&output.gltf, out_dir), "gltf"),
        target(output_path(&output.report, out_dir), "report"),
    ];
    let stl = output_path(&output.stl, out_dir);
    for component in &project.components {
        let name = file_name(&component.name.value);
        targets.push(target(stl.join(format!("{name}.stl")), "stl"));
    }
    targets.push(target(output_path(&output.prusa, out_dir), "prusa"));
    let sheet = output_path(&output.sheet, out_dir);
    let stem = sheet
        .file_stem()
        .map_or_else(|| "insertion".into(), |s| s.to_string_lossy().into_owned());
    let folder = sheet.parent().map(Path::to_path_buf).unwrap_or_default();
    targets.push(target(sheet, "sheet"));
    for component in &project.components {
        let name = file_name(&component.name.value);
        targets.push(target(folder.join(format!("{stem}-{name}.svg")), "sheet"));
    }
    if project.optimize.is_some() {
        targets.push(target(output_path(&output.solution, out_dir), "solution"));
    }
    targets
}

/// The files a build of `project` (read from `project_path`) reads: the project file, its
/// calibration file (whether there is one yet or not), every component's mesh, the external
/// buffers of its glTF meshes that `policy` lets it read.
pub fn input_files(project: &Project, project_path: &Path, policy: &ReadPolicy) -> Vec<PathBuf> {
    spanned_inputs(project, project_path, policy)
        .into_iter()
        .map(|(path, _)| path)
        .collect()
}

/// [`input_files`], each with the span of the `mesh=` that reads it (none for the project file).
fn spanned_inputs(
    project: &Project,
    project_path: &Path,
    policy: &ReadPolicy,
) -> Vec<(PathBuf, Option<SourceSpan>)> {
    let mut inputs = vec![
        (project_path.to_path_buf(), None),
        (calibration_path(project_path), None),
    ];
    // A rig's thousands of parts are one file: its buffers are looked up once.
    let mut seen = std::collections::BTreeSet::new();
    for component in &project.components {
        let mesh = &component.mesh;
        if !seen.insert(&mesh.value) {
            continue;
        }
        inputs.push((mesh.value.clone(), Some(mesh.span)));
        for buffer in external_buffer_paths(&mesh.value, policy) {
            inputs.push((buffer, Some(mesh.span)));
        }
    }
    inputs
}

/// Where `paths` are, to tell in constant time whether a path is one of them: by lexical form,
/// and by device and inode for those that exist (a link, another spelling of one file).
struct FileIndex {
    lexical: HashMap<PathBuf, usize>,
    inode: HashMap<(u64, u64), usize>,
}

impl FileIndex {
    fn new() -> FileIndex {
        FileIndex {
            lexical: HashMap::new(),
            inode: HashMap::new(),
        }
    }

    /// The index of the first path added that is `path`'s file; `None` when there is none.
    fn find(&self, path: &Path) -> Option<usize> {
        let by_name = self.lexical.get(&lexical(path)).copied();
        let by_inode = inode(path).and_then(|key| self.inode.get(&key).copied());
        by_name.into_iter().chain(by_inode).min()
    }

    /// Adds `path` as number `index`, unless a path already added is its file.
    fn add(&mut self, path: &Path, index: usize) {
        self.lexical.entry(lexical(path)).or_insert(index);
        if let Some(key) = inode(path) {
            self.inode.entry(key).or_insert(index);
        }
    }
}

/// The device and inode of the existing file at `path` (links followed).
fn inode(path: &Path) -> Option<(u64, u64)> {
    identity(&std::fs::metadata(path).ok()?)
}

/// The problems of the output paths of `project`, read from `project_path` with text `source`,
/// written as `options` allow (into `out_dir` when given): an output that is an input, two outputs
/// that are one file, an output outside the project's folder (not checked with `out_dir`, which
/// the user chose). Empty when every output may be written.
pub fn check_output_paths(
    project: &Project,
    source: &str,
    project_path: &Path,
    out_dir: Option<&Path>,
    options: WriteOptions,
    policy: &ReadPolicy,
) -> Vec<Problem> {
    let targets = output_targets(project, out_dir);
    // Read again only when a problem needs a span.
    let lazy = std::cell::OnceCell::new();
    let spans = || lazy.get_or_init(|| OutputSpans::of(source));
    let inputs = spanned_inputs(project, project_path, policy);
    let mut read = FileIndex::new();
    for (index, (input, _)) in inputs.iter().enumerate() {
        read.add(input, index);
    }
    let mut problems = Vec::new();
    for target in &targets {
        let shown = target.path.display();
        let calibration = target.path.file_name().is_some_and(|name| {
            name.to_string_lossy()
                .to_lowercase()
                .ends_with(CALIBRATION_SUFFIX)
        });
        let input = read.find(&target.path).map(|index| inputs[index].clone());
        // Any project's calibration file is read by its builds, this project's or not.
        let calibration = calibration.then_some((target.path.clone(), None));
        if let Some((input, input_span)) = input.or(calibration) {
            let what = if lexical(&input) == lexical(&target.path) {
                if input
                    .to_string_lossy()
                    .to_lowercase()
                    .ends_with(CALIBRATION_SUFFIX)
                {
                    "a calibration file".to_owned()
                } else {
                    "a file".to_owned()
                }
            } else {
                input.display().to_string()
            };
            let mut problem = Problem::error(
                OVERWRITES_INPUT,
                format!(
                    "the `{}` output {shown} is {what}, which the build reads: writing it would destroy it",
                    target.node,
                ),
            )
            .with_help(format!(
                "name another path in `output {{ {} \"...\" }}`",
                target.node
            ));
            match (spans().get(target.node), input_span) {
                (Some(span), _) => problem = problem.with_label(span, "this output"),
                (None, Some(span)) => {
                    problem = problem.with_label(
                        span,
                        format!("the default `{}` output is this file", target.node),
                    )
                }
                (None, None) => {}
            }
            problems.push(problem);
        }
    }
    let mut written = FileIndex::new();
    for (index, target) in targets.iter().enumerate() {
        let earlier = written.find(&target.path);
        written.add(&target.path, index);
        if let Some(first) = earlier.map(|first| &targets[first]) {
            let message = if first.node == target.node {
                format!(
                    "the `{}` output writes {} twice: two components' names give one file name",
                    target.node,
                    target.path.display()
                )
            } else {
                format!(
                    "the `{}` and `{}` outputs are both {}",
                    first.node,
                    target.node,
                    target.path.display()
                )
            };
            let mut problem = Problem::error(DUPLICATE_OUTPUT, message)
                .with_help("give each output its own path");
            let mut nodes = vec![first.node, target.node];
            nodes.dedup();
            for node in nodes {
                if let Some(span) = spans().get(node) {
                    problem = problem.with_label(span, format!("the `{node}` output"));
                }
            }
            problems.push(problem);
        }
    }
    if out_dir.is_none() && !options.outside_project {
        let folder = lexical(&crate::emit::atomic::folder_of(project_path));
        let mut reported: Vec<&str> = Vec::new();
        for target in &targets {
            if lexical(&target.path).starts_with(&folder) || reported.contains(&target.node) {
                continue;
            }
            reported.push(target.node);
            let mut problem = Problem::error(
                OUTSIDE_PROJECT,
                format!(
                    "the `{}` output {} is outside the project's folder {}",
                    target.node,
                    target.path.display(),
                    folder.display()
                ),
            )
            .with_help(
                "name a path inside the project's folder, or pass `--write-outside` to write there (or `--out-dir DIR`)",
            );
            if let Some(span) = spans().get(target.node) {
                problem = problem.with_label(span, "this path");
            }
            problems.push(problem);
        }
    }
    problems
}

/// The suffixes of the files each `output` child writes, whatever a project names them: what may
/// be removed of an earlier build's outputs in the folder that child writes into.
fn output_suffixes(node: &str) -> &'static [&'static str] {
    match node {
        "gltf" => &[".glb", ".gltf"],
        "report" => &[".json"],
        "stl" => &[".stl"],
        "prusa" => &[".3mf"],
        "sheet" => &[".md", ".svg"],
        "solution" => &[".solution.kdl"],
        _ => &[],
    }
}

/// The suffix of every project's calibration file: a file builds read, never one they write.
const CALIBRATION_SUFFIX: &str = ".calibration.json";

/// What a build of a project may touch of the files an earlier build's journal and manifest
/// name (see [`crate::emit::output_set`]): neither record is trusted, so each file is checked
/// here, resolved (links in its folder's path followed).
///
/// - An interrupted replacement is finished only onto one of this build's own output files.
/// - A file of an earlier build is removed only when it has the suffix of an output of some kind
///   (`.glb` for `gltf`, `.json` for `report`, `.stl`, ...) and is in a folder this build writes
///   that kind into, is not a calibration file, and is none of the build's inputs, nor its
///   solution file (kept even when a build writes none: it is committed, and `check` reads it
///   when `optimize` comes back).
#[derive(Debug, Clone)]
pub struct OutputScope {
    /// This build's output files, resolved.
    targets: Vec<PathBuf>,
    /// Each folder this build writes outputs into, resolved, with the suffixes of those outputs.
    folders: Vec<(PathBuf, &'static [&'static str])>,
    /// The build's inputs and solution file, resolved.
    kept: Vec<PathBuf>,
}

impl OutputScope {
    /// The scope of a build of `project`, read from `project_path`, writing into `out_dir` if
    /// given. Every glTF buffer counts as an input, wherever it is.
    pub fn of(project: &Project, project_path: &Path, out_dir: Option<&Path>) -> OutputScope {
        let anywhere = ReadPolicy {
            within: None,
            limits: crate::geometry::MeshLimits::default(),
        };
        let mut targets = Vec::new();
        let mut folders = Vec::new();
        for target in output_targets(project, out_dir) {
            let Some(path) = resolved(&target.path) else {
                continue;
            };
            if let Some(folder) = path.parent() {
                folders.push((folder.to_path_buf(), output_suffixes(target.node)));
            }
            targets.push(path);
        }
        folders.sort();
        folders.dedup();
        let mut kept: Vec<PathBuf> = input_files(project, project_path, &anywhere)
            .iter()
            .chain([&output_path(&project.output.solution, out_dir)])
            .filter_map(|path| resolved(path))
            .collect();
        kept.sort();
        kept.dedup();
        OutputScope {
            targets,
            folders,
            kept,
        }
    }
}

impl crate::emit::output_set::Scope for OutputScope {
    fn may_replace(&self, target: &Path) -> bool {
        resolved(target).is_some_and(|target| self.targets.contains(&target))
    }

    fn may_remove(&self, path: &Path) -> bool {
        let Some(path) = resolved(path) else {
            return false;
        };
        let name = path
            .file_name()
            .map(|name| name.to_string_lossy().to_lowercase())
            .unwrap_or_default();
        let folder = path.parent().unwrap_or(Path::new(""));
        let of_an_output = self.folders.iter().any(|(output_folder, suffixes)| {
            output_folder == folder && suffixes.iter().any(|suffix| name.ends_with(suffix))
        });
        of_an_output
            && !name.ends_with(CALIBRATION_SUFFIX)
            && !self
                .kept
                .iter()
                .any(|kept| *kept == path || same_file(kept, &path))
    }
}

/// `path` with its folder resolved (made absolute, links followed) and its file name kept as it
/// is (a link there is the file itself, which is never followed when removing); `None` when its
/// folder does not exist or it names no file.
fn resolved(path: &Path) -> Option<PathBuf> {
    let name = match path.components().next_back()? {
        Component::Normal(name) => name,
        _ => return None,
    };
    let folder = match path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder,
        _ => Path::new("."),
    };
    Some(folder.canonicalize().ok()?.join(name))
}

/// `path` absolute, with `.` and `..` resolved lexically (symbolic links are not followed: a
/// link inside the project's folder is the user's choice).
pub(crate) fn lexical(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut out = PathBuf::new();
    for component in absolute.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The span of the path each child of the project's `output` node writes.
struct OutputSpans {
    spans: Vec<(String, SourceSpan)>,
}

impl OutputSpans {
    /// Read from the project text `source` (already parsed once without error).
    fn of(source: &str) -> OutputSpans {
        let mut spans = Vec::new();
        if let Ok(document) = crate::spec::syntax::read(source) {
            let children = document
                .nodes()
                .iter()
                .filter(|node| node.name().value() == "output")
                .filter_map(|node| node.children());
            for child in children.flat_map(|children| children.nodes()) {
                if let Some(entry) = child.entries().first() {
                    spans.push((child.name().value().to_owned(), entry.span()));
                }
            }
        }
        OutputSpans { spans }
    }

    fn get(&self, node: &str) -> Option<SourceSpan> {
        self.spans
            .iter()
            .find(|(name, _)| name == node)
            .map(|(_, span)| *span)
    }
}
