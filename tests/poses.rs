//! `down` and `ballast poses` on the T shape: the listed facets, their pasted lines, and `down`
//! against the equivalent `rotate`.

use std::path::{Path, PathBuf};
use std::process::Command;

use ballast::balance::{BallRest, PoseEvaluation};
use ballast::compile::{compile, Compilation};

fn t_shape() -> (PathBuf, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/t_shape.kdl");
    let text = std::fs::read_to_string(&path).unwrap();
    (path, text)
}

/// The T shape's project with `extra` poses added, compiled (its solution file's capsules).
fn t_shape_with(extra: &str) -> Result<Compilation, Vec<ballast::diagnostic::Problem>> {
    let (path, text) = t_shape();
    compile(&format!("{text}\n{extra}\n"), &path)
}

fn pose<'a>(compiled: &'a Compilation, name: &str) -> &'a PoseEvaluation {
    compiled
        .poses
        .iter()
        .find(|p| p.pose == name)
        .unwrap_or_else(|| panic!("no pose {name}"))
}

/// Asserts two evaluations of one resting state agree: where it stands does not matter, only how.
fn assert_same_rest(a: &PoseEvaluation, b: &PoseEvaluation) {
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-6 * (1.0 + x.abs());
    assert!(
        close(a.support.tilt_margin, b.support.tilt_margin),
        "{} vs {}",
        a.support.tilt_margin,
        b.support.tilt_margin
    );
    assert!(close(a.support.centre_height, b.support.centre_height));
    assert!(close(a.mass, b.mass));
    assert_eq!(a.support.contacts.len(), b.support.contacts.len());
    let rests = |e: &PoseEvaluation| e.balls.iter().map(|b| b.rest).collect::<Vec<BallRest>>();
    assert_eq!(rests(a), rests(b));
    let angles = |e: &PoseEvaluation| {
        let mut v: Vec<f64> = e
            .support
            .edges
            .iter()
            .map(|edge| edge.toppling_angle)
            .collect();
        v.sort_by(f64::total_cmp);
        v
    };
    for (x, y) in angles(a).into_iter().zip(angles(b)) {
        assert!(close(x, y), "{x} vs {y}");
    }
    let met = |e: &PoseEvaluation| e.goals.iter().map(|g| g.met).collect::<Vec<_>>();
    assert_eq!(met(a), met(b));
}

#[test]
fn down_gives_the_evaluation_of_the_equivalent_rotation() {
    // `rotate 0 36.8699 0` puts the face with outward normal n = Ry(−36.87°)·(0, 0, −1) =
    // (0.6, 0, −0.8) on the ground (the T is 3 : 4 from the stem foot to the bar end). The solid
    // T rolls off it, so the ray from its centre along n leaves through another facet: aim at
    // the face's corners instead (the vertices farthest along n), from the solid centroid.
    let (path, text) = t_shape();
    let plain = compile(&text, &path).expect("compiles");
    let mesh = &plain.meshes[0];
    let n = nalgebra::Vector3::new(0.6, 0.0, -0.8);
    let top = mesh
        .positions
        .iter()
        .map(|p| n.dot(&p.coords))
        .fold(f64::MIN, f64::max);
    let face: Vec<_> = mesh
        .positions
        .iter()
        .filter(|p| n.dot(&p.coords) > top - 1e-9)
        .collect();
    assert_eq!(face.len(), 4);
    let aim = face
        .iter()
        .map(|p| p.coords)
        .sum::<nalgebra::Vector3<f64>>()
        / 4.0
        - ballast::geometry::mass_properties(mesh).centroid.coords;
    let compiled = t_shape_with(&format!(
        "pose \"right by down\" {{ down {} {} {}; stand margin=2 }}\n\
         pose \"upside down by down\" {{ down 0 0 1; stand margin=2 }}",
        aim.x, aim.y, aim.z
    ))
    .expect("compiles");
    // The solid rolls off that face: a warning, not an error.
    assert!(compiled
        .warnings
        .iter()
        .any(|w| w.code == "ballast::pose::unstable_down" && !w.is_error()));
    assert_same_rest(
        pose(&compiled, "on its right side"),
        pose(&compiled, "right by down"),
    );
    assert_same_rest(
        pose(&compiled, "upside down"),
        pose(&compiled, "upside down by down"),
    );
    let by_down = pose(&compiled, "right by down").resting.as_ref().unwrap();
    assert!(by_down.correction < 1e-9, "{}", by_down.correction);
    // The written rotation is 2·10⁻⁶° off the exact atan2(3, 4).
    let written = pose(&compiled, "on its right side")
        .resting
        .as_ref()
        .unwrap();
    let off = (36.8699 - 3f64.atan2(4.0).to_degrees()).abs();
    assert!(
        (written.correction - off).abs() < 1e-7,
        "{}",
        written.correction
    );
}

