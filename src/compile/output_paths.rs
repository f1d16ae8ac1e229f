//! Where a build may write: never over a file it reads (the project, a mesh, a glTF buffer),
//! never one file twice, and inside the project's folder unless the user asked otherwise.
//!
//! Checked by [`check_output_paths`] before anything is computed, with the span of the `output`
//! child that named the path (or of the mesh a default path would overwrite); [`write_outputs`]
//! checks the files it is about to write against the inputs once more.
//!
//! [`write_outputs`]: super::write_outputs

use std::path::{Component, Path, PathBuf};

use miette::SourceSpan;

use super::output_path;
use crate::diagnostic::Problem;
use crate::emit::output_set::same_file;
use crate::emit::print_files::file_name;
use crate::geometry::{external_buffer_paths, ReadPolicy};
use crate::spec::model::Project;

/// An output path is a file the build reads: the project, a mesh or a glTF buffer.
pub const OVERWRITES_INPUT: &str = "ballast::output::overwrites_input";
/// Two outputs are one file.
pub const DUPLICATE_OUTPUT: &str = "ballast::output::duplicate";
/// An output path leaves the project's folder (absolute, or through `..`) without
/// `--write-outside`.
pub const OUTSIDE_PROJECT: &str = "ballast::output::outside_project";

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

/// The files a build of `project` (read from `project_path`) reads: the project file, every
/// component's mesh, the external buffers of its glTF meshes that `policy` lets it read.
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
    let mut inputs = vec![(project_path.to_path_buf(), None)];
    for component in &project.components {
        let mesh = &component.mesh;
        inputs.push((mesh.value.clone(), Some(mesh.span)));
        for buffer in external_buffer_paths(&mesh.value, policy) {
            inputs.push((buffer, Some(mesh.span)));
        }
    }
    inputs
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
    let mut problems = Vec::new();
    for target in &targets {
        let shown = target.path.display();
        for (input, input_span) in &inputs {
            if !same_file(&target.path, input) {
                continue;
            }
            let mut problem = Problem::error(
                OVERWRITES_INPUT,
                format!(
                    "the `{}` output {shown} is {}, which the build reads: writing it would destroy it",
                    target.node,
                    input.display()
                ),
            )
            .with_help(format!(
                "name another path in `output {{ {} \"...\" }}`",
                target.node
            ));
            match (spans().get(target.node), *input_span) {
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
    for (index, target) in targets.iter().enumerate() {
        let key = lexical(&target.path);
        if let Some(first) = targets[..index]
            .iter()
            .find(|other| lexical(&other.path) == key || same_file(&other.path, &target.path))
        {
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
