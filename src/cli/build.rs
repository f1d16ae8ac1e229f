//! `ballast build`: check, optimize when the project asks, then write the glTF file, the JSON
//! report and the solution file atomically.

use std::path::{Path, PathBuf};

use super::{compile_file, file_name, goals_status, progress, table, EXIT_INVALID};
use crate::compile::{
    output_path, solution_text, Compilation, CompileOptions, DesignSource, Report, Workspace,
};
use crate::emit::{write_atomic, write_glb};

/// Builds the project at `path` as `options` say.
pub fn run(path: &Path, options: &CompileOptions) -> i32 {
    let mut workspace = Workspace {
        progress: progress::on_terminal(),
        ..Workspace::new()
    };
    let Ok(compilation) = compile_file(path, options, &mut workspace) else {
        return EXIT_INVALID;
    };
    let written = match write_outputs(&compilation, path, options) {
        Ok(written) => written,
        Err(message) => {
            eprintln!("error: {message}");
            return EXIT_INVALID;
        }
    };
    if let Some(optimization) = &compilation.optimization {
        print!("{}", table::optimization(optimization, &compilation));
    }
    print!("{}", table::summary(&compilation, &file_name(path)));
    for target in &written {
        println!("wrote {}", target.display());
    }
    goals_status(&compilation)
}

/// Encodes every output of `compilation` (the project read from `path`), then writes each one
/// atomically where the project and `options` say; returns the paths written, in order. Nothing
/// is written when an output cannot be encoded.
pub(super) fn write_outputs(
    compilation: &Compilation,
    path: &Path,
    options: &CompileOptions,
) -> Result<Vec<PathBuf>, String> {
    let glb = write_glb(&compilation.scene())
        .map_err(|error| format!("cannot encode the glTF file: {error}"))?;
    let report = Report::new(compilation, path).to_json();
    let output = &compilation.project.output;
    let out_dir = options.out_dir.as_deref();
    let mut targets = vec![
        (output_path(&output.gltf, out_dir), glb),
        (output_path(&output.report, out_dir), report.into_bytes()),
    ];
    if compilation.source == DesignSource::Optimized {
        let text = solution_text(
            &compilation.project,
            &file_name(path),
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
