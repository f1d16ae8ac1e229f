//! `ballast verify` against hand computations and on the examples.

use std::path::Path;

use ballast::compile::{compile, Compilation};
use ballast::verify::{verify, Detail, Verification};

mod geometry_support;

use ballast::geometry::TriMesh;
use geometry_support::box_mesh;

/// `mesh` moved by `offset`, as OBJ text.
fn obj(mesh: &TriMesh, offset: [f64; 3]) -> String {
    let mut text = String::new();
    for p in &mesh.positions {
        text += &format!(
            "v {} {} {}\n",
            p.x + offset[0],
            p.y + offset[1],
            p.z + offset[2]
        );
    }
    for [a, b, c] in &mesh.triangles {
        text += &format!("f {} {} {}\n", a + 1, b + 1, c + 1);
    }
    text
}

/// Compiles `project` (KDL) beside a mesh file `mesh.obj` holding `obj`.
fn compiled(project: &str, obj: &str) -> Compilation {
    let folder = tempfile::tempdir().expect("a temporary folder");
    std::fs::write(folder.path().join("mesh.obj"), obj).expect("the mesh is written");
    let path = folder.path().join("project.kdl");
    std::fs::write(&path, project).expect("the project is written");
    match compile(project, &path) {
        Ok(compilation) => compilation,
        Err(problems) => panic!("the project compiles: {problems:#?}"),
    }
}

fn only_goal(verification: &Verification) -> &ballast::verify::GoalCheck {
    &verification.poses[0].goals[0]
}

#[test]
fn a_solid_box_topples_at_atan_half_width_over_height() {
    // 40 wide (x), 60 deep (y), 100 tall: the narrow side topples first, at atan(20 / 50).
    let project = r#"
component "box" mesh="mesh.obj"
pose "up" {
    stand margin=1
}
"#;
    let compilation = compiled(
        project,
        &obj(&box_mesh(40.0, 60.0, 100.0), [-20.0, -30.0, 0.0]),
    );
    let verification = verify(&compilation);
    let goal = only_goal(&verification);
    let by_hand = (20.0f64 / 50.0).atan().to_degrees();
    let measured = goal.measured.expect("the box stands");
    assert!((measured - by_hand).abs() < 1.0, "{measured} vs {by_hand}");
}

#[test]
fn a_leaning_prism_stands_on_the_slope_that_brings_its_centre_over_its_edge() {
    // A box 20 wide (x), 40 deep, 60 tall, sheared so that its top sits 40 further along x: its
    // centre of mass (the prism's centre, by its symmetry) is 30 along x and 30 up, 10 past the
    // base's edge at 20, so it topples; a ground descending towards −x by atan(10 / 30) brings
    // the centre over the edge.
    let project = r#"
component "prism" mesh="mesh.obj"
pose "leaning" {
    imbalance margin=1
}
"#;
    let mut prism = box_mesh(20.0, 40.0, 60.0);
    for p in &mut prism.positions {
        p.x += 40.0 * p.z / 60.0;
    }
    let compilation = compiled(project, &obj(&prism, [0.0, 0.0, 0.0]));
    let verification = verify(&compilation);
    let goal = only_goal(&verification);
    let by_hand = -(10.0f64 / 30.0).atan().to_degrees();
    let measured = goal.measured.expect("the prism stands on some slope");
    assert!((measured - by_hand).abs() < 1.0, "{measured} vs {by_hand}");
    assert!(
        (goal.computed - by_hand).abs() < 1.0,
        "{} vs {by_hand}",
        goal.computed
    );
    assert!(goal.agrees, "{goal:#?}");
    let Detail::Imbalance {
        topples, slopes, ..
    } = &goal.detail
    else {
        panic!("an imbalance check: {goal:#?}");
    };
    assert!(topples);
    assert_eq!(slopes.len(), ballast::verify::TILT_DIRECTIONS);
}

