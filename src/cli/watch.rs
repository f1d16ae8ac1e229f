//! `ballast watch`: build, then rebuild on every change to the project file or its meshes, with
//! one workspace (grid and skeleton cache) for the whole session, printing a short summary of
//! each build.
//!
//! After an edit that leaves the meshes alone, a rebuild first judges the last design as it is
//! with the edited project and writes that at once; when it misses a goal, it then optimizes
//! from it (a warm start) and writes that; last it runs the same full search `build` runs and
//! writes its result, so once the session is quiet the outputs are exactly `build`'s. A newer
//! save cancels any step.

use std::collections::BTreeSet;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::{
    compile_file, file_name, progress, say, MessageFormat, NotCompiled, EXIT_INVALID, EXIT_MET,
};
use crate::cancel::Cancel;
use crate::compile::{
    write_outputs_with, Compilation, CompileOptions, DesignSource, WarmStart, Workspace,
};
use crate::optimize::{Built, PrecomputeCache};
use crate::spec::{parse_project_with, read_source};
use crate::watch::{self, differences, list, referenced_files, shown, Snapshot};

/// Watches the project at `path` until Ctrl-C (status 0), with grids and skeletons from `cache`,
/// diagnostics printed as `format` says; status 2 when watching cannot start.
pub fn run(
    path: &Path,
    format: MessageFormat,
    options: &CompileOptions,
    cache: PrecomputeCache,
) -> i32 {
    let mut session = Session {
        path,
        format,
        options,
        workspace: Workspace {
            cache,
            progress: progress::on_terminal(),
            ..Workspace::new()
        },
        last: None,
        files: referenced_files(path, None, &options.read_policy(path)),
    };
    // Watched from before the first build, so a save during it is not missed.
    session.follow_parsed();
    say(
        format,
        &format!("watching {}; Ctrl-C to stop\n", file_name(path)),
    );
    let files = session.files.clone();
    match watch::run(files, |changed, cancel| session.rebuild(changed, cancel)) {
        Ok(()) => {
            say(format, &format!("stopped watching {}\n", file_name(path)));
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
    /// How diagnostics are printed; the rest of the output goes where it leaves room.
    format: MessageFormat,
    options: &'a CompileOptions,
    /// Grids and skeletons, reused while the meshes stay the same.
    workspace: Workspace,
    /// The last good build.
    last: Option<Last>,
    /// The files the project referenced when last read.
    files: BTreeSet<PathBuf>,
}

/// The last good build: what the summary compares with, and where the next optimization starts.
struct Last {
    snapshot: Snapshot,
    design: WarmStart,
}

/// What one step of a rebuild starts from.
#[derive(Debug, Clone)]
enum Start {
    /// The last design, judged as it is with no search.
    Judge(WarmStart),
    /// A search from the last design.
    Warm(WarmStart),
    /// The full search, as `build` runs it.
    Full,
}

impl Session<'_> {
    /// Builds after `changed` changed (nothing: the first build) unless `cancel` is set first;
    /// returns the files to watch.
    fn rebuild(&mut self, changed: &[PathBuf], cancel: &Cancel) -> BTreeSet<PathBuf> {
        self.workspace.cancel = cancel.clone();
        let name = file_name(self.path);
        if changed.is_empty() {
            say(self.format, &format!("\nbuilding {name}\n"));
        } else {
            let changed: BTreeSet<PathBuf> = changed.iter().cloned().collect();
            say(
                self.format,
                &format!("\nchanged: {}; rebuilding {name}\n", list(&changed)),
            );
        }
        // The last design judged at once, then (when it misses a goal) a search from it, then
        // the full search as `build` runs it; each written as it is reached.
        let mut start = match &self.last {
            Some(last) => Start::Judge(last.design.clone()),
            None => Start::Full,
        };
        loop {
            start = match self.step(start) {
                Some(Early::Judged | Early::WarmStarted) => Start::Full,
                Some(Early::JudgedMissing) => match &self.last {
                    Some(last) => Start::Warm(last.design.clone()),
                    None => Start::Full,
                },
                Some(Early::Final) | None => break,
            };
        }
        self.files.clone()
    }

    /// Compiles from `start`, writes, prints a summary against the last good build and becomes
    /// the last good build; which result of the rebuild it wrote, `None` when it wrote nothing
    /// (invalid, cancelled or not writable: already said).
    fn step(&mut self, start: Start) -> Option<Early> {
        let name = file_name(self.path);
        let mut options = self.options.clone();
        if let Some(optimize) = &mut options.optimize {
            (optimize.warm_start, optimize.judge_warm_start) = match start {
                Start::Judge(last) => (Some(last), true),
                Start::Warm(last) => (Some(last), false),
                Start::Full => (None, false),
            };
        }
        self.workspace.start_build();
        let start = Instant::now();
        let compiled = compile_file(self.path, &options, &mut self.workspace, self.format);
        let compile_seconds = start.elapsed().as_secs_f64();
        let compilation = match compiled {
            Ok(compilation) => compilation,
            Err(NotCompiled::Invalid(_)) => {
                say(
                    self.format,
                    &format!("{name} is invalid: the last good outputs are left as they were\n"),
                );
                self.follow_parsed();
                return None;
            }
            Err(NotCompiled::Cancelled) => {
                say(
                    self.format,
                    "cancelled: the last good outputs are left as they were\n",
                );
                return None;
            }
        };
        // Only what this build used stays cached.
        self.workspace.prune(&compilation.source);
        self.files = referenced_files(
            self.path,
            Some(&compilation.project),
            &options.read_policy(self.path),
        );
        let write_start = Instant::now();
        let written = match write_outputs_with(
            &compilation,
            self.path,
            options.out_dir.as_deref(),
            &mut self.workspace.print_files,
        ) {
            Ok(written) => written,
            Err(message) => {
                eprintln!("error: {message}");
                say(
                    self.format,
                    &format!(
                        "{name} built but not written: the last good outputs are left as they were\n"
                    ),
                );
                return None;
            }
        };
        let write_seconds = write_start.elapsed().as_secs_f64();
        let warm_started = compilation
            .optimization
            .as_ref()
            .is_some_and(|optimization| optimization.warm_started);
        let snapshot = Snapshot::new(&compilation);
        let (met, goals) = snapshot.goals_met();
        let judged = compilation.source == DesignSource::Earlier;
        let early = match (judged, warm_started) {
            (true, _) if met == goals => Early::Judged,
            (true, _) => Early::JudgedMissing,
            (false, true) => Early::WarmStarted,
            (false, false) => Early::Final,
        };
        say(
            self.format,
            &summary(&SummaryInput {
                name: &name,
                compilation: &compilation,
                snapshot: &snapshot,
                last: self.last.as_ref().map(|last| &last.snapshot),
                built: self.workspace.cache.built(),
                held: self.workspace.cache.len(),
                meshes_loaded: self.workspace.meshes.loaded(),
                compile_seconds,
                write_seconds,
                written: &written.written,
                removed: &written.removed,
                early,
            }),
        );
        self.last = Some(Last {
            snapshot,
            design: WarmStart::new(&compilation.meshes, compilation.design),
        });
        Some(early)
    }

    /// Follows the files the project names if it can be parsed (before the first build, after
    /// an invalid one); otherwise keeps the set it had, and adds its rig file.
    fn follow_parsed(&mut self) {
        let Ok(Some(source)) = read_source(self.path, "project file") else {
            return;
        };
        let policy = self.options.read_policy(self.path);
        let parsed = parse_project_with(&source, self.path, &policy);
        match parsed.project {
            Some(project) => self.files = referenced_files(self.path, Some(&project), &policy),
            // A rig that cannot be read yet is followed, to build once it is fixed.
            None => self
                .files
                .extend(parsed.rig.as_deref().map(watch::watch_key)),
        }
    }
}

struct SummaryInput<'a> {
    name: &'a str,
    compilation: &'a Compilation,
    snapshot: &'a Snapshot,
    last: Option<&'a Snapshot>,
    built: Built,
    held: usize,
    meshes_loaded: usize,
    compile_seconds: f64,
    write_seconds: f64,
    written: &'a [PathBuf],
    /// Outputs of the last build this one no longer writes, removed.
    removed: &'a [PathBuf],
    /// Which result of the rebuild this is.
    early: Early,
}

