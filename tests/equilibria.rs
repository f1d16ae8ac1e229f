//! Every stable state of hanging and floating goals: a one-capsule box against a closed form, the
//! hammer's second hang and the fish's stuck state recomputed here from the centre of mass of the
//! flipped ball, and `unique=#true` failing a goal that has another state.

mod balance_support;
mod geometry_support;
mod objective_support;

use std::path::Path;

use balance_support::{assert_close, ball_volume, capsule, evaluate, project, rest_pose};
use ballast::balance::{BallRest, Equilibria, GoalOutcome, PoseEvaluation};
use ballast::compile::{compile, Compilation};
use ballast::design::Design;
use ballast::objective::Parameters;
use ballast::random::SplitMix64;
use ballast::spec::model::{Goal, Pose, Project};
use geometry_support::box_mesh;
use nalgebra::{Point3, Vector3};
use objective_support::{objective, random_capsule, tall_box, unique};

/// The equilibria of goal `goal` of `evaluation`, and whether the goal was met.
fn equilibria(evaluation: &PoseEvaluation, goal: usize) -> (&Equilibria, bool) {
    let outcome = &evaluation.goals[goal];
    match &outcome.outcome {
        GoalOutcome::Suspend { equilibria, .. } | GoalOutcome::Immerse { equilibria, .. } => {
            (equilibria, outcome.met)
        }
        other => panic!("not a hanging or floating goal: {other:?}"),
    }
}

/// Angle between two vectors, degrees.
fn degrees_between(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    (a.dot(b) / (a.norm() * b.norm()))
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees()
}

// The box [0,40]×[0,60]×[0,100] mm at 15 % infill, hung from (20, 30, 58), with one capsule of
// radius 8 whose axis (length 30) is centred on the vertical through the point at height 30 and
// rises `alpha` degrees along +x. The ball fills the capsule's width (no clearance), so it sits
// exactly at an end point.
//
// By hand: the material less the void, M0, has its centre on the vertical x = 20 at
// z0 = (V·50 − v·30) / (V − v) (V the box's volume, v = πr²(L + 4/3 r) the void's); the ball m
// sits at e = (20 ± (L/2) cos α, 30, 30 ± (L/2) sin α). With c = (M0 c0 + m e) / (M0 + m), the
// model hangs with gravity along c − s, turned φ = atan(|c_x − 20| / (s_z − c_z)) from vertical.
// The axis â = (cos α, 0, sin α) then has â·g = −sin(α + φ) with the ball at `from` (it stays
// when α + φ ≥ 3°, the min-angle) and sin(φ − α) at `to` (it stays when φ − α ≥ 3°).
const SUSPENSION: [f64; 3] = [20.0, 30.0, 58.0];
const INFILL: f64 = 0.15;
const RADIUS: f64 = 8.0;
const LENGTH: f64 = 30.0;
const HEIGHT: f64 = 30.0;

/// The closed form above: for the ball at `to` (else `from`), the angle φ off vertical, and how
/// far above horizontal the axis keeps the ball at its end there (negative: it rolls away).
fn closed_form(alpha: f64, to: bool, project: &Project) -> (f64, f64) {
    let pi = std::f64::consts::PI;
    let material = project.material.density * INFILL;
    let box_volume = 40.0 * 60.0 * 100.0;
    let void = pi * RADIUS * RADIUS * (LENGTH + 4.0 / 3.0 * RADIUS);
    let m0 = material * (box_volume - void);
    let z0 = (box_volume * 50.0 - void * HEIGHT) / (box_volume - void);
    let m = project.ball.density * ball_volume(RADIUS);
    let sign = if to { 1.0 } else { -1.0 };
    let a = alpha.to_radians();
    let ex = 20.0 + sign * LENGTH / 2.0 * a.cos();
    let ez = HEIGHT + sign * LENGTH / 2.0 * a.sin();
    let cx = (m0 * 20.0 + m * ex) / (m0 + m);
    let cz = (m0 * z0 + m * ez) / (m0 + m);
    let phi = ((cx - 20.0).abs()).atan2(SUSPENSION[2] - cz).to_degrees();
    let keeps = if to { phi - alpha } else { alpha + phi };
    (phi, keeps)
}

