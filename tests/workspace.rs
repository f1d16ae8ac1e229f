//! One workspace across builds, as watch mode keeps it: the cache skips precomputation for meshes
//! it has seen, an earlier design warm-starts the optimizer only for the meshes it was made for,
//! progress names the long stages, and a cancelled build gives nothing and caches nothing.

mod edit_support;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use ballast::compile::{
    compile_with, Compilation, CompileOptions, Failure, OptimizeOptions, Stage, WarmStart,
    Workspace,
};
use ballast::optimize::Round;

fn t_shape() -> (PathBuf, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/t_shape.kdl");
    let source = std::fs::read_to_string(&path).unwrap();
    (path, source)
}

fn options(warm_start: Option<WarmStart>) -> CompileOptions {
    CompileOptions {
        out_dir: None,
        optimize: Some(OptimizeOptions {
            warm_start,
            ..OptimizeOptions::default()
        }),
        ..CompileOptions::default()
    }
}

/// A workspace whose progress is recorded in the returned list.
fn recording() -> (Workspace, Arc<Mutex<Vec<Stage>>>) {
    let stages: Arc<Mutex<Vec<Stage>>> = Arc::default();
    let sink = stages.clone();
    let workspace = Workspace {
        progress: Some(Box::new(move |stage| sink.lock().unwrap().push(stage))),
        ..Workspace::new()
    };
    (workspace, stages)
}

fn build(
    source: &str,
    path: &Path,
    options: &CompileOptions,
    workspace: &mut Workspace,
) -> Compilation {
    workspace.start_build();
    compile_with(source, path, options, workspace).unwrap_or_else(|f| panic!("{f:?}"))
}

fn taken(stages: &Arc<Mutex<Vec<Stage>>>) -> Vec<Stage> {
    std::mem::take(&mut *stages.lock().unwrap())
}

#[test]
fn a_goal_edit_reuses_the_precomputation_and_starts_from_the_last_design() {
    let (path, source) = t_shape();
    let (mut workspace, stages) = recording();
    let first = build(&source, &path, &options(None), &mut workspace);
    let cold = taken(&stages);
    assert!(
        matches!(&cold[..2], [Stage::Grid { component, nodes }, Stage::Skeleton { .. }] if component == "T" && *nodes > 0),
        "{cold:?}"
    );
    let solves: Vec<Round> = cold
        .iter()
        .filter_map(|stage| match stage {
            Stage::Round(at) => Some(*at),
            _ => None,
        })
        .collect();
    // Each solve says its round and place: rounds counted from 1, solves from 1 within each.
    for (i, at) in solves.iter().enumerate() {
        assert!(
            at.round <= at.most_rounds && at.solve <= at.solves,
            "{at:?}"
        );
        let next_round = i == 0 || solves[i - 1].round + 1 == at.round;
        let next_solve = i > 0 && solves[i - 1].round == at.round && solves[i - 1].solve < at.solve;
        assert!(
            (at.solve == 1 && next_round && (i > 0 || at.round == 1)) || next_solve,
            "{solves:?}"
        );
    }
    // A round's solves are numbered 1 to the count it says it runs, none left out.
    for round in solves.iter().map(|at| at.round) {
        let numbers: Vec<usize> = solves
            .iter()
            .filter(|at| at.round == round)
            .map(|at| at.solve)
            .collect();
        let said = solves.iter().find(|at| at.round == round).unwrap().solves;
        assert_eq!(numbers, (1..=said).collect::<Vec<_>>(), "{solves:?}");
    }
    let rounds: Vec<usize> = solves
        .iter()
        .filter(|at| at.solve == 1)
        .map(|at| at.capsules)
        .collect();
    assert_eq!(rounds.len(), solves.last().unwrap().round);
    assert!(
        rounds.len() >= 2 && rounds.windows(2).all(|w| w[0] > w[1]),
        "{rounds:?}"
    );
    assert_eq!(rounds.last(), Some(&0));
    let optimization = first.optimization.as_ref().unwrap();
    assert!(!optimization.warm_started && optimization.meets_goals);

    // Another margin asked of every pose (a smaller one: printed, the T has little more than 2°
    // to give): no sampling, no thinning, and the heuristic starts from the last design's capsules.
    let edited = source.replace("stand margin=2", "stand margin=1");
    let warm = WarmStart::new(&first.meshes, first.design.clone());
    let second = build(&edited, &path, &options(Some(warm.clone())), &mut workspace);
    let again = taken(&stages);
    assert!(
        again
            .iter()
            .all(|stage| matches!(stage, Stage::Round { .. })),
        "{again:?}"
    );
    assert!(
        matches!(again.first(), Some(Stage::Round(at)) if at.round == 1 && at.solve == 1 && at.capsules == first.design.capsules.len()),
        "{again:?}"
    );
    let optimization = second.optimization.as_ref().unwrap();
    assert!(optimization.warm_started && optimization.meets_goals);
    assert!(optimization.seeds.is_empty());
    assert_eq!(workspace.cache.built().grids, 0);
    assert_eq!(workspace.meshes.loaded(), 0);

    // The same warm start after the mesh moved does not fit: a cold start, and a new grid.
    let folder = tempfile::tempdir().unwrap();
    std::fs::create_dir(folder.path().join("meshes")).unwrap();
    let obj = std::fs::read_to_string(path.with_file_name("meshes/t_shape.obj")).unwrap();
    std::fs::write(
        folder.path().join("meshes/t_shape.obj"),
        edit_support::shifted_obj(&obj, 1.0),
    )
    .unwrap();
    let elsewhere = folder.path().join("t_shape.kdl");
    let third = build(&edited, &elsewhere, &options(Some(warm)), &mut workspace);
    assert!(!third.optimization.as_ref().unwrap().warm_started);
    assert_eq!(workspace.cache.built().grids, 1);
    assert!(matches!(taken(&stages).first(), Some(Stage::Grid { .. })));
}

