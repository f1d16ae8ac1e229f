//! The optimizer on the examples: the three local solvers compared, precompute time per mesh
//! size, optimization time per capsule count, the heuristic ranked against random starts, and the
//! six-pose character end to end. Each case runs once (or a few times) and prints a markdown
//! table; every time is also given as a ratio to a baseline (one pass summing every vertex
//! coordinate of `examples/meshes/hammer.obj`, as in `benches/pipeline.rs`) measured in the same
//! process just before the case. `docs/benchmarks.md` records the figures.
//!
//! Run with `cargo bench --bench optimizer`. Choose a subset with arguments or the environment:
//!
//! - cases: `solvers`, `precompute`, `counts`, `rank`, `spot` (arguments, or `BALLAST_BENCH_CASES`
//!   as a comma-separated list; all when none is given);
//! - examples: `BALLAST_BENCH_EXAMPLES`, comma-separated (e.g. `spot,t_shape`);
//! - random starts per capsule count for `rank`: `BALLAST_BENCH_STARTS` (default 100);
//! - examples ranked: `BALLAST_BENCH_RANK` (default `spot,t_shape`).
//!
//! Meshes beyond the examples come from `../shared/meshes` beside the checkout; a missing one is
//! skipped with a note.

mod support;

use std::collections::HashMap;
use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use ballast::balance::PartPrints;
use ballast::compile::{
    self, compile_with, print_setup, CompileOptions, OptimizeOptions, Preparation, Workspace,
};
use ballast::fabrication::PrintSetup;
use ballast::geometry::{load_mesh, DistanceGrid, MeshSelector, Skeleton, TriMesh};
use ballast::objective::{GridInterior, Parameters};
use ballast::optimize::{choose, default_cell, rank, run_heuristic, Candidate, Method, Problem};
use ballast::spec::model::{Optimize, Project};
use support::{baseline, manifest, ratio};

/// Every example, in the order of `examples/README.md`.
const EXAMPLES: [&str; 6] = [
    "t_shape",
    "sheared_cylinder",
    "articulated",
    "hammer",
    "fish",
    "spot",
];

const METHODS: [(Method, &str); 3] = [
    (Method::Hybrid, "hybrid"),
    (Method::Slsqp, "slsqp"),
    (Method::Cobyla, "cobyla"),
];

const CASES: [&str; 5] = ["solvers", "precompute", "counts", "rank", "spot"];

/// A comma-separated list from the environment, or `default`.
fn list(var: &str, default: &[&str]) -> Vec<String> {
    match std::env::var(var) {
        Ok(value) if !value.trim().is_empty() => value
            .split(',')
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty())
            .collect(),
        _ => default.iter().map(|s| s.to_string()).collect(),
    }
}

/// A compiled example: the project and its meshes.
struct Example {
    name: String,
    project: Project,
    meshes: Vec<TriMesh>,
    prints: PartPrints,
    print: PrintSetup,
}

impl Example {
    fn load(name: &str) -> Example {
        let path = manifest().join("examples").join(format!("{name}.kdl"));
        let source = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let compiled = compile_with(
            &source,
            &path,
            &CompileOptions::default(),
            &mut Workspace::new(),
        )
        .unwrap_or_else(|failure| panic!("{name} did not compile: {failure:?}"));
        let prints = compiled.part_prints();
        // As `build` sets the optimizer up: from the orientations, not from the bed's plan (the
        // same directions, rounded differently).
        let print = print_setup(&compiled.project, &compiled.orientations);
        Example {
            name: name.to_string(),
            project: compiled.project,
            meshes: compiled.meshes,
            prints,
            print,
        }
    }

    fn settings(&self) -> &Optimize {
        self.project
            .optimize
            .as_ref()
            .expect("every example has an optimize node")
    }

    fn parameters(&self) -> Parameters {
        Parameters::for_project(&self.project)
    }

    fn triangles(&self) -> usize {
        self.meshes.iter().map(|m| m.triangles.len()).sum()
    }
}

/// The distance grids, skeletons and seeds of an example, built afresh as `optimize_design`
/// builds them.
fn prepare(example: &Example) -> Preparation {
    compile::prepare(
        &example.project,
        example.settings(),
        &example.meshes,
        &example.print,
        &mut Workspace::new(),
        None,
    )
    .expect("nothing cancels the bench")
}

