//! The optimizer on every example: what it must achieve, and that the committed solution files are
//! what a build writes today (so they are current and the build is deterministic).

use std::path::{Path, PathBuf};

use ballast::balance::GoalOutcome;
use ballast::compile::{
    compile_with, length_decimals, solution_text, Compilation, CompileOptions, DesignSource,
    OptimizeOptions, Workspace,
};
use ballast::optimize::{capsule_radius, grid_scale};
use ballast::spec::stock::stock_diameters_mm;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(format!("{name}.kdl"))
}

fn optimized(name: &str, options: OptimizeOptions) -> Compilation {
    let path = example(name);
    let source = std::fs::read_to_string(&path).unwrap();
    let options = CompileOptions {
        out_dir: None,
        optimize: Some(options),
        ..CompileOptions::default()
    };
    compile_with(&source, &path, &options, &mut Workspace::new())
        .unwrap_or_else(|failure| panic!("{name} did not compile: {failure:?}"))
}

/// Every goal's verdict, pose by pose, as (pose, kind, met, tilt margin if any).
fn verdicts(compilation: &Compilation) -> Vec<(String, bool, Option<f64>)> {
    compilation
        .poses
        .iter()
        .flat_map(|pose| {
            pose.goals.iter().map(move |goal| {
                let tilt = match goal.outcome {
                    GoalOutcome::Stand { tilt_margin, .. }
                    | GoalOutcome::Imbalance { tilt_margin, .. } => Some(tilt_margin),
                    _ => None,
                };
                (pose.pose.clone(), goal.met, tilt)
            })
        })
        .collect()
}

/// Optimizes `name` and checks that the committed solution file is exactly what was written.
fn optimized_and_current(name: &str) -> Compilation {
    let compilation = optimized(name, OptimizeOptions::default());
    assert_eq!(compilation.source, DesignSource::Optimized);
    let written = solution_text(
        &compilation.project,
        &format!("{name}.kdl"),
        &compilation.meshes,
        &compilation.design,
    );
    let committed = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("examples")
            .join(format!("{name}.solution.kdl")),
    )
    .unwrap();
    assert_eq!(
        written, committed,
        "examples/{name}.solution.kdl is not what `ballast build` writes now"
    );
    every_ball_is_a_stock_ball(name, &compilation);
    every_ball_goes_in_at_a_pause(name, &compilation);
    check_agrees_with_build(name, &compilation);
    compilation
}

/// Asserts that every capsule of the design takes its ball at a planned pause in its component's
/// print orientation, with no `no_insertion_window` warning.
fn every_ball_goes_in_at_a_pause(name: &str, compilation: &Compilation) {
    let planned: Vec<_> = compilation
        .print_plan
        .components
        .iter()
        .flat_map(|component| &component.capsules)
        .collect();
    assert_eq!(planned.len(), compilation.design.capsules.len(), "{name}");
    for insertion in planned {
        assert!(
            insertion.pause.is_some(),
            "{name}: capsule {} has no pause: {insertion:?}",
            insertion.capsule
        );
    }
    assert!(
        compilation
            .warnings
            .iter()
            .all(|w| w.code != "ballast::capsule::no_insertion_window"),
        "{name}"
    );
}

/// Asserts that the project uses the stock ball list (it lists none) and that every capsule holds
/// a ball of it, in a capsule exactly that ball plus the clearance on the solution file's grid.
fn every_ball_is_a_stock_ball(name: &str, compilation: &Compilation) {
    let ball = &compilation.project.ball;
    let units = compilation.project.units;
    let stock: Vec<f64> = stock_diameters_mm()
        .into_iter()
        .map(|mm| units.from_millimetres(mm))
        .collect();
    assert_eq!(ball.diameters, stock, "{name}: not the stock list");
    let scale = grid_scale(length_decimals(&compilation.meshes));
    for capsule in &compilation.design.capsules {
        let diameter = 2.0 * capsule.ball_radius;
        assert!(
            stock.contains(&diameter),
            "{name}: capsule {} holds a {diameter} ball, not a stock one",
            capsule.name
        );
        assert_eq!(
            capsule.radius,
            capsule_radius(ball, capsule.ball_radius, scale),
            "{name}: capsule {} is not its ball plus the clearance",
            capsule.name
        );
    }
}

/// Asserts that `ballast check` on the committed solution file judges every goal exactly as the
/// optimizing build did: the design the optimizer judged is the one it wrote.
fn check_agrees_with_build(name: &str, built: &Compilation) {
    let path = example(name);
    let source = std::fs::read_to_string(&path).unwrap();
    let checked = compile_with(
        &source,
        &path,
        &CompileOptions::default(),
        &mut Workspace::new(),
    )
    .unwrap_or_else(|failure| panic!("{name} did not check: {failure:?}"));
    assert!(matches!(checked.source, DesignSource::SolutionFile(_)));
    assert_eq!(checked.design, built.design, "{name}: design read back");
    assert_eq!(verdicts(&checked), verdicts(built), "{name}: verdicts");
}

