//! `ballast build`: check, optimize when the project asks, then write the glTF file, the JSON
//! report and the solution file atomically.

use std::path::Path;

use super::{
    compile_file, file_name, goals_status, optimization_table, progress, table, EXIT_INVALID,
};
use crate::compile::{write_outputs, CompileOptions, Workspace};
use crate::optimize::PrecomputeCache;

/// Builds the project at `path` as `options` say, with grids and skeletons from `cache`.
pub fn run(path: &Path, options: &CompileOptions, cache: PrecomputeCache) -> i32 {
    let mut workspace = Workspace {
        cache,
        progress: progress::on_terminal(),
        ..Workspace::new()
    };
    let Ok(compilation) = compile_file(path, options, &mut workspace) else {
        return EXIT_INVALID;
    };
    let written = match write_outputs(&compilation, path, options.out_dir.as_deref()) {
        Ok(written) => written,
        Err(message) => {
            eprintln!("error: {message}");
            return EXIT_INVALID;
        }
    };
    if let Some(optimization) = &compilation.optimization {
        let from_disk = workspace.cache.built().loaded;
        print!(
            "{}",
            optimization_table::optimization(optimization, &compilation, from_disk)
        );
    }
    print!("{}", table::summary(&compilation, &file_name(path)));
    for target in &written {
        println!("wrote {}", target.display());
    }
    goals_status(&compilation)
}
