//! Writing a compilation's outputs: the glTF file, the JSON report, the print files (an STL per
//! component, the PrusaSlicer 3MF, the insertion sheet and its pictures) and, for an optimized
//! design, the solution file, each replaced whole (atomically) only once all are encoded.

use std::path::{Path, PathBuf};

use super::{
    bed_parts, output_path, print_settings, solution_text, Compilation, DesignSource, Report,
};
use crate::emit::print_files::{file_name, write_prusa_3mf, write_sheet, write_stl};
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
    targets.extend(print_files(compilation, path, out_dir)?);
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

/// The print files of `compilation`, encoded: each component's STL in the `stl` folder, the
/// PrusaSlicer project, the insertion sheet and its pictures beside it.
fn print_files(
    compilation: &Compilation,
    path: &Path,
    out_dir: Option<&Path>,
) -> Result<Vec<(PathBuf, Vec<u8>)>, String> {
    let output = &compilation.project.output;
    let parts = bed_parts(
        &compilation.project,
        &compilation.meshes,
        &compilation.design,
        &compilation.print_plan,
    );
    let settings = print_settings(&compilation.project, &compilation.design);
    let folder = output_path(&output.stl, out_dir);
    let mut targets: Vec<(PathBuf, Vec<u8>)> = parts
        .iter()
        .map(|part| {
            (
                folder.join(format!("{}.stl", file_name(&part.name))),
                write_stl(part),
            )
        })
        .collect();
    let prusa = write_prusa_3mf(&parts, &settings)
        .map_err(|error| format!("cannot encode the PrusaSlicer project: {error}"))?;
    targets.push((output_path(&output.prusa, out_dir), prusa));
    let sheet_path = output_path(&output.sheet, out_dir);
    let stem = sheet_path.file_stem().map_or_else(
        || "insertion".into(),
        |stem| stem.to_string_lossy().into_owned(),
    );
    let title = path
        .file_name()
        .map(|name| name.to_string_lossy().into_owned())
        .unwrap_or_default();
    let sheet = write_sheet(&title, &parts, &settings, &stem);
    let pictures = sheet_path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    targets.push((sheet_path, sheet.markdown.into_bytes()));
    for (name, svg) in sheet.pictures {
        targets.push((pictures.join(name), svg.into_bytes()));
    }
    Ok(targets)
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
