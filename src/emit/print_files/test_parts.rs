//! Parts the print-file writers' tests share.

use std::f64::consts::PI;

use nalgebra::Point3;

use super::{BedMesh, BedPart, BedPause, BedVoid, PrintSettings};

/// An axis-aligned box from `min` to `max`, outward triangles.
pub(crate) fn box_mesh(min: Point3<f64>, max: Point3<f64>) -> BedMesh {
    let positions = (0..8)
        .map(|i| {
            Point3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        })
        .collect();
    let triangles = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    BedMesh {
        positions,
        triangles,
    }
}

/// A 40 × 30 × 20 mm block at x 10..50, y 20..50 on the bed, with a vertical capsule (`keel`,
/// ball 7 mm) and a tilted one (`tip`, ball 5 mm), one pause each on the 0.35 + k × 0.3 mm grid.
pub(crate) fn box_with_two_capsules() -> BedPart {
    BedPart {
        name: "block".to_string(),
        surface: box_mesh(Point3::new(10.0, 20.0, 0.0), Point3::new(50.0, 50.0, 20.0)),
        voids: vec![
            BedVoid {
                name: "keel".to_string(),
                from: Point3::new(20.0, 35.0, 7.0),
                to: Point3::new(20.0, 35.0, 13.0),
                radius: 4.0,
                ball_diameter: 7.0,
            },
            BedVoid {
                name: "tip".to_string(),
                from: Point3::new(30.0, 27.0, 5.0),
                to: Point3::new(42.0, 29.0, 12.0),
                radius: 3.0,
                ball_diameter: 5.0,
            },
        ],
        pauses: vec![
            BedPause {
                layers_done: 24,
                height: 7.25,
                resume_height: 7.55,
                voids: vec![1],
                message: "Insert one 5 mm steel ball into capsule `tip`".to_string(),
            },
            BedPause {
                layers_done: 34,
                height: 10.25,
                resume_height: 10.55,
                voids: vec![0],
                message: "Insert one 7 mm steel ball into capsule `keel`".to_string(),
            },
        ],
        orientation: "rest-frame -z down (declared)".to_string(),
    }
}

/// PrusaSlicer's defaults with 15% infill.
pub(crate) fn settings() -> PrintSettings {
    PrintSettings {
        layer_height: 0.3,
        first_layer_height: 0.35,
        perimeters: 3,
        top_solid_layers: 3,
        bottom_solid_layers: 3,
        infill: 0.15,
        extrusion_width: 0.45,
        solid_infill_below_area: 70.0,
        bed: [250.0, 210.0],
    }
}

/// The exact volume of a void's capsule.
pub(crate) fn capsule_volume(void: &BedVoid) -> f64 {
    let r = void.radius;
    PI * r * r * ((void.to - void.from).norm() + 4.0 / 3.0 * r)
}