fn hung_box(alpha: f64) -> (Project, PoseEvaluation) {
    let mut project = project(&["box"]);
    project.ball.clearance = 0.0;
    let goal = Goal::Suspend {
        point: Point3::from(SUSPENSION),
        component: 0,
        tolerance: 2.0,
        unique: true,
    };
    let pose = rest_pose(1, vec![goal]);
    let a = alpha.to_radians();
    let half = Vector3::new(a.cos(), 0.0, a.sin()) * LENGTH / 2.0;
    let middle = Point3::new(20.0, 30.0, HEIGHT);
    let design = Design {
        capsules: vec![capsule(0, middle - half, middle + half, RADIUS, RADIUS)],
        infill: INFILL,
    };
    let evaluation = evaluate(&project, &[box_mesh(40.0, 60.0, 100.0)], &design, &pose);
    (project, evaluation)
}

#[test]
fn a_hung_box_with_one_capsule_has_the_states_of_the_closed_form() {
    let mut seen = [false; 3];
    for alpha in [5.0, 12.0, 18.0, 30.0] {
        let (project, evaluation) = hung_box(alpha);
        let (found, met) = equilibria(&evaluation, 0);
        assert!(found.complete);
        assert_eq!(found.assignments, 2);
        // A state where the axis keeps its ball at least min-angle above horizontal, a marginal
        // one within min-angle of it, none when the ball clearly rolls away.
        let min_angle = project.ball.min_angle;
        let mut expected = Vec::new();
        for to in [false, true] {
            let (phi, keeps) = closed_form(alpha, to, &project);
            if keeps > -min_angle {
                expected.push((to, phi, keeps < min_angle));
            }
        }
        assert_eq!(
            found.states.len(),
            expected.len(),
            "alpha {alpha}: {found:?}"
        );
        for (state, (to, phi, marginal)) in found.states.iter().zip(&expected) {
            let rest = if *to { BallRest::To } else { BallRest::From };
            assert_eq!(state.balls[0].rest, rest);
            // In the pose the axis rises along +x, so the ball is wanted at `from`.
            assert_eq!(state.wanted, !to);
            assert_eq!(state.balls[0].moved, *to);
            assert_close("angle off vertical", state.angle, *phi, 1e-9);
            assert_eq!(state.marginal, *marginal, "alpha {alpha}");
        }
        // unique=#true: the goal fails while the other state exists (and always here, since
        // the wanted hang is some 17° off vertical, beyond the tolerance).
        assert!(!met);
        let others = found.unwanted().count();
        let marginal = found.states.iter().any(|s| s.marginal);
        seen[0] |= others == 1 && !marginal;
        seen[1] |= marginal;
        seen[2] |= others == 0;
    }
    assert_eq!(
        seen, [true; 3],
        "the cases cover a second state, a marginal one and none"
    );
}

fn checked(name: &str) -> Compilation {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(format!("{name}.kdl"));
    let source = std::fs::read_to_string(&path).unwrap();
    compile(&source, &path).unwrap_or_else(|problems| panic!("{name}: {problems:?}"))
}

