//! The convex hull of the example meshes: every vertex under every facet, facets convex and
//! outward, and the facets closing up into a polyhedron: their area-weighted normals sum to zero,
//! as for any closed surface, up to what merging coplanar triangles may move (the tolerance times
//! the facets' perimeters). (Euler's V − E + F = 2 need not hold once coplanar triangles are
//! merged: a corner within the tolerance of a neighbour facet's edge is left out of that facet.)

use std::path::Path;
use std::time::Instant;

use ballast::geometry::{convex_hull, load_mesh, MeshSelector};

#[test]
fn the_example_meshes_have_closed_convex_hulls() {
    for name in [
        "t_shape.obj",
        "spot.obj",
        "blub_fish.obj",
        "hammer.obj",
        "sheared_cylinder.obj",
    ] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("examples/meshes")
            .join(name);
        let mesh = load_mesh(&path, &MeshSelector::Whole).unwrap();
        let points = &mesh.positions;
        let started = Instant::now();
        let hull = convex_hull(points).expect("a hull");
        let took = started.elapsed();
        for facet in &hull.facets {
            let above = points
                .iter()
                .map(|p| facet.normal.dot(&p.coords) - facet.offset)
                .fold(f64::NEG_INFINITY, f64::max);
            assert!(
                above <= hull.tolerance,
                "{name}: a vertex {above} above a facet"
            );
            let n = facet.corners.len();
            assert!(n >= 3);
            for k in 0..n {
                let [a, b, c] = [k, (k + 1) % n, (k + 2) % n].map(|j| points[facet.corners[j]]);
                assert!(
                    (b - a).cross(&(c - b)).dot(&facet.normal) > 0.0,
                    "{name}: a facet turns the wrong way"
                );
            }
        }
        let area: f64 = hull.facets.iter().map(|f| f.area).sum();
        let closure: nalgebra::Vector3<f64> = hull.facets.iter().map(|f| f.normal * f.area).sum();
        let perimeter: f64 = hull
            .facets
            .iter()
            .map(|f| {
                let n = f.corners.len();
                (0..n)
                    .map(|k| (points[f.corners[(k + 1) % n]] - points[f.corners[k]]).norm())
                    .sum::<f64>()
            })
            .sum();
        assert!(
            closure.norm() <= hull.tolerance * perimeter,
            "{name}: {} with {area} of area and {perimeter} of edges",
            closure.norm()
        );
        println!(
            "{name}: {} vertices, hull of {} facets in {:.1} ms",
            points.len(),
            hull.facets.len(),
            took.as_secs_f64() * 1e3
        );
    }
}
