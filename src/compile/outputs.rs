//! Writing a compilation's outputs: the glTF file, the JSON report and, for an optimized design,
//! the solution file, each replaced whole (atomically) only once all are encoded.

use std::path::{Path, PathBuf};

use super::{output_path, solution_text, Compilation, DesignSource, Report};
use crate::emit::{write_atomic, write_glb};

/// Encodes every output of `compilation` (the project read from `path`), then writes each one
/// atomically where the project says, or into `out_dir`; returns the paths written, in order.
/// Nothing is written when an output cannot be encoded.
pub fn write_outputs(
    compilation: &Compilation,
    path: &Path,
    out_dir: Option<&Path>,
) -> Result<Vec<PathBuf>, String> {
    let glb = write_glb(&compilation.scene())
        .map_err(|error| format!("cannot encode the glTF file: {error}"))?;
    let report = Report::new(compilation, path).to_json();
    let output = &compilation.project.output;
    let mut targets = vec![
        (output_path(&output.gltf, out_dir), glb),
        (output_path(&output.report, out_dir), report.into_bytes()),
    ];
    if compilation.source == DesignSource::Optimized {
        let text = solution_text(
            &compilation.project,
            &path
                .file_name()
                .map(|name| name.to_string_lossy().into_owned())
                .unwrap_or_default(),
            &compilation.meshes,
            &compilation.design,
        );
        targets.push((output_path(&output.solution, out_dir), text.into_bytes()));
    }
    // Every output is encoded before any is written; each write replaces its file whole.
    for (target, bytes) in &targets {
        write_output(target, bytes)
            .map_err(|error| format!("cannot write {}: {error}", target.display()))?;
    }
    Ok(targets.into_iter().map(|(target, _)| target).collect())
}

fn write_output(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    if let Some(folder) = path
        .parent()
        .filter(|folder| !folder.as_os_str().is_empty())
    {
        std::fs::create_dir_all(folder)?;
    }
    write_atomic(path, bytes)
}