/// One run of the heuristic with one method.
struct Run {
    candidates: Vec<Candidate>,
    chosen: usize,
    seconds: f64,
    baseline: f64,
}

impl Run {
    fn evaluations(&self) -> usize {
        self.candidates.iter().map(|c| c.outcome.evaluations).sum()
    }
}

fn heuristic(example: &Example, prepared: &Preparation, method: Method, base: &TriMesh) -> Run {
    let baseline = baseline(base);
    let settings = example.settings();
    let problem = Problem::new(
        &example.project,
        &example.meshes,
        &example.prints,
        example.print.clone(),
        prepared.interior.clone(),
        method,
    );
    let clock = Instant::now();
    let candidates = run_heuristic(&problem, &prepared.seeds, settings.capsules, &|_| {});
    let seconds = clock.elapsed().as_secs_f64();
    let chosen = choose(&candidates, settings.capsules, settings.tolerance_degrees);
    Run {
        candidates,
        chosen,
        seconds,
        baseline,
    }
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

fn main() {
    let arguments: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let cases: Vec<String> = if arguments.iter().any(|a| CASES.contains(&a.as_str())) {
        arguments
            .into_iter()
            .filter(|a| CASES.contains(&a.as_str()))
            .collect()
    } else {
        list("BALLAST_BENCH_CASES", &CASES)
    };
    let wanted = |case: &str| cases.iter().any(|c| c == case);
    let names = list("BALLAST_BENCH_EXAMPLES", &EXAMPLES);
    let starts: usize = std::env::var("BALLAST_BENCH_STARTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100);
    let ranked = list("BALLAST_BENCH_RANK", &["spot", "t_shape"]);

    let base = load_mesh(
        &manifest().join("examples/meshes/hammer.obj"),
        &MeshSelector::Whole,
    )
    .expect("examples/meshes/hammer.obj loads");
    let first = baseline(&base);
    println!(
        "baseline: Σ (x + y + z) over {} vertices, {:.1} µs (median of 201); ratios below are \
         time / the baseline measured just before each case (k: thousands, M: millions)\n",
        base.positions.len(),
        first * 1e6
    );

    let examples: Vec<Example> = names.iter().map(|n| Example::load(n)).collect();
    let mut prepared: HashMap<String, Preparation> = HashMap::new();
    let mut runs: HashMap<(String, &str), Run> = HashMap::new();
    let mut get_prepared = |example: &Example| -> Arc<GridInterior> {
        prepared
            .entry(example.name.clone())
            .or_insert_with(|| prepare(example))
            .interior
            .clone()
    };
    for example in &examples {
        get_prepared(example);
    }

    if wanted("solvers") {
        println!("## Solver comparison (full heuristic)\n");
        println!(
            "| example | triangles | poses | method | seconds | ratio | evaluations | best objective per count (°) | chosen | meets goals |"
        );
        println!("| --- | ---: | ---: | --- | ---: | ---: | ---: | --- | ---: | --- |");
        for example in &examples {
            let prep = &prepared[&example.name];
            for (method, label) in METHODS {
                let run = heuristic(example, prep, method, &base);
                let per_count: Vec<String> = run
                    .candidates
                    .iter()
                    .map(|c| {
                        format!(
                            "{}: {:.2}{}",
                            c.capsules,
                            c.outcome.value.to_degrees(),
                            if c.outcome.meets_goals { "" } else { " ✗" }
                        )
                    })
                    .collect();
                let chosen = &run.candidates[run.chosen];
                println!(
                    "| {} | {} | {} | {label} | {:.2} | {} | {} | {} | {} | {} |",
                    example.name,
                    example.triangles(),
                    example.project.poses.len(),
                    run.seconds,
                    ratio(run.seconds, run.baseline),
                    run.evaluations(),
                    per_count.join(", "),
                    chosen.capsules,
                    yes(chosen.outcome.meets_goals),
                );
                runs.insert((example.name.clone(), label), run);
            }
        }
        println!("\n(✗: that count's design misses a goal or cannot be printed)\n");
        println!("### Failures: a capsule count met every goal with one method and not another\n");
        println!("| example | capsules | met with | missed with |");
        println!("| --- | ---: | --- | --- |");
        let mut any = false;
        for example in &examples {
            let mut counts: Vec<usize> = METHODS
                .iter()
                .flat_map(|(_, label)| &runs[&(example.name.clone(), *label)].candidates)
                .map(|c| c.capsules)
                .collect();
            counts.sort_unstable();
            counts.dedup();
            for count in counts.into_iter().rev() {
                let verdict = |label: &str| {
                    runs[&(example.name.clone(), label)]
                        .candidates
                        .iter()
                        .find(|c| c.capsules == count)
                        .map(|c| c.outcome.meets_goals)
                };
                let met: Vec<&str> = METHODS
                    .iter()
                    .filter(|(_, l)| verdict(l) == Some(true))
                    .map(|(_, l)| *l)
                    .collect();
                let missed: Vec<&str> = METHODS
                    .iter()
                    .filter(|(_, l)| verdict(l) == Some(false))
                    .map(|(_, l)| *l)
                    .collect();
                if !met.is_empty() && !missed.is_empty() {
                    any = true;
                    println!(
                        "| {} | {count} | {} | {} |",
                        example.name,
                        met.join(", "),
                        missed.join(", ")
                    );
                }
            }
        }
        if !any {
            println!("| (none) | | | |");
        }
        println!();
    }

    if wanted("precompute") {
        println!("## Precompute: distance grid (default cell) and skeleton\n");
        println!(
            "| mesh | triangles | grid nodes | cell | grid s | skeleton s | total s | ratio |"
        );
        println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
        let mut meshes: Vec<(String, &TriMesh, f64)> = Vec::new();
        for example in &examples {
            let radius = example.parameters().min_radius;
            for (component, mesh) in example.project.components.iter().zip(&example.meshes) {
                let label = if example.meshes.len() > 1 {
                    format!("{} ({})", example.name, component.name.value)
                } else {
                    example.name.clone()
                };
                meshes.push((label, mesh, radius));
            }
        }
        // The hammer subdivided once, with the hammer example's capsule size.
        let large_path = manifest().join("../shared/meshes/large/hammer_240k.obj");
        let large = match load_mesh(&large_path, &MeshSelector::Whole) {
            Ok(mesh) => Some(mesh),
            Err(error) => {
                eprintln!("note: skipping hammer_240k: {error}");
                None
            }
        };
        let hammer_radius = examples
            .iter()
            .find(|e| e.name == "hammer")
            .map(|e| e.parameters().min_radius)
            .unwrap_or_else(|| {
                Parameters::for_project(&Example::load("hammer").project).min_radius
            });
        if let Some(mesh) = &large {
            meshes.push(("hammer_240k".to_string(), mesh, hammer_radius));
        }
        for (label, mesh, radius) in meshes {
            let baseline = baseline(&base);
            let cell = default_cell(mesh, radius);
            // The median of three runs of each.
            let mut grid_times = Vec::new();
            let mut skeleton_times = Vec::new();
            let mut nodes = 0;
            for _ in 0..3 {
                let clock = Instant::now();
                let grid = DistanceGrid::new(mesh, cell);
                grid_times.push(clock.elapsed().as_secs_f64());
                let clock = Instant::now();
                black_box(Skeleton::from_grid(mesh, &grid));
                skeleton_times.push(clock.elapsed().as_secs_f64());
                nodes = grid.dims().iter().product::<usize>();
            }
            grid_times.sort_by(f64::total_cmp);
            skeleton_times.sort_by(f64::total_cmp);
            let (grid, skeleton) = (grid_times[1], skeleton_times[1]);
            println!(
                "| {label} | {} | {nodes} | {cell:.4} | {grid:.3} | {skeleton:.3} | {:.3} | {} |",
                mesh.triangles.len(),
                grid + skeleton,
                ratio(grid + skeleton, baseline)
            );
        }
        println!();
    }

    if wanted("counts") {
        println!("## Optimization time per capsule count (default method, hybrid)\n");
        println!(
            "| example | capsules | seconds | ratio | evaluations | objective (°) | meets goals |"
        );
        println!("| --- | ---: | ---: | ---: | ---: | ---: | --- |");
        for example in examples
            .iter()
            .filter(|e| e.name == "spot" || e.name == "t_shape")
        {
            let key = (example.name.clone(), "hybrid");
            if !runs.contains_key(&key) {
                let run = heuristic(example, &prepared[&example.name], Method::Hybrid, &base);
                runs.insert(key.clone(), run);
            }
            let run = &runs[&key];
            for c in &run.candidates {
                println!(
                    "| {} | {} | {:.3} | {} | {} | {:.2} | {} |",
                    example.name,
                    c.capsules,
                    c.seconds,
                    ratio(c.seconds, run.baseline),
                    c.outcome.evaluations,
                    c.outcome.value.to_degrees(),
                    yes(c.outcome.meets_goals)
                );
            }
        }
        println!();
    }

    if wanted("rank") {
        println!("## Heuristic against {starts} random starts per capsule count (hybrid)\n");
        println!(
            "| example | capsules | rank | heuristic (°) | best random (°) | gap | random starts meeting goals | seconds | ratio |"
        );
        println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
        for example in examples.iter().filter(|e| ranked.contains(&e.name)) {
            let key = (example.name.clone(), "hybrid");
            if !runs.contains_key(&key) {
                let run = heuristic(example, &prepared[&example.name], Method::Hybrid, &base);
                runs.insert(key.clone(), run);
            }
            let run = &runs[&key];
            let prep = &prepared[&example.name];
            let problem = Problem::new(
                &example.project,
                &example.meshes,
                &example.prints,
                example.print.clone(),
                prep.interior.clone(),
                Method::Hybrid,
            );
            for candidate in &run.candidates {
                let baseline = baseline(&base);
                let clock = Instant::now();
                let rankings = rank(
                    &problem,
                    prep.interior.as_ref(),
                    &prep.seeds,
                    std::slice::from_ref(candidate),
                    starts,
                    example.settings().seed,
                );
                let seconds = clock.elapsed().as_secs_f64();
                for r in rankings {
                    // The gap: how much worse the heuristic is than the best random start, as a
                    // percentage of the best's magnitude (negative: the heuristic is better).
                    let gap = (r.heuristic_objective - r.best_objective)
                        / r.best_objective.abs().max(1e-9)
                        * 100.0;
                    println!(
                        "| {} | {} | {} | {:.3} | {:.3} | {:+.2} % | {} | {:.1} | {} |",
                        example.name,
                        r.capsules,
                        r.rank,
                        r.heuristic_objective,
                        r.best_objective,
                        gap,
                        r.meeting_goals,
                        seconds,
                        ratio(seconds, baseline)
                    );
                }
            }
        }
        println!();
    }

    if wanted("spot") {
        println!("## Spot (six poses) end to end, default options\n");
        println!(
            "| run | precompute s | heuristic s | compile total s | ratio | chosen | meets goals |"
        );
        println!("| --- | ---: | ---: | ---: | ---: | ---: | --- |");
        let path = manifest().join("examples/spot.kdl");
        let source = std::fs::read_to_string(&path).expect("examples/spot.kdl");
        for run in 1..=3 {
            let baseline = baseline(&base);
            let options = CompileOptions {
                out_dir: None,
                optimize: Some(OptimizeOptions::default()),
                ..CompileOptions::default()
            };
            let clock = Instant::now();
            let compiled = compile_with(&source, &path, &options, &mut Workspace::new())
                .expect("spot compiles");
            let seconds = clock.elapsed().as_secs_f64();
            let optimization = compiled.optimization.as_ref().expect("spot is optimized");
            println!(
                "| {run} | {:.3} | {:.3} | {seconds:.3} | {} | {} | {} |",
                optimization.timings.precompute,
                optimization.timings.heuristic,
                ratio(seconds, baseline),
                optimization.chosen,
                yes(optimization.meets_goals)
            );
        }
        println!();
    }

    let last = baseline(&base);
    println!(
        "baseline at the end: {:.1} µs ({:.2} × the first)",
        last * 1e6,
        last / first
    );
}