/// Asserts that in every pose with a `stand` or `imbalance` goal, no ball rolls while the ground
/// tilts by less than the goal's margin: the goal is met with the balls rolling, not only held.
fn no_ball_rolls_within_the_required_margin(compilation: &Compilation) {
    for pose in &compilation.poses {
        for goal in &pose.goals {
            let margin = match goal.outcome {
                GoalOutcome::Stand { margin, .. } | GoalOutcome::Imbalance { margin, .. } => margin,
                _ => continue,
            };
            for moved in &pose.support.ball_moves {
                assert!(
                    moved.tilt >= margin,
                    "{}: ball {} rolls at {:.2}°, within the margin of {margin}°",
                    pose.pose,
                    moved.capsule,
                    moved.tilt
                );
            }
        }
    }
}

#[test]
fn sheared_cylinder_stands_on_both_ends_and_no_capsule_cannot() {
    let compilation = optimized_and_current("sheared_cylinder");
    assert!(compilation.all_goals_met(), "{:?}", verdicts(&compilation));
    assert!(!compilation.design.capsules.is_empty());
    let optimization = compilation.optimization.as_ref().unwrap();
    let none = optimization
        .candidates
        .iter()
        .find(|c| c.capsules == 0)
        .expect("the heuristic goes down to zero capsules");
    assert!(!none.meets_goals);
    assert!(none.worst_tilt_margin.unwrap() < 0.0);
}

/// The paper's sheared cylinder with one capsule: the heuristic's design is as good as the best of
/// 20 random starts (`--exhaustive 20`), within the objective's resolution on the solution file's
/// grid (designs a grid step apart differ by up to 0.004°). Its stock ball is the trial of
/// `Problem::with_other_balls`: the snapped 7/8" ball reaches -9.86°, the random starts'
/// 13/16" one -10.15°.
#[test]
fn sheared_cylinder_with_one_capsule_is_as_good_as_twenty_random_starts() {
    let options = OptimizeOptions {
        exhaustive: 20,
        ..OptimizeOptions::default()
    };
    let compilation = optimized("sheared_cylinder", options);
    let optimization = compilation.optimization.as_ref().unwrap();
    let one = optimization
        .exhaustive
        .iter()
        .find(|ranking| ranking.capsules == 1)
        .expect("a ranking for one capsule");
    assert_eq!(one.starts, 20);
    assert!(
        one.heuristic_objective <= one.best_objective + 0.005,
        "{one:?}"
    );
}

#[test]
fn t_shape_stands_in_all_four_orientations_with_three_capsules() {
    let compilation = optimized_and_current("t_shape");
    assert!(compilation.all_goals_met(), "{:?}", verdicts(&compilation));
    let candidates = &compilation.optimization.as_ref().unwrap().candidates;
    let three = candidates
        .iter()
        .find(|c| c.capsules == 3)
        .unwrap_or_else(|| panic!("no candidate with 3 capsules: {candidates:?}"));
    assert!(three.meets_goals, "{three:?}");
    // The paper reports 8° with one capsule and 13° with two on its T, for uniform material and
    // balls of any size; printed, the solid shells weigh more than the balls can move, and with
    // stock balls it takes three capsules to keep a little above the 2° asked. Solid, the T
    // topples on its sides (−8°).
    assert!(three.worst_tilt_margin.unwrap() >= 2.0, "{three:?}");
    let none = candidates.iter().find(|c| c.capsules == 0).unwrap();
    assert!(none.worst_tilt_margin.unwrap() < -5.0, "{none:?}");
}

#[test]
fn a_requested_capsule_count_is_honoured() {
    let compilation = optimized(
        "t_shape",
        OptimizeOptions {
            capsules: Some(4),
            ..OptimizeOptions::default()
        },
    );
    assert_eq!(compilation.design.capsules.len(), 4);
    assert_eq!(
        compilation.optimization.as_ref().unwrap().requested,
        Some(4)
    );
    assert!(compilation.all_goals_met(), "{:?}", verdicts(&compilation));
}

#[test]
fn articulated_arm_stands_in_one_pose_and_topples_in_its_mirror() {
    let compilation = optimized_and_current("articulated");
    let verdicts = verdicts(&compilation);
    assert!(compilation.all_goals_met(), "{verdicts:?}");
    assert!(verdicts[0].2.unwrap() > 0.0, "{verdicts:?}");
    assert!(verdicts[1].2.unwrap() < 0.0, "{verdicts:?}");
    no_ball_rolls_within_the_required_margin(&compilation);
}

