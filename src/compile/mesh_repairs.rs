//! The diagnostics for what loading repaired in a component's mesh ([`Repairs`]): a warning for
//! each kind of repair, saying what changed; an error for a hole too wide for a slicer to close.

use super::design::round;
use super::meshes::format_position;
use crate::diagnostic::Problem;
use crate::geometry::{Hole, Repairs};
use crate::spec::model::Component;

/// The largest share of a mesh's size a hole may span, when that is more than the wall, and be
/// capped: a missing triangle or a crack is a few percent of it; a missing face or an open
/// sheet, most of it.
const HOLE_SHARE: f64 = 0.1;

/// The problems of `component`'s mesh repaired as `repairs` says (its holes in project units),
/// where a hole wider than `wall`, and than 10 % of the mesh's largest `extent`, is an error: a
/// slicer closes cracks and pinholes, but a hole that wide is a missing piece of the surface, and
/// a cap across it a guess.
pub(super) fn repair_problems(
    component: &Component,
    repairs: &Repairs,
    wall: f64,
    extent: f64,
) -> Vec<Problem> {
    let name = &component.name.value;
    let span = component.mesh.span;
    let plural = |count: usize| if count == 1 { "" } else { "s" };
    let mut problems = Vec::new();
    if let Some(first) = repairs.collapsed_triangles.first() {
        let count = repairs.collapsed_triangles.len();
        problems.push(
            Problem::warning(
                "ballast::mesh::collapsed",
                format!(
                    "the mesh of component `{name}` has {count} triangle{} with two corners at \
                     one point (the first is triangle {} of the file), left out: they enclose \
                     nothing, so the volume is unchanged",
                    plural(count),
                    first + 1
                ),
            )
            .with_help(
                "nothing to do; a mesh editor's merge by distance removes them from the file",
            ),
        );
    }
    if repairs.repeated_triangles > 0 {
        let count = repairs.repeated_triangles;
        problems.push(
            Problem::warning(
                "ballast::mesh::repeated",
                format!(
                    "the mesh of component `{name}` has {count} triangle{} repeating the corners \
                     of another, left out (a doubled face counts once; a face and its reverse \
                     enclose nothing)",
                    plural(count)
                ),
            )
            .with_help(
                "a mesh editor's merge by distance, then delete duplicate faces, removes them",
            ),
        );
    }
    if repairs.flipped_triangles > 0 {
        let count = repairs.flipped_triangles;
        problems.push(
            Problem::warning(
                "ballast::mesh::flipped",
                format!(
                    "the mesh of component `{name}` has {count} triangle{} facing the other way \
                     from the surface around {}, turned over to match it",
                    plural(count),
                    if count == 1 { "it" } else { "them" }
                ),
            )
            .with_help("recalculate the normals in a mesh editor to fix the file"),
        );
    }
    if repairs.turned_inside_out {
        problems.push(
            Problem::warning(
                "ballast::mesh::inverted",
                format!(
                    "the mesh of component `{name}` is inside out (its triangles face inwards): \
                     every triangle was turned over, as a slicer does"
                ),
            )
            .with_help("flip the normals in a mesh editor to fix the file"),
        );
    }
    problems.extend(hole_problem(
        name,
        &repairs.holes,
        wall,
        wall.max(HOLE_SHARE * extent),
    ));
    problems
        .into_iter()
        .map(|problem| problem.with_label(span, "this mesh"))
        .collect()
}

/// One diagnostic for all of a mesh's holes: an error naming the widest when it is wider than
/// `limit` (at least the `wall`), else a warning that they were capped.
fn hole_problem(name: &str, holes: &[Hole], wall: f64, limit: f64) -> Option<Problem> {
    let widest = holes
        .iter()
        .copied()
        .reduce(|a, b| if b.width > a.width { b } else { a })?;
    let count = holes.len();
    let holes_text = if count == 1 {
        "a hole".to_string()
    } else {
        format!("{count} holes")
    };
    let place = format!(
        "{} mm across at {}, {} edges around it",
        round(widest.width),
        format_position(&widest.centre),
        widest.edges
    );
    Some(if widest.width > limit {
        Problem::error(
            "ballast::mesh::open",
            format!(
                "the mesh of component `{name}` has {holes_text} in its surface{}: {place}, \
                 wider than the wall ({} mm) and than 10 % of the mesh's size, too wide to close \
                 as a slicer closes a crack",
                if count == 1 { "" } else { ", the widest" },
                round(wall)
            ),
        )
        .with_help("a printable solid must be closed: fill the holes in a mesh editor")
    } else {
        Problem::warning(
            "ballast::mesh::hole",
            format!(
                "the mesh of component `{name}` has {holes_text} in its surface, capped as a \
                 slicer closes {}{}: {place}",
                if count == 1 { "it" } else { "them" },
                if count == 1 { "" } else { " (the widest" }
            ) + if count == 1 { "" } else { ")" },
        )
        .with_help("a mesh editor's fill holes closes them in the file")
    })
}
