//! `ballast build`: check, then write the glTF file and the JSON report atomically.

use std::path::{Path, PathBuf};

use super::{compile_file, file_name, goals_status, table, EXIT_INVALID};
use crate::compile::Report;
use crate::emit::{write_atomic, write_glb};

/// Builds the project at `path`, writing into `out_dir` when given instead of the project's folders.
pub fn run(path: &Path, out_dir: Option<&Path>) -> i32 {
    let Some(compilation) = compile_file(path) else {
        return EXIT_INVALID;
    };
    let glb = match write_glb(&compilation.scene()) {
        Ok(bytes) => bytes,
        Err(error) => {
            eprintln!("error: cannot encode the glTF file: {error}");
            return EXIT_INVALID;
        }
    };
    let report = Report::new(&compilation, path).to_json();
    let output = &compilation.project.output;
    let targets = [
        (destination(&output.gltf, out_dir), glb.as_slice()),
        (destination(&output.report, out_dir), report.as_bytes()),
    ];
    // Both outputs are encoded before either is written; each write replaces its file whole.
    for (target, bytes) in &targets {
        if let Err(error) = write_output(target, bytes) {
            eprintln!("error: cannot write {}: {error}", target.display());
            return EXIT_INVALID;
        }
    }
    print!("{}", table::summary(&compilation, &file_name(path)));
    for (target, _) in &targets {
        println!("wrote {}", target.display());
    }
    goals_status(&compilation)
}

/// Where an output goes: its own path, or its file name inside `out_dir`.
fn destination(path: &Path, out_dir: Option<&Path>) -> PathBuf {
    match (out_dir, path.file_name()) {
        (Some(folder), Some(name)) => folder.join(name),
        _ => path.to_path_buf(),
    }
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