/// Recomputes, from the pose's own centre of mass, the angle off vertical the model settles at
/// with ball 0 moved to its other end, hung or floating about `anchor` (world), and the elevation
/// of the ball's axis there, positive when it keeps the ball at its new end. The ball's mass moves
/// by the capsule's axis, and its drop against the end cap (`r − b`, along gravity) turns from the
/// pose's gravity to the new one: iterated until the direction settles.
fn flipped_angle(compilation: &Compilation, pose: usize, anchor: &Point3<f64>) -> (f64, f64) {
    let evaluation = &compilation.poses[pose];
    let capsule = &compilation.design.capsules[0];
    let frame = compilation.project.poses[pose].component_frame(capsule.component);
    let axis = frame * (capsule.to - capsule.from);
    let ball = &evaluation.balls[0];
    let shift = match ball.rest {
        BallRest::From => axis,
        _ => -axis,
    };
    let down = -compilation.project.up.unit_vector();
    let drop = capsule.radius - capsule.ball_radius;
    let weight = ball.mass / evaluation.mass;
    let mut gravity = down;
    for _ in 0..100 {
        let moved = shift + (gravity - down) * drop;
        let centre = Point3::from(evaluation.centre_of_mass) + moved * weight;
        gravity = (centre - anchor).normalize();
    }
    let keeps = shift.normalize().dot(&gravity);
    (degrees_between(&gravity, &down), keeps.asin().to_degrees())
}

#[test]
fn the_hammer_also_hangs_off_level_with_its_ball_at_the_other_end() {
    let compilation = checked("hammer");
    let level = &compilation.poses[0];
    let GoalOutcome::Suspend { point, .. } = level.goals[0].outcome else {
        panic!("the level pose hangs");
    };
    let (found, _) = equilibria(level, 0);
    assert!(found.complete);
    assert_eq!(found.states.len(), 2, "{found:?}");
    assert!(found.states[0].wanted);
    let other = &found.states[1];
    assert!(!other.wanted && other.balls[0].moved);
    assert_ne!(other.balls[0].rest, level.balls[0].rest);
    let (angle, keeps) = flipped_angle(&compilation, 0, &Point3::from(point));
    // A real second state, well away from level (23° for the design of the uniform-infill mass
    // model, 39° for today's print-true one).
    assert!(other.angle > 10.0, "{}", other.angle);
    assert_close("second hang", other.angle, angle, 0.01);
    assert!(
        keeps > compilation.project.ball.min_angle,
        "the ball stays: {keeps}"
    );
    // Head down it has one state only: the flipped ball would not stay.
    let (head_down, _) = equilibria(&compilation.poses[1], 0);
    assert_eq!(head_down.states.len(), 1, "{head_down:?}");
    assert!(head_down.states[0].wanted);
    // The warning names it.
    let warning = compilation
        .warnings
        .iter()
        .find(|w| w.code == "ballast::goal::other_state")
        .expect("a warning for the second hang");
    let named = format!("{:.1}°", other.angle);
    assert!(warning.message.contains(&named), "{}", warning.message);
}

/// The fish as optimized before its goal asked for uniqueness, under the uniform-infill mass model
/// it was optimized for: released upside down, its ball rolls to the other end and it stays
/// turned.
const STUCK_FISH: &str = r#"
units in
up y
material "PLA" density=1.24
print model="uniform"
ball density=7.85 clearance=(mm)0.2
infill 0.75
wall (mm)1.2
component "fish" mesh="MESH"
pose "swimming" {
    immerse fluid-density=1.0 min-distance=(mm)0.5 tolerance=2 mass-tolerance=1
}
capsule "fish 1" component="fish" radius=0.1853 {
    from 3.2266 0.2128 -0.004
    to 3.3442 -0.2715 -0.0309
}
"#;

