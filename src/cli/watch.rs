//! `ballast watch`: build, then rebuild on every change to the project file or its meshes, with
//! one grid cache for the whole session, printing a short summary of each build.

use std::collections::BTreeSet;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::build::write_outputs;
use super::{compile_file, file_name, EXIT_INVALID, EXIT_MET};
use crate::compile::{Compilation, CompileOptions};
use crate::optimize::GridCache;
use crate::spec::parse_project;
use crate::watch::{self, differences, list, referenced_files, shown, Snapshot};

/// Watches the project at `path` until Ctrl-C (status 0); status 2 when watching cannot start.
pub fn run(path: &Path, options: &CompileOptions) -> i32 {
    let mut session = Session {
        path,
        options,
        cache: GridCache::new(),
        last: None,
        files: referenced_files(path, None),
    };
    // Watched from before the first build, so a save during it is not missed.
    session.follow_parsed();
    println!("watching {}; Ctrl-C to stop", file_name(path));
    let files = session.files.clone();
    match watch::run(files, |changed| session.rebuild(changed)) {
        Ok(()) => {
            println!("stopped watching {}", file_name(path));
            EXIT_MET
        }
        Err(message) => {
            eprintln!("error: {message}");
            EXIT_INVALID
        }
    }
}

/// What a watch session keeps between builds.
struct Session<'a> {
    path: &'a Path,
    options: &'a CompileOptions,
    /// Distance grids, reused while the meshes stay the same.
    cache: GridCache,
    /// The last good build.
    last: Option<Snapshot>,
    /// The files the project referenced when last read.
    files: BTreeSet<PathBuf>,
}

impl Session<'_> {
    /// Builds after `changed` changed (nothing: the first build); returns the files to watch.
    fn rebuild(&mut self, changed: &[PathBuf]) -> BTreeSet<PathBuf> {
        let name = file_name(self.path);
        println!();
        if changed.is_empty() {
            println!("building {name}");
        } else {
            let changed: BTreeSet<PathBuf> = changed.iter().cloned().collect();
            println!("changed: {}; rebuilding {name}", list(&changed));
        }
        let grids_before = self.cache.len();
        let start = Instant::now();
        let compiled = compile_file(self.path, self.options, &mut self.cache);
        let compile_seconds = start.elapsed().as_secs_f64();
        let Some(compilation) = compiled else {
            println!("{name} is invalid: the last good outputs are left as they were");
            self.follow_parsed();
            return self.files.clone();
        };
        self.files = referenced_files(self.path, Some(&compilation.project));
        let write_start = Instant::now();
        let written = match write_outputs(&compilation, self.path, self.options) {
            Ok(written) => written,
            Err(message) => {
                eprintln!("error: {message}");
                println!(
                    "{name} built but not written: the last good outputs are left as they were"
                );
                return self.files.clone();
            }
        };
        let write_seconds = write_start.elapsed().as_secs_f64();
        let snapshot = Snapshot::new(&compilation);
        print!(
            "{}",
            summary(&SummaryInput {
                name: &name,
                compilation: &compilation,
                snapshot: &snapshot,
                last: self.last.as_ref(),
                grids_built: self.cache.len().saturating_sub(grids_before),
                grids_held: self.cache.len(),
                compile_seconds,
                write_seconds,
                written: &written,
            })
        );
        self.last = Some(snapshot);
        self.files.clone()
    }

    /// Follows the files the project names if it can be parsed (before the first build, after
    /// an invalid one); otherwise keeps the set it had.
    fn follow_parsed(&mut self) {
        let Ok(source) = std::fs::read_to_string(self.path) else {
            return;
        };
        if let Some(project) = parse_project(&source, self.path).project {
            self.files = referenced_files(self.path, Some(&project));
        }
    }
}

struct SummaryInput<'a> {
    name: &'a str,
    compilation: &'a Compilation,
    snapshot: &'a Snapshot,
    last: Option<&'a Snapshot>,
    grids_built: usize,
    grids_held: usize,
    compile_seconds: f64,
    write_seconds: f64,
    written: &'a [PathBuf],
}

/// The few lines printed after a good build.
fn summary(input: &SummaryInput) -> String {
    let mut out = String::new();
    let snapshot = input.snapshot;
    let (met, total) = snapshot.goals_met();
    let _ = write!(
        out,
        "{}: {met} of {total} goal{} met, {} capsule{}",
        input.name,
        plural(total),
        snapshot.capsules,
        plural(snapshot.capsules),
    );
    if let Some(tilt) = snapshot.worst_tilt_margin {
        let _ = write!(out, ", worst tilt margin {tilt:.1}");
    }
    out.push('\n');
    if let Some(last) = input.last {
        let lines = differences(last, snapshot);
        if lines.is_empty() {
            out.push_str(
                "  since the last good build: no change in goals, capsules or tilt margin\n",
            );
        } else {
            out.push_str("  since the last good build:\n");
            for line in lines {
                let _ = writeln!(out, "    {line}");
            }
        }
    }
    let optimization = input.compilation.optimization.as_ref();
    let grids = match (optimization, input.grids_built) {
        (None, _) => "not needed (the design is not optimized)".to_string(),
        (Some(_), 0) => format!("reused ({} in the cache)", input.grids_held),
        (Some(_), built) => format!("{built} built ({} in the cache)", input.grids_held),
    };
    let _ = writeln!(out, "  distance grids: {grids}");
    let stages = match optimization {
        Some(optimization) => format!(
            " (precompute {:.2} s, optimizer {:.2} s)",
            optimization.timings.precompute,
            optimization.timings.heuristic
                + optimization.timings.exhaustive
                + optimization.timings.conflicts
        ),
        None => String::new(),
    };
    let _ = writeln!(
        out,
        "  time: compile {:.2} s{stages}, write {:.2} s",
        input.compile_seconds, input.write_seconds
    );
    let written: Vec<String> = input
        .written
        .iter()
        .map(|path| shown(&watch::watch_key(path)).display().to_string())
        .collect();
    let _ = writeln!(out, "  wrote {}", written.join(", "));
    out
}

fn plural(count: usize) -> &'static str {
    if count == 1 {
        ""
    } else {
        "s"
    }
}