#[test]
fn a_cancelled_build_gives_nothing_and_caches_nothing() {
    let (path, source) = t_shape();
    let mut workspace = Workspace::new();
    workspace.cancel.cancel();
    let result = compile_with(&source, &path, &options(None), &mut workspace);
    assert!(matches!(result, Err(Failure::Cancelled)), "{result:?}");
    assert!(workspace.cache.is_empty());

    // Reset, the same workspace builds.
    workspace.cancel.reset();
    let built = compile_with(&source, &path, &options(None), &mut workspace);
    assert!(built.is_ok());
    assert_eq!(workspace.cache.len(), 1);
}

#[test]
fn a_build_that_is_not_optimized_reports_no_stage() {
    let (path, source) = t_shape();
    let (mut workspace, stages) = recording();
    let checked = compile_with(&source, &path, &CompileOptions::default(), &mut workspace);
    assert!(checked.is_ok());
    assert!(taken(&stages).is_empty());
}

#[test]
fn a_mesh_is_sliced_once_per_print_settings() {
    // The hammer: an example with a calibration file.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hammer.kdl");
    let source = std::fs::read_to_string(&path).unwrap();
    let mut workspace = Workspace::new();
    let check = CompileOptions::default();
    let first = build(&source, &path, &check, &mut workspace);
    assert_eq!(workspace.prints.sliced(), 1);
    let again = build(&source, &path, &check, &mut workspace);
    assert_eq!(workspace.prints.sliced(), 0);
    assert_eq!(again.prints, first.prints);
    assert_eq!(again.poses, first.poses);
    // Other settings are another print: sliced again, and more perimeters weigh more.
    let thicker = source.replace("wall (mm)1.2", "wall (mm)1.2\nprint perimeters=4");
    let other = build(&thicker, &path, &check, &mut workspace);
    assert_eq!(workspace.prints.sliced(), 1);
    // The example's calibration was measured at the default settings: it corrects the first
    // build and is left out of the other.
    assert_eq!(other.corrections[0], Default::default());
    let uncorrected = first.prints[0].solid.volume - first.corrections[0].volume;
    assert!(other.prints[0].solid.volume > uncorrected);
    // PLA at 1.24 g/cm³, the volume in cubic inches.
    let correction_grams = 1.24 * first.project.units.cubic_in_cm3() * first.corrections[0].volume;
    assert!(other.poses[0].mass > first.poses[0].mass - correction_grams);
}

/// A T asked, in one orientation, both to stand and to topple: no design meets both.
const CONFLICTING: &str = r#"
infill 0.2
optimize capsules=1
component "T" mesh="meshes/t_shape.obj" {
    print { down 1 0 0 }
}
pose "on its right side" {
    rotate 0 36.8699 0
    stand margin=1
}
pose "again on its right side" {
    rotate 0 36.8699 0
    imbalance margin=1
}
"#;