#[test]
fn a_fish_without_uniqueness_can_float_about_150_degrees_turned() {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes/blub_fish.obj");
    let source = STUCK_FISH.replace("MESH", &mesh.to_string_lossy());
    let compilation = compile(&source, &mesh.with_file_name("stuck_fish.kdl")).unwrap();
    let swimming = &compilation.poses[0];
    let GoalOutcome::Immerse {
        buoyancy_centre, ..
    } = swimming.goals[0].outcome
    else {
        panic!("the fish floats");
    };
    let (found, met) = equilibria(swimming, 0);
    assert!(met, "the goal does not ask for uniqueness");
    assert_eq!(found.states.len(), 2, "{found:?}");
    let stuck = &found.states[1];
    assert!(!stuck.wanted);
    assert!((145.0..155.0).contains(&stuck.angle), "{}", stuck.angle);
    let (angle, keeps) = flipped_angle(&compilation, 0, &Point3::from(buoyancy_centre));
    assert_close("stuck state", stuck.angle, angle, 0.01);
    assert!(
        keeps > compilation.project.ball.min_angle,
        "the ball stays: {keeps}"
    );
    // The same design with unique=#true fails the goal.
    let source = source.replace("mass-tolerance=1", "mass-tolerance=1 unique=#true");
    let unique = compile(&source, &mesh.with_file_name("stuck_fish.kdl")).unwrap();
    assert!(!unique.poses[0].goals[0].met);
}

#[test]
fn the_committed_fish_rights_itself_from_every_orientation() {
    let compilation = checked("fish");
    let (found, met) = equilibria(&compilation.poses[0], 0);
    assert!(met);
    assert!(found.complete);
    assert_eq!(found.assignments, 1 << compilation.design.capsules.len());
    assert_eq!(found.states.len(), 1, "{found:?}");
    assert!(found.states[0].wanted && found.states[0].angle < 2.0);
}

/// `count` random steep capsules in the tall box, and the box hung from its top centre.
fn many_capsules(count: usize, goal: Goal) -> (Project, Design, Pose) {
    let mut rng = SplitMix64::new(11);
    let capsules = (0..count)
        .map(|j| {
            let mut c = random_capsule(
                &mut rng,
                0,
                Point3::origin(),
                Point3::new(40.0, 60.0, 100.0),
                true,
            );
            c.name = format!("c{j}");
            c
        })
        .collect();
    let design = Design {
        capsules,
        infill: 0.2,
    };
    (project(&["box"]), design, rest_pose(1, vec![goal]))
}

fn hung_from_top(unique: bool) -> Goal {
    Goal::Suspend {
        point: Point3::new(20.0, 30.0, 100.0),
        component: 0,
        tolerance: 2.0,
        unique,
    }
}

#[test]
fn past_twelve_balls_only_moves_of_one_or_two_balls_are_tried() {
    for (count, assignments, complete) in [(12, 4096, true), (13, 1 + 13 + 78, false)] {
        let (project, design, pose) = many_capsules(count, hung_from_top(false));
        let evaluation = evaluate(&project, &[tall_box()], &design, &pose);
        let (found, _) = equilibria(&evaluation, 0);
        assert_eq!(found.complete, complete, "{count} balls");
        assert_eq!(found.assignments, assignments, "{count} balls");
        // Every state listed keeps its balls: each axis at least min-angle from horizontal,
        // unless marked marginal.
        for state in &found.states {
            let lowest = state
                .balls
                .iter()
                .map(|b| b.elevation)
                .fold(f64::INFINITY, f64::min);
            assert_eq!(state.marginal, lowest < project.ball.min_angle);
        }
    }
}

#[test]
fn a_unique_goal_adds_one_constraint_per_other_assignment() {
    for (count, others) in [(1, 1), (3, 7), (6, 63), (7, 7 + 21)] {
        let (project, design, pose) = many_capsules(count, hung_from_top(false));
        let mut with_unique = project.clone();
        with_unique.poses = vec![pose.clone()];
        with_unique.poses[0].goals[0].value = unique(hung_from_top(false));
        let mut plain = project;
        plain.poses = vec![pose];
        let count_of = |project: &Project| {
            let objective = objective(
                project,
                &[tall_box()],
                &design,
                Parameters::for_project(project),
            );
            objective
                .constraints(&objective.layout().to_vector(&design))
                .len()
        };
        assert_eq!(
            count_of(&with_unique) - count_of(&plain),
            others,
            "{count} capsules"
        );
    }
}

