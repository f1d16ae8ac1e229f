//! One workspace across builds, as watch mode keeps it: the cache skips precomputation for meshes
//! it has seen, an earlier design warm-starts the optimizer only for the meshes it was made for,
//! progress names the long stages, and a cancelled build gives nothing and caches nothing.

mod edit_support;

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use ballast::compile::{
    compile_with, Compilation, CompileOptions, Failure, OptimizeOptions, Stage, WarmStart,
    Workspace,
};

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
    let rounds: Vec<usize> = cold
        .iter()
        .filter_map(|stage| match stage {
            Stage::Round { capsules } => Some(*capsules),
            _ => None,
        })
        .collect();
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
    assert_eq!(
        again.first(),
        Some(&Stage::Round {
            capsules: first.design.capsules.len()
        })
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
    let (path, source) = t_shape();
    let mut workspace = Workspace::new();
    let check = CompileOptions::default();
    let first = build(&source, &path, &check, &mut workspace);
    assert_eq!(workspace.prints.sliced(), 1);
    let again = build(&source, &path, &check, &mut workspace);
    assert_eq!(workspace.prints.sliced(), 0);
    assert_eq!(again.prints, first.prints);
    assert_eq!(again.poses, first.poses);
    // Other settings are another print: sliced again, and more perimeters weigh more.
    let thicker = source.replace("wall 1.2", "wall 1.2\nprint perimeters=4");
    let other = build(&thicker, &path, &check, &mut workspace);
    assert_eq!(workspace.prints.sliced(), 1);
    assert!(other.prints[0].solid.volume > first.prints[0].solid.volume);
    assert!(other.poses[0].mass > first.poses[0].mass);
}