#[test]
fn an_explanation_cut_short_keeps_the_design_and_says_so() {
    let (folder, path) = t_project(CONFLICTING);

    // Run to its end, the explanation names the pair and was not cut short.
    let (mut workspace, stages) = recording();
    let full = build(CONFLICTING, &path, &options(None), &mut workspace);
    let optimization = full.optimization.as_ref().unwrap();
    assert!(!optimization.meets_goals && optimization.interrupted.is_none());
    assert!(!optimization.conflicts_cut_short);
    assert!(!optimization.conflicts.is_empty());
    let solves: Vec<usize> = taken(&stages)
        .iter()
        .filter_map(|stage| match stage {
            Stage::Conflicts { solve } => Some(*solve),
            _ => None,
        })
        .collect();
    assert_eq!(solves, (1..=solves.len()).collect::<Vec<_>>());
    let last = *solves.last().unwrap();

    // Out of time as the last solve of the explanation starts: the same design, written and
    // marked as interrupted, the explanation marked as cut short, and what it had shown kept.
    let cancel = ballast::cancel::Cancel::new();
    let stop = cancel.clone();
    let mut workspace = Workspace {
        cancel,
        progress: Some(Box::new(move |stage| {
            if stage == (Stage::Conflicts { solve: last }) {
                stop.interrupt(ballast::cancel::Interruption::TimeLimit);
            }
        })),
        ..Workspace::new()
    };
    let cut = build(CONFLICTING, &path, &options(None), &mut workspace);
    let optimization = cut.optimization.as_ref().unwrap();
    assert_eq!(
        optimization.interrupted,
        Some(ballast::cancel::Interruption::TimeLimit)
    );
    assert!(optimization.conflicts_cut_short);
    assert!(optimization.conflicts.len() < full.optimization.as_ref().unwrap().conflicts.len());
    assert_eq!(cut.design, full.design);
    ballast::compile::write_outputs(&cut, &path, None).unwrap();
    let report: serde_json::Value = serde_json::from_slice(
        &std::fs::read(folder.path().join("build/model.report.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(report["optimization"]["conflicts_cut_short"], true);
    assert_eq!(report["optimization"]["interrupted"], "time-limit");
    let solution = std::fs::read_to_string(folder.path().join("model.solution.kdl")).unwrap();
    assert!(solution.starts_with("// INTERRUPTED:"), "{solution}");
}

/// The T laid on both sides, each asked for more margin than one capsule gives it, and upright,
/// which any design meets.
const TWO_UNREACHABLE: &str = r#"
infill 0.2
optimize
component "T" mesh="meshes/t_shape.obj" {
    print { down 1 0 0 }
}
pose "upright" {
    stand margin=2
}
pose "on its right side" {
    rotate 0 36.8699 0
    stand margin=15
}
pose "on its left side" {
    rotate 0 -36.8699 0
    stand margin=15
}
"#;

/// A folder with the T's mesh under `meshes/` and `source` as `model.kdl`; the project's path.
fn t_project(source: &str) -> (tempfile::TempDir, PathBuf) {
    let folder = tempfile::tempdir().unwrap();
    std::fs::create_dir(folder.path().join("meshes")).unwrap();
    let (t_path, _) = t_shape();
    std::fs::copy(
        t_path.with_file_name("meshes/t_shape.obj"),
        folder.path().join("meshes/t_shape.obj"),
    )
    .unwrap();
    let path = folder.path().join("model.kdl");
    std::fs::write(&path, source).unwrap();
    (folder, path)
}

#[test]
fn with_one_capsule_asked_the_explanation_names_each_goal_one_capsule_cannot_meet() {
    let one_capsule = CompileOptions {
        optimize: Some(OptimizeOptions {
            capsules: Some(1),
            ..OptimizeOptions::default()
        }),
        ..CompileOptions::default()
    };
    let (_folder, path) = t_project(TWO_UNREACHABLE);
    let built = build(TWO_UNREACHABLE, &path, &one_capsule, &mut Workspace::new());
    let optimization = built.optimization.as_ref().unwrap();
    assert_eq!(optimization.chosen, 1);
    assert!(!optimization.meets_goals);
    assert!(!optimization.conflicts_cut_short);
    let alone: Vec<&str> = optimization
        .conflicts
        .iter()
        .filter(|conflict| conflict.goals.len() == 1)
        .map(|conflict| conflict.goals[0].pose.as_str())
        .collect();
    assert_eq!(
        alone,
        ["on its right side", "on its left side"],
        "{:#?}",
        optimization.conflicts
    );
    for conflict in &optimization.conflicts {
        assert!(conflict.shortfall.is_finite() && conflict.shortfall > 0.0);
    }
    // Each, asked alone of one capsule, is missed too: the explanation searched the space the
    // build was asked to search.
    for (pose, turn) in [
        ("on its right side", 36.8699),
        ("on its left side", -36.8699),
    ] {
        let source = format!(
            "infill 0.2\noptimize capsules=1\ncomponent \"T\" mesh=\"meshes/t_shape.obj\" {{\n    \
             print {{ down 1 0 0 }}\n}}\npose \"{pose}\" {{\n    rotate 0 {turn} 0\n    \
             stand margin=15\n}}\n"
        );
        let (_folder, path) = t_project(&source);
        let single = build(&source, &path, &options(None), &mut Workspace::new());
        let optimization = single.optimization.as_ref().unwrap();
        assert!(!optimization.meets_goals, "{pose} met by one capsule alone");
    }
}

/// The T with one capsule placed by hand, no search: `INFILL` is replaced to change the print.
const PLACED: &str = r#"
infill INFILL
component "T" mesh="meshes/t_shape.obj"
pose "upright" { stand }
capsule "heavy" component="T" radius=3 {
    from 5 0 12
    to 15 0 12
}
"#;

/// The print files under `folder` (STL, 3MF, the sheet and its pictures), by path.
fn print_files_under(folder: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    walkdir(folder)
        .into_iter()
        .filter(|path| {
            path.extension()
                .is_some_and(|e| ["stl", "3mf", "md", "svg"].iter().any(|x| e == *x))
        })
        .map(|path| {
            let bytes = std::fs::read(&path).unwrap();
            (path, bytes)
        })
        .collect()
}

/// The paths of the files whose bytes differ between `a` and `b`, or that only one has.
fn differing(a: &BTreeMap<PathBuf, Vec<u8>>, b: &BTreeMap<PathBuf, Vec<u8>>) -> Vec<PathBuf> {
    a.keys()
        .chain(b.keys())
        .filter(|path| a.get(*path) != b.get(*path))
        .cloned()
        .collect()
}

fn walkdir(folder: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(folder).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            found.extend(walkdir(&path));
        } else {
            found.push(path);
        }
    }
    found
}

#[test]
fn print_files_are_encoded_again_only_when_what_they_show_changed() {
    let source = PLACED.replace("INFILL", "0.2");
    let (folder, path) = t_project(&source);
    let out = folder.path().join("out");
    let mut workspace = Workspace::new();
    let compile = |source: &str, workspace: &mut Workspace| {
        workspace.start_build();
        compile_with(source, &path, &CompileOptions::default(), workspace).unwrap()
    };
    let write = |compilation: &Compilation, workspace: &mut Workspace| {
        ballast::compile::write_outputs_with(
            compilation,
            &path,
            Some(&out),
            &mut workspace.print_files,
        )
        .unwrap();
        print_files_under(&out)
    };

    let first = compile(&source, &mut workspace);
    let written = write(&first, &mut workspace);
    assert_eq!(workspace.print_files.encoded(), 1);
    assert_eq!(written.len(), 4, "{:?}", written.keys());

    // The same design and settings again (a goal-only edit judging the last design): the
    // cached print files, the same bytes as a build that encodes them afresh.
    let again = compile(
        &source.replace("{ stand }", "{ stand margin=1 }"),
        &mut workspace,
    );
    let rewritten = write(&again, &mut workspace);
    assert_eq!(workspace.print_files.encoded(), 1);
    assert_eq!(differing(&rewritten, &written), Vec::<PathBuf>::new());
    ballast::compile::write_outputs(&again, &path, Some(&out)).unwrap();
    assert_eq!(
        differing(&print_files_under(&out), &written),
        Vec::<PathBuf>::new()
    );

    // Another infill changes the 3MF's settings: encoded again, as a fresh build encodes it.
    let denser = PLACED.replace("INFILL", "0.3");
    let changed = compile(&denser, &mut workspace);
    let cached = write(&changed, &mut workspace);
    assert_eq!(workspace.print_files.encoded(), 2);
    let changed_files = differing(&cached, &written);
    assert!(
        changed_files
            .iter()
            .any(|p| p.extension().is_some_and(|e| e == "3mf")),
        "{changed_files:?}"
    );
    ballast::compile::write_outputs(&changed, &path, Some(&out)).unwrap();
    assert_eq!(
        differing(&print_files_under(&out), &cached),
        Vec::<PathBuf>::new()
    );
}