#[test]
fn hammer_hangs_level_and_fish_self_rights_from_every_orientation() {
    for name in ["hammer", "fish"] {
        let compilation = optimized_and_current(name);
        assert!(
            compilation.all_goals_met(),
            "{name}: {:?}",
            verdicts(&compilation)
        );
        let optimization = compilation.optimization.as_ref().unwrap();
        let none = optimization.candidates.iter().find(|c| c.capsules == 0);
        assert!(!none.unwrap().meets_goals, "{name}: solid already meets it");
        // A hanging or floating goal's term is its angle less its tolerance: a candidate whose
        // objective puts every goal clearly within tolerance is one the judge finds meeting them,
        // when that objective is corrected by the material of the design judged (the hammer's
        // four capsules once reported -1.06 deg, corrected at another design, and hung 2.31 deg
        // off level).
        for candidate in &optimization.candidates {
            assert!(
                !candidate.printable || candidate.objective > -0.25 || candidate.meets_goals,
                "{name}: {candidate:?}"
            );
        }
        // The fish asks for uniqueness: the optimizer's design floats upright only. The hammer
        // does not, and its design also hangs turned in its level pose.
        let states: Vec<usize> = compilation.poses[0]
            .goals
            .iter()
            .map(|goal| match &goal.outcome {
                GoalOutcome::Suspend { equilibria, .. }
                | GoalOutcome::Immerse { equilibria, .. } => equilibria.states.len(),
                _ => 0,
            })
            .collect();
        let expected = if name == "fish" { 1 } else { 2 };
        assert_eq!(states, vec![expected], "{name}: stable states");
    }
}

#[test]
fn spot_meets_all_six_goals_that_the_solid_misses_three_of() {
    let compilation = optimized_and_current("spot");
    assert_eq!(compilation.poses.len(), 6);
    assert!(compilation.all_goals_met(), "{:?}", verdicts(&compilation));
    assert!(compilation.design.capsules.len() <= 2);
    no_ball_rolls_within_the_required_margin(&compilation);
}

#[test]
fn a_pinned_capsule_is_kept_exactly_and_a_written_seed_may_move() {
    let path = example("t_shape");
    let source = std::fs::read_to_string(&path).unwrap().replace(
        "\noptimize tolerance=0.2\n",
        "\noptimize capsules=2\n\
         capsule \"junction\" component=\"T\" radius=8 pinned=#true { from -15 0 23; to 15 0 26; }\n\
         capsule \"bar\" component=\"T\" radius=2 { from -50 0 35; to -40 0 36; }\n",
    );
    let options = CompileOptions {
        out_dir: None,
        optimize: Some(OptimizeOptions::default()),
        ..CompileOptions::default()
    };
    let compilation = compile_with(&source, &path, &options, &mut Workspace::new()).unwrap();
    let capsules = &compilation.design.capsules;
    assert_eq!(capsules.len(), 2, "{capsules:?}");
    let junction = capsules.iter().find(|c| c.name == "junction").unwrap();
    assert_eq!(junction.from, nalgebra::Point3::new(-15.0, 0.0, 23.0));
    assert_eq!(junction.to, nalgebra::Point3::new(15.0, 0.0, 26.0));
    assert_eq!(junction.radius, 8.0);
    // The moved seed is named after where it ended (its component and a counter), and the report
    // says it came from `bar`.
    let origins = &compilation.optimization.as_ref().unwrap().origins;
    let from_bar = origins
        .iter()
        .find(|o| o.seed == "written" && o.seed_name.as_deref() == Some("bar"))
        .unwrap_or_else(|| panic!("{origins:?}"));
    assert!(!capsules.iter().any(|c| c.name == "bar"), "{capsules:?}");
    let bar = capsules
        .iter()
        .find(|c| c.name == from_bar.capsule)
        .unwrap();
    assert_eq!(bar.name, "T 1");
    assert_ne!(bar.from, nalgebra::Point3::new(-50.0, 0.0, 35.0));
    // The written seed replaces the skeleton's seeds.
    let optimization = compilation.optimization.as_ref().unwrap();
    assert!(optimization.seeds.is_empty());
    // Two capsules around this junction miss a goal: the random starts of the second chance
    // were tried, and none meeting every goal, the design is still the one from `bar`.
    assert!(!optimization.meets_goals);
    assert!(optimization.rescue_starts > 0);
    let text = solution_text(
        &compilation.project,
        "t_shape.kdl",
        &compilation.meshes,
        &compilation.design,
    );
    assert!(
        text.contains("capsule \"junction\" component=\"T\" radius=8 pinned=#true {"),
        "{text}"
    );
}
