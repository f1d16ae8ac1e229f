//! Edit-to-output latency in watch mode, on the six-pose character (`examples/spot.kdl`), and in
//! process also on the hammer example with the 240k-triangle hammer of `../shared/meshes` (skipped
//! with a note when that folder is missing).
//!
//! Two ways, each on a scratch copy of the example:
//!
//! - **In process**: the library calls a watch session makes (one [`Workspace`] across builds,
//!   compile then write every output), for a goal-only edit (the early result: the last design
//!   judged as it is; a search from the last design; the full search with the cache) and for a
//!   mesh edit, against a fresh `build`.
//! - **End to end**, on both: the real binary (`ballast watch`) is started, a goal-only edit and
//!   a mesh edit are saved, and the time from the save to the line saying the outputs were written is
//!   read from its output. This adds the file-system notification and the debounce window.
//!
//! Every time is also given as a ratio to a baseline (one pass summing every vertex coordinate of
//! `examples/meshes/hammer.obj`) measured in the same process. `docs/benchmarks.md` records the
//! figures. Run with `cargo bench --bench watch`; `BALLAST_BENCH_REPEATS` sets the edits per case
//! (default 5; the median is shown).

#[path = "../tests/edit_support/mod.rs"]
mod edit_support;
mod support;

use std::fs;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::thread;
use std::time::{Duration, Instant};

use ballast::compile::{
    compile_with, write_outputs_with, Compilation, CompileOptions, DesignSource, OptimizeOptions,
    WarmStart, Workspace,
};
use ballast::geometry::{load_mesh, MeshSelector};
use support::{baseline, manifest, ratio};

/// An example to edit: its project, the mesh it reads, and a goal-only edit.
struct Case {
    /// The project file under `examples/`, without `.kdl`.
    example: &'static str,
    /// The mesh copied in as the project's mesh: a path under `examples/meshes`, or absolute.
    mesh: PathBuf,
    /// Text of the project's goals, and the text an edit switches it to (and back).
    goals: [&'static str; 2],
}

impl Case {
    fn spot() -> Case {
        Case {
            example: "spot",
            mesh: manifest().join("examples/meshes/spot.obj"),
            goals: ["stand margin=5", "stand margin=4"],
        }
    }

    fn hammer_240k() -> Case {
        Case {
            example: "hammer",
            mesh: manifest().join("../shared/meshes/large/hammer_240k.obj"),
            goals: ["tolerance=2", "tolerance=3"],
        }
    }
}

/// A scratch copy of an example: the project and its mesh.
struct Scratch {
    _folder: tempfile::TempDir,
    project: PathBuf,
    mesh: PathBuf,
    goals: [&'static str; 2],
}

impl Scratch {
    fn new(case: &Case) -> Scratch {
        let folder = tempfile::tempdir().expect("a scratch folder");
        let meshes = folder.path().join("meshes");
        fs::create_dir(&meshes).expect("meshes/");
        let mesh = meshes.join(format!("{}.obj", case.example));
        fs::copy(&case.mesh, &mesh).expect("the mesh");
        let project = folder.path().join(format!("{}.kdl", case.example));
        let source = manifest().join(format!("examples/{}.kdl", case.example));
        fs::copy(source, &project).expect("the project");
        Scratch {
            _folder: folder,
            project,
            mesh,
            goals: case.goals,
        }
    }

    /// Saves the project with its goals as the `k`-th text of the case's two (k even: the
    /// second), as an editor does (a temp file renamed over it).
    fn edit_goals(&self, k: usize) {
        let text = fs::read_to_string(&self.project).expect("the project");
        let edited = text.replace(self.goals[k % 2], self.goals[1 - k % 2]);
        save_by_rename(&self.project, edited.as_bytes());
    }