#[test]
fn a_ball_that_rolls_within_the_margin_lowers_it_as_by_hand() {
    // A box 60 × 60 × 100 at infill 0.1 with a capsule from x = −2 to x = 18 at z ≈ 80, rising
    // 8° towards +x. Set down, the ball rests at `from`, near the middle. Tilted towards +x, the
    // ball rolls to `to` once the tilt passes 8°, moving the centre of mass towards the downhill
    // edge: the margin is then the one with the ball at `to`, well below the one the ball at
    // `from` would give.
    let rise = 20.0 * 8f64.to_radians().tan();
    let project = format!(
        r#"
// The hand computation weighs uniform material at the infill fraction, and a ball of the
// capsule radius less the clearance.
print model="uniform"
ball any-size=#true
infill 0.1
component "box" mesh="mesh.obj"
capsule "c" component="box" radius=8 {{
    from -2 0 {low}
    to 18 0 {high}
}}
pose "up" {{
    stand margin=1
}}
"#,
        low = 80.0 - rise / 2.0,
        high = 80.0 + rise / 2.0
    );
    let compilation = compiled(
        &project,
        &obj(&box_mesh(60.0, 60.0, 100.0), [-30.0, -30.0, 0.0]),
    );
    let pla = 1.24e-3 * 0.1;
    let box_volume = 60.0 * 60.0 * 100.0;
    let void = std::f64::consts::PI * 64.0 * (20.0f64.hypot(rise) + 4.0 * 8.0 / 3.0);
    let ball = 7.85e-3 * 4.0 / 3.0 * std::f64::consts::PI * 7.8f64.powi(3);
    let mass = pla * (box_volume - void) + ball;
    // The void's centre at the axis midpoint (8, 0, 80), the ball's on the axis at an end.
    let centre = |x: f64, z: f64| {
        (
            (-pla * void * 8.0 + ball * x) / mass,
            (pla * box_volume * 50.0 - pla * void * 80.0 + ball * z) / mass,
        )
    };
    let (x_to, z_to) = centre(18.0, 80.0 + rise / 2.0);
    let (x_from, z_from) = centre(-2.0, 80.0 - rise / 2.0);
    let rolled = ((30.0 - x_to) / z_to).atan().to_degrees();
    let held = ((30.0 - x_from) / z_from).atan().to_degrees();
    let other_side = ((30.0 + x_from) / z_from).atan().to_degrees();
    assert!(
        rolled > 8.0,
        "the ball rolls before the model topples: {rolled}"
    );
    assert!(
        held.min(other_side) - rolled > 2.0,
        "{rolled} {held} {other_side}"
    );
    let verification = verify(&compilation);
    let measured = only_goal(&verification).measured.expect("the box stands");
    assert!((measured - rolled).abs() < 1.0, "{measured} vs {rolled}");
}

#[test]
fn a_box_hung_off_centre_turns_by_atan_offset_over_drop() {
    // A solid box 40 × 60 × 100 (centre (0, 0, 50)) hung from (10, 0, 100): the string from the
    // point to the centre of mass is 11.31° off vertical, by hand atan(10 / 50).
    let project = r#"
component "box" mesh="mesh.obj"
pose "hung" {
    suspend 10 0 100 tolerance=20
}
"#;
    let compilation = compiled(
        project,
        &obj(&box_mesh(40.0, 60.0, 100.0), [-20.0, -30.0, 0.0]),
    );
    let verification = verify(&compilation);
    let goal = only_goal(&verification);
    let by_hand = (10.0f64 / 50.0).atan().to_degrees();
    let measured = goal.measured.expect("a release from the pose");
    assert!((measured - by_hand).abs() < 1.0, "{measured} vs {by_hand}");
    let Detail::Suspend { states, .. } = &goal.detail else {
        panic!("a suspend goal");
    };
    // Without balls a hanging body has one stable state, whatever it is released from.
    assert_eq!(states.len(), 1, "{states:#?}");
}

