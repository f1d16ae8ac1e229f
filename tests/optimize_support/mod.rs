//! The optimization problem of a bundled example, for the tests that drive the optimizer's
//! pieces directly (`Problem`, the heuristic, the rescue).

use std::path::Path;

use ballast::compile::{self, compile_with, print_setup, CompileOptions, Preparation, Workspace};
use ballast::optimize::{Method, Problem};

/// Runs `check` with the problem of `examples/{name}.kdl` (the hybrid solver) and what the
/// optimizer stage prepared for it (distance grids and seeds).
pub fn with_example_problem(name: &str, check: impl FnOnce(&Problem, &Preparation)) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("examples/{name}.kdl"));
    let source = std::fs::read_to_string(&path).expect("the example's project file");
    let compiled = compile_with(
        &source,
        &path,
        &CompileOptions::default(),
        &mut Workspace::new(),
    )
    .expect("the example compiles");
    let project = &compiled.project;
    let settings = project.optimize.as_ref().expect("an optimize node");
    let print = print_setup(project, &compiled.orientations);
    let prepared = compile::prepare(
        project,
        settings,
        &compiled.meshes,
        &print,
        &mut Workspace::new(),
        None,
    )
    .expect("nothing cancels");
    let prints = compiled.part_prints();
    let problem = Problem::new(
        project,
        &compiled.meshes,
        &prints,
        print,
        prepared.interior.clone(),
        Method::Hybrid,
    );
    check(&problem, &prepared);
}
