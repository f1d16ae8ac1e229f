//! `ballast verify` against hand computations and on the examples.

use std::path::Path;

use ballast::compile::{compile, Compilation};
use ballast::verify::{verify, Detail, Verification};

mod geometry_support;

use ballast::geometry::TriMesh;
use geometry_support::{box_mesh, prism};

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
    eprintln!("{goal:#?}");
    let measured = goal.measured.expect("the box stands");
    assert!((measured - by_hand).abs() < 1.0, "{measured} vs {by_hand}");
}