    /// Saves the mesh with every vertex moved by a new tiny amount along x: a new content, the
    /// same goals met.
    fn edit_mesh(&self, k: usize) {
        let text = fs::read_to_string(&self.mesh).expect("the mesh");
        let dx = 1e-4 * (k as f64 + 1.0);
        save_by_rename(&self.mesh, edit_support::shifted_obj(&text, dx).as_bytes());
    }
}

fn save_by_rename(path: &Path, bytes: &[u8]) {
    let temp = path.with_extension("swp");
    fs::write(&temp, bytes).expect("a temp file");
    fs::rename(&temp, path).expect("a rename");
}

/// A build's options: from `warm_start` when given, judging it only when `judge`.
fn options(warm_start: Option<WarmStart>, judge: bool) -> CompileOptions {
    CompileOptions {
        out_dir: None,
        optimize: Some(OptimizeOptions {
            warm_start,
            judge_warm_start: judge,
            ..OptimizeOptions::default()
        }),
        ..CompileOptions::default()
    }
}

/// One build as watch mode runs it: compile in `workspace`, then write every output; seconds.
fn build(
    scratch: &Scratch,
    options: &CompileOptions,
    workspace: &mut Workspace,
) -> (Compilation, f64) {
    let clock = Instant::now();
    let source = fs::read_to_string(&scratch.project).expect("the project");
    workspace.start_build();
    let compilation =
        compile_with(&source, &scratch.project, options, workspace).expect("it compiles");
    workspace.prune(&compilation.source);
    write_outputs_with(
        &compilation,
        &scratch.project,
        None,
        &mut workspace.print_files,
    )
    .expect("outputs are written");
    (compilation, clock.elapsed().as_secs_f64())
}

fn median(mut times: Vec<f64>) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn in_process(case: &Case, repeats: usize, base: f64) {
    let triangles = match load_mesh(&case.mesh, &MeshSelector::Whole) {
        Ok(mesh) => mesh.triangles.len(),
        Err(error) => {
            println!("note: skipping {}: {error}\n", case.mesh.display());
            return;
        }
    };
    let scratch = Scratch::new(case);
    let mut fresh = Vec::new();
    let mut judged = Vec::new();
    let mut warm = Vec::new();
    let mut full = Vec::new();
    let mut mesh = Vec::new();
    let mut workspace = Workspace::new();
    let (mut last, _) = build(&scratch, &options(None, false), &mut workspace);
    for k in 0..repeats {
        fresh.push(build(&scratch, &options(None, false), &mut Workspace::new()).1);

        scratch.edit_goals(k);
        let start = WarmStart::new(&last.meshes, last.design.clone());
        let (early, seconds) = build(
            &scratch,
            &options(Some(start.clone()), true),
            &mut workspace,
        );
        assert_eq!(
            early.source,
            DesignSource::Earlier,
            "a goal-only edit judges the last design"
        );
        judged.push(seconds);
        warm.push(build(&scratch, &options(Some(start), false), &mut workspace).1);
        let (settled, seconds) = build(&scratch, &options(None, false), &mut workspace);
        full.push(seconds);
        last = settled;

        scratch.edit_mesh(k);
        let start = WarmStart::new(&last.meshes, last.design.clone());
        let (moved, seconds) = build(&scratch, &options(Some(start), true), &mut workspace);
        assert_eq!(
            moved.source,
            DesignSource::Optimized,
            "a mesh edit searches"
        );
        assert!(!moved.optimization.as_ref().is_some_and(|o| o.warm_started));
        mesh.push(seconds);
        last = moved;
    }
    println!(
        "### In process (library calls of one watch session), `{}`, {triangles} triangles\n",
        case.example
    );
    println!("| build | median s | ratio |");
    println!("| --- | ---: | ---: |");
    for (label, times) in [
        ("fresh `build`: a new workspace", fresh),
        (
            "goal-only edit: early result, the last design judged",
            judged,
        ),
        (
            "goal-only edit: search from the last design (the full search where it misses a goal)",
            warm,
        ),
        (
            "goal-only edit: full search, grids and skeleton cached",
            full,
        ),
        ("mesh edit: new grid and skeleton, full search", mesh),
    ] {
        let seconds = median(times);
        println!("| {label} | {seconds:.3} | {} |", ratio(seconds, base));
    }
    println!();
}

/// The real binary watching a scratch copy; its output lines with the time each was read.
struct Watcher {
    child: std::process::Child,
    lines: Receiver<(Instant, String)>,
}

impl Watcher {
    fn start(project: &Path) -> Watcher {
        let mut child = Command::new(env!("CARGO_BIN_EXE_ballast"))
            .env("BALLAST_CACHE_DIR", "off")
            .arg("watch")
            .arg(project)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("ballast watch starts");
        let stdout = child.stdout.take().expect("its output");
        let (sender, lines) = channel();
        thread::spawn(move || {
            for line in BufReader::new(stdout).lines().map_while(Result::ok) {
                if sender.send((Instant::now(), line)).is_err() {
                    break;
                }
            }
        });
        Watcher { child, lines }
    }

    /// Reads lines until one starts with `start` and contains `text` (when `holds`, else one
    /// that does not); when it was read.
    fn until(&self, start: &str, text: &str, holds: bool) -> Instant {
        loop {
            let (at, line) = self
                .lines
                .recv_timeout(Duration::from_secs(120))
                .expect("ballast watch keeps building");
            if line.starts_with(start) && line.contains(text) == holds {
                return at;
            }
        }
    }
}

impl Drop for Watcher {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn end_to_end(case: &Case, repeats: usize, base: f64) {
    let scratch = Scratch::new(case);
    let watcher = Watcher::start(&scratch.project);
    // A summary's last line says what follows (`; now ...`) except after the rebuild's last step.
    let (written, follows) = ("  wrote ", "; now ");
    watcher.until(written, follows, false);
    let mut early = Vec::new();
    let mut full = Vec::new();
    let mut mesh = Vec::new();
    for k in 0..repeats {
        let saved = Instant::now();
        scratch.edit_goals(k);
        early.push((watcher.until(written, follows, true) - saved).as_secs_f64());
        full.push((watcher.until(written, follows, false) - saved).as_secs_f64());

        let saved = Instant::now();
        scratch.edit_mesh(k);
        mesh.push((watcher.until(written, follows, false) - saved).as_secs_f64());
    }
    println!(
        "### End to end (`ballast watch`, save to outputs written, debounce included), `{}`\n",
        case.example
    );
    println!("| edit | median s | ratio |");
    println!("| --- | ---: | ---: |");
    for (label, times) in [
        (
            "goal-only edit: early result, the last design judged",
            early,
        ),
        ("goal-only edit: full search written", full),
        ("mesh edit: written", mesh),
    ] {
        let seconds = median(times);
        println!("| {label} | {seconds:.3} | {} |", ratio(seconds, base));
    }
    println!();
}

fn main() {
    let repeats = std::env::var("BALLAST_BENCH_REPEATS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(5usize)
        .max(1);
    let hammer = load_mesh(
        &manifest().join("examples/meshes/hammer.obj"),
        &MeshSelector::Whole,
    )
    .expect("examples/meshes/hammer.obj");
    let base = baseline(&hammer);
    println!(
        "baseline: {:.3e} s ({} vertices summed)\n",
        base,
        hammer.positions.len()
    );
    in_process(&Case::spot(), repeats, base);
    end_to_end(&Case::spot(), repeats, baseline(&hammer));
    let hammer_240k = Case::hammer_240k();
    in_process(&hammer_240k, repeats, baseline(&hammer));
    if hammer_240k.mesh.is_file() {
        end_to_end(&hammer_240k, repeats, baseline(&hammer));
    }
}
