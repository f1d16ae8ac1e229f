//! The plan a sliced file is checked against when the project has no print plan: every
//! component printed upright, as the mass model assumes.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

use crate::compile::Compilation;
use crate::fabrication::{ComponentPlan, OrientationChoice, PrintPlan};

/// Gap between neighbouring parts on the bed, mm.
const GAP_MM: f64 = 10.0;

/// Every component of `compilation` printed with the project's `up` axis up (the direction the
/// `fdm` mass model builds along), its lowest point on the bed, side by side along x in project
/// order with a 10 mm gap. It plans the orientation only: no insertions, no pauses.
pub fn upright_plan(compilation: &Compilation) -> PrintPlan {
    let project = &compilation.project;
    let up = project.up.unit_vector();
    let rotation = UnitQuaternion::rotation_between(&up, &Vector3::z()).unwrap_or_default();
    let gap = project.units.from_millimetres(GAP_MM);
    let mut x = 0.0;
    let components = compilation
        .meshes
        .iter()
        .enumerate()
        .map(|(index, mesh)| {
            let turned: Vec<Point3<f64>> = mesh.positions.iter().map(|p| rotation * p).collect();
            let (low, high) = turned.iter().fold(
                (
                    Point3::from([f64::INFINITY; 3]),
                    Point3::from([f64::NEG_INFINITY; 3]),
                ),
                |(lo, hi), p| (lo.inf(p), hi.sup(p)),
            );
            let (low, high) = if turned.is_empty() {
                (Point3::origin(), Point3::origin())
            } else {
                (low, high)
            };
            let to_bed =
                Isometry3::from_parts(Translation3::new(x - low.x, -low.y, -low.z), rotation);
            x += high.x - low.x + gap;
            let area = bed_area(&turned, &mesh.triangles, low.z);
            ComponentPlan {
                component: index,
                to_bed,
                down: -up,
                orientation: OrientationChoice::Chosen {
                    area,
                    reason: "upright along the project's up axis, as the mass model prints it"
                        .to_string(),
                },
                capsules: Vec::new(),
                pauses: Vec::new(),
            }
        })
        .collect();
    PrintPlan {
        first_layer_height: project.print.first_layer_height,
        layer_height: project.print.layer_height,
        components,
    }
}

/// Area of the triangles of `positions` that lie flat at height `bottom`.
fn bed_area(positions: &[Point3<f64>], triangles: &[[u32; 3]], bottom: f64) -> f64 {
    let extent = positions
        .iter()
        .map(|p| p.z - bottom)
        .fold(0.0, f64::max)
        .max(1.0);
    triangles
        .iter()
        .filter_map(|t| {
            let [a, b, c] = t.map(|i| positions.get(i as usize));
            let (a, b, c) = (a?, b?, c?);
            [a, b, c]
                .iter()
                .all(|p| (p.z - bottom).abs() <= 1e-9 * extent)
                .then(|| (b - a).cross(&(c - a)).norm() / 2.0)
        })
        .sum()
}