#[test]
fn a_box_with_a_ball_off_centre_floats_turned_as_by_hand() {
    // A box 40 × 40 × 40 at infill 0.5 with a vertical capsule at x = 12: the ball rests at the
    // bottom (z = 8 − 0.2); the centre of buoyancy is the box's centre (0, 0, 20). By hand, the
    // angle between up and the centre of mass's direction to the centre of buoyancy.
    let project = r#"
// The hand computation weighs uniform material at the infill fraction, and a ball of the
// capsule radius less the clearance.
print model="uniform"
ball any-size=#true
infill 0.5
component "box" mesh="mesh.obj"
capsule "c" component="box" radius=6 {
    from 12 0 8
    to 12 0 32
}
pose "floating" {
    immerse fluid-density=1 tolerance=90
}
"#;
    let compilation = compiled(
        project,
        &obj(&box_mesh(40.0, 40.0, 40.0), [-20.0, -20.0, 0.0]),
    );
    let pla = 1.24e-3 * 0.5;
    let box_volume = 64000.0;
    let void = std::f64::consts::PI * 36.0 * (24.0 + 8.0);
    let ball = 7.85e-3 * 4.0 / 3.0 * std::f64::consts::PI * 5.8f64.powi(3);
    let mass = pla * (box_volume - void) + ball;
    let x = (-pla * void * 12.0 + ball * 12.0) / mass;
    let z = (pla * box_volume * 20.0 - pla * void * 20.0 + ball * 8.0) / mass;
    let by_hand = (x.abs() / (20.0 - z)).atan().to_degrees();
    let verification = verify(&compilation);
    let goal = only_goal(&verification);
    let measured = goal.measured.expect("a release from the pose");
    assert!((measured - by_hand).abs() < 1.0, "{measured} vs {by_hand}");
}

/// The verification of the example `name` with its committed solution file.
fn example(name: &str) -> Verification {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(format!("{name}.kdl"));
    let source = std::fs::read_to_string(&path).expect("the example is readable");
    let compilation = compile(&source, &path).expect("the example compiles");
    verify(&compilation)
}