/// Quasi-static release of a one-ball model from gravity direction `start` (unit, the pose's
/// world frame) with its ball at `to` (else `from`): the model turns a small step at a time
/// towards hanging (or floating) with its centre of mass below `anchor`, the ball rolling to the
/// lower end whenever its axis is at least min-angle from horizontal and staying put otherwise.
/// Returns the settled angle off the pose's gravity, degrees. It uses only the pose's centre of
/// mass and the capsule, not the enumeration.
fn released(compilation: &Compilation, anchor: &Point3<f64>, start: Vector3<f64>, to: bool) -> f64 {
    let evaluation = &compilation.poses[0];
    let capsule = &compilation.design.capsules[0];
    let frame = compilation.project.poses[0].component_frame(capsule.component);
    let ends = [frame * capsule.from, frame * capsule.to];
    let axis = (ends[1] - ends[0]).normalize();
    let ball = &evaluation.balls[0];
    let drop = capsule.radius - capsule.ball_radius;
    let fixed = Point3::from(evaluation.centre_of_mass).coords * evaluation.mass
        - Vector3::from(ball.centre_world) * ball.mass;
    let sine = compilation.project.ball.min_angle.to_radians().sin();
    let mut gravity = start.normalize();
    let mut at_to = to;
    for _ in 0..20_000 {
        let along = axis.dot(&gravity);
        if along >= sine {
            at_to = true;
        } else if along <= -sine {
            at_to = false;
        }
        let end = ends[usize::from(at_to)];
        let centre = (fixed + (end.coords + gravity * drop) * ball.mass) / evaluation.mass;
        let wanted = (Point3::from(centre) - anchor).normalize();
        let step = (wanted - gravity * wanted.dot(&gravity)) * 0.02;
        gravity = (gravity + step).normalize();
        if step.norm() < 1e-12 {
            break;
        }
    }
    degrees_between(&gravity, &-compilation.project.up.unit_vector())
}

/// `count` directions spread evenly over the sphere (a Fibonacci lattice).
fn directions(count: usize) -> Vec<Vector3<f64>> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..count)
        .map(|k| {
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / count as f64;
            let r = (1.0 - z * z).sqrt();
            let turn = golden * k as f64;
            Vector3::new(r * turn.cos(), r * turn.sin(), z)
        })
        .collect()
}

#[test]
fn released_quasi_statically_the_committed_fish_rights_itself_and_the_stuck_one_does_not() {
    let fish = checked("fish");
    let GoalOutcome::Immerse {
        buoyancy_centre,
        tolerance,
        ..
    } = fish.poses[0].goals[0].outcome
    else {
        panic!("the fish floats");
    };
    let mut worst = 0.0f64;
    for start in directions(300) {
        for to in [false, true] {
            worst = worst.max(released(&fish, &Point3::from(buoyancy_centre), start, to));
        }
    }
    eprintln!("fish released from 600 starts: at most {worst:.3}° off upright");
    assert!(worst <= tolerance, "settled {worst}° off upright");

    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes/blub_fish.obj");
    let source = STUCK_FISH.replace("MESH", &mesh.to_string_lossy());
    let stuck = compile(&source, &mesh.with_file_name("stuck_fish.kdl")).unwrap();
    let GoalOutcome::Immerse {
        buoyancy_centre, ..
    } = stuck.poses[0].goals[0].outcome
    else {
        panic!("the fish floats");
    };
    let (found, _) = equilibria(&stuck.poses[0], 0);
    let up = stuck.project.up.unit_vector();
    // Released upside down (gravity along the pose's up), the ball rolls and the fish stays turned
    // where the enumeration says.
    let settled = [false, true].map(|to| {
        released(
            &stuck,
            &Point3::from(buoyancy_centre),
            up + Vector3::x() * 0.01,
            to,
        )
    });
    eprintln!("stuck fish released upside down: {settled:?}°");
    assert!(
        settled
            .iter()
            .any(|angle| (angle - found.states[1].angle).abs() < 0.1),
        "{settled:?} against {}",
        found.states[1].angle
    );
}