/// Which result of a rebuild a build is, and so what follows it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Early {
    /// The last design judged, meeting every goal: the full search follows.
    Judged,
    /// The last design judged, missing a goal: a search from it follows, then the full search.
    JudgedMissing,
    /// Optimized from the last design: the full search follows.
    WarmStarted,
    /// The full search's result (or the first build's).
    Final,
}

/// The few lines printed after a good build.
fn summary(input: &SummaryInput) -> String {
    let mut out = String::new();
    let snapshot = input.snapshot;
    let (met, total) = snapshot.goals_met();
    let from = match input.early {
        Early::Judged | Early::JudgedMissing => " (the last design, judged)",
        Early::WarmStarted => " (from the last design)",
        Early::Final => "",
    };
    let _ = write!(
        out,
        "{}{from}: {met} of {total} goal{} met, {} capsule{}",
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
    let components = input.compilation.meshes.len();
    let meshes = match input.meshes_loaded {
        0 => "reused".to_string(),
        loaded => format!("{loaded} of {components} loaded and checked"),
    };
    let _ = writeln!(out, "  meshes: {meshes}");
    let optimization = input.compilation.optimization.as_ref();
    let built = input.built;
    let precompute = if matches!(input.early, Early::Judged | Early::JudgedMissing) {
        "not needed (the last design is judged as it is)".to_string()
    } else if optimization.is_none() {
        "not needed (the design is not optimized)".to_string()
    } else {
        let mut parts = Vec::new();
        if built.grids > 0 || built.skeletons > 0 {
            parts.push(format!(
                "{} grid{} and {} skeleton{} built",
                built.grids,
                plural(built.grids),
                built.skeletons,
                plural(built.skeletons),
            ));
        }
        if built.loaded > 0 {
            parts.push(format!("{} read from the disk cache", built.loaded));
        }
        if parts.is_empty() {
            parts.push("reused".to_string());
        }
        format!(
            "{} ({} mesh{} in the cache)",
            parts.join(", "),
            input.held,
            plural_es(input.held)
        )
    };
    let _ = writeln!(out, "  grids and skeletons: {precompute}");
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
    let _ = write!(out, "  wrote {}", written.join(", "));
    if !input.removed.is_empty() {
        let removed: Vec<String> = input
            .removed
            .iter()
            .map(|path| shown(&watch::watch_key(path)).display().to_string())
            .collect();
        let _ = write!(
            out,
            "; removed {} (no longer an output)",
            removed.join(", ")
        );
    }
    match input.early {
        Early::Judged | Early::WarmStarted => {
            out.push_str("; now the full search, as `build` runs it")
        }
        Early::JudgedMissing => {
            out.push_str("; now a search from it, then the full search as `build` runs it")
        }
        Early::Final => {}
    }
    out.push('\n');
    out
}

fn plural(count: usize) -> &'static str {
    if count == 1 {
        ""
    } else {
        "s"
    }
}

fn plural_es(count: usize) -> &'static str {
    if count == 1 {
        ""
    } else {
        "es"
    }
}