#[test]
fn the_hammer_hangs_level_and_has_a_second_hang() {
    let verification = example("hammer");
    let level = &verification.poses[0].goals[0];
    assert!(level.agrees, "{level:#?}");
    let measured = level.measured.expect("a release from the pose");
    assert!((measured - level.computed).abs() < 1.0);
    let Detail::Suspend { states, .. } = &level.detail else {
        panic!("a suspend goal");
    };
    // The second stable hang ballast reports (36.1° off level for the print-true design), with
    // the ball at the other end, is found by the simulation too.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/hammer.kdl");
    let compilation = compile(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    let ballast::balance::GoalOutcome::Suspend { equilibria, .. } =
        &compilation.poses[0].goals[0].outcome
    else {
        panic!("a suspend goal");
    };
    let second = equilibria
        .states
        .iter()
        .find(|state| !state.wanted)
        .expect("ballast reports a second hang");
    assert!(
        states
            .iter()
            .any(|state| (state.angle - second.angle).abs() < 1.0
                && state.balls != states[0].balls),
        "{states:#?}"
    );
}

#[test]
fn the_fish_floats_upright_when_released_from_its_pose() {
    let verification = example("fish");
    let swimming = &verification.poses[0].goals[0];
    let measured = swimming.measured.expect("a release from the pose");
    assert!((measured - swimming.computed).abs() <= 1.0, "{swimming:#?}");
    let Detail::Immerse { releases, .. } = &swimming.detail else {
        panic!("an immerse goal");
    };
    assert!(releases[0].settled, "{:#?}", releases[0]);
}

#[test]
fn the_unique_hangs_and_floats_right_themselves_from_every_release() {
    // Spot hung level and the fish under water ask for `unique=#true`: released from each of
    // the ten orientations, the simulated print must come to rest (a light print swings and
    // settles within the simulated time) in the one state ballast computed.
    for (name, pose) in [("spot", "hung level"), ("fish", "swimming")] {
        let verification = example(name);
        let check = verification
            .poses
            .iter()
            .find(|check| check.pose == pose)
            .unwrap_or_else(|| panic!("{name} has a pose {pose}"));
        let goal = &check.goals[0];
        assert!(goal.agrees, "{name}: {goal:#?}");
        let (Detail::Suspend { releases, states } | Detail::Immerse { releases, states }) =
            &goal.detail
        else {
            panic!("{name}: a hanging or floating goal");
        };
        assert_eq!(releases.len(), 10, "{name}");
        for release in releases {
            assert!(release.settled, "{name}: {release:#?}");
            assert!(
                (release.angle - goal.computed).abs() <= 1.0,
                "{name}: {release:#?}"
            );
        }
        assert_eq!(states.len(), 1, "{name}: {states:#?}");
    }
}

#[test]
fn the_t_shape_is_checked_on_every_side_and_agrees() {
    // Every stand goal gets a measured margin within 1° of the computed one. Upright, a 16 mm
    // ball changes end while the ground tilts, just before the model would topple: the
    // simulated body must take the shift of weight without a jolt.
    let verification = example("t_shape");
    assert_eq!(verification.poses.len(), 4);
    for pose in &verification.poses {
        let goal = &pose.goals[0];
        let Detail::Stand { runs, .. } = &goal.detail else {
            panic!("a stand goal");
        };
        assert_eq!(runs.len(), ballast::verify::TILT_DIRECTIONS);
        let measured = goal.measured.expect("the T stands");
        assert!(
            measured > 2.0 && measured < 60.0,
            "{}: {measured}",
            pose.pose
        );
        assert!(goal.agrees, "{}: {goal:#?}", pose.pose);
    }
}

#[test]
fn every_other_example_agrees_with_the_simulation() {
    // The T shape, the hammer, the fish and Spot's hang have tests of their own above; these are
    // the rest: the sheared cylinder on both ends, the articulated arm's stand and imbalance, and
    // Spot's four stands (one on a narrow triangle of three feet) and its imbalance, and the
    // figure built from a rig's animations.
    for name in ["sheared_cylinder", "articulated", "spot", "figure"] {
        let verification = example(name);
        for pose in &verification.poses {
            for goal in &pose.goals {
                if KNOWN_DISAGREEMENTS.contains(&(name, pose.pose.as_str())) {
                    continue;
                }
                assert!(
                    goal.agrees,
                    "{name}, pose {}: {:?}",
                    pose.pose, goal.disagreement
                );
            }
        }
    }
}

/// Goals of the examples whose simulated value is known to differ from the computed one by
/// more than the agreement bound, with the reason in docs/physics.md ("Known disagreements").
/// [`the_known_disagreements_persist`] keeps the list honest: an entry that comes to agree fails it.
const KNOWN_DISAGREEMENTS: [(&str, &str); 1] = [("spot", "on its back")];

#[test]
fn the_known_disagreements_persist() {
    // Spot on its back must topple: computed, it rocks onto a neighbouring facet of its
    // rounded back and stands there on slopes from about 3.0°; simulated, it arrives there
    // moving and rolls on, standing only from 4.2°.
    for (name, pose_name) in KNOWN_DISAGREEMENTS {
        let verification = example(name);
        let pose = verification
            .poses
            .iter()
            .find(|pose| pose.pose == pose_name)
            .expect("the pose exists");
        let goal = &pose.goals[0];
        assert!(
            !goal.agrees,
            "{name}, pose {pose_name} now agrees: {goal:#?}"
        );
        let measured = goal.measured.expect("a measured slope");
        assert!(
            measured < goal.computed && goal.computed < 0.0,
            "{name}, pose {pose_name}: {goal:#?}"
        );
    }
}