#[test]
fn a_zero_down_or_one_beside_a_rotation_is_an_error_at_its_span() {
    for (extra, code) in [
        (
            "pose \"nowhere\" { down 0 0 0; stand }",
            "ballast::pose::zero_down",
        ),
        (
            "pose \"both\" { rotate 0 0 10; down 0 0 -1; stand }",
            "ballast::pose::down_with_steps",
        ),
    ] {
        let Err(problems) = t_shape_with(extra) else {
            panic!("{code}: the project compiled");
        };
        let (_, text) = t_shape();
        let problem = problems
            .iter()
            .find(|p| p.code == code)
            .unwrap_or_else(|| panic!("{code} missing from {problems:?}"));
        assert!(problem.is_error());
        let label = problem.labels.first().expect("a span");
        let source = format!("{text}\n{extra}\n");
        let at = &source[label.0.offset()..label.0.offset() + label.0.len()];
        assert!(at.contains("down") || at.contains("rotate"), "{code}: {at}");
    }
}

#[test]
fn ballast_poses_lists_the_t_shapes_faces_and_its_lines_paste() {
    let (path, _) = t_shape();
    let output = Command::new(env!("CARGO_BIN_EXE_ballast"))
        .args(["poses", path.to_str().unwrap()])
        .env("NO_COLOR", "1")
        .output()
        .expect("the ballast binary runs");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let stdout = String::from_utf8(output.stdout).unwrap();
    let lines: Vec<&str> = stdout.lines().filter(|l| l.starts_with("pose ")).collect();
    let rows: Vec<&str> = stdout
        .lines()
        .filter(|l| {
            l.trim_start()
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_digit())
        })
        .collect();
    // The four faces the example uses: upright, upside down and both sides.
    for normal in ["  0 0 -1", "  0 0 1", "  0.6 0 -0.8", "  -0.6 0 -0.8"] {
        assert!(
            rows.iter().any(|r| r.ends_with(normal)),
            "{normal} missing:\n{stdout}"
        );
    }
    // The hull has 8 facets: those four, the two 20 × 50 bar ends (the T falls off them) and
    // the front and back (where the solid T rests best).
    assert!(stdout.contains("of its 8 hull facets"), "{stdout}");
    assert_eq!(lines.len(), 6, "{stdout}");
    assert_eq!(rows.len(), 6, "{stdout}");
    assert!(rows[0].ends_with("  0 1 0") || rows[0].ends_with("  0 -1 0"));
    // Pasted into the project, every line parses and rests exactly on its facet, with the
    // design margin the listing printed.
    let compiled = t_shape_with(&lines.join("\n")).expect("the pasted poses compile");
    for (k, row) in rows.iter().enumerate() {
        let evaluation = pose(&compiled, &format!("facet {}", k + 1));
        assert!(evaluation.resting.as_ref().unwrap().correction < 1e-6);
        let design_margin: f64 = row
            .split_whitespace()
            .nth(2)
            .unwrap()
            .trim_end_matches('°')
            .parse()
            .unwrap();
        assert!(
            (evaluation.support.tilt_margin - design_margin).abs() <= 0.005,
            "facet {}: {} vs {row}",
            k + 1,
            evaluation.support.tilt_margin
        );
    }
}

#[test]
fn a_pose_that_settles_is_drawn_where_it_rests() {
    // Upright turned by 5° about x: the T settles back onto its base, turning about the edge it
    // first touches. The frames the drawing takes are the settled ones, so the base's four
    // corners lie on the ground the support was found on; in the written frame only the two of
    // that edge do.
    let compiled = t_shape_with("pose \"leaning\" {\n    rotate 5 0 0\n    stand\n}").unwrap();
    let leaning = pose(&compiled, "leaning");
    let resting = leaning.resting.as_ref().expect("it settles on a facet");
    assert!((resting.correction - 5.0).abs() < 1e-6, "{resting:?}");
    let mesh = &compiled.meshes[0];
    let ground = leaning.support.ground_height;
    let on_ground = |frame: &nalgebra::Isometry3<f64>| {
        mesh.positions
            .iter()
            .filter(|p| ((frame * *p).z - ground).abs() < 1e-9)
            .count()
    };
    assert_eq!(on_ground(&leaning.component_frames[0]), 4);
    let written = compiled
        .project
        .poses
        .iter()
        .find(|p| p.name.value == "leaning")
        .unwrap()
        .component_frame(0);
    assert_eq!(on_ground(&written), 2);
}
