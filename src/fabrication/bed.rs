//! The bed layout: every component turned into its print orientation, its lowest point lifted
//! to z = 0, the components side by side along x with a gap between their bounding boxes, each
//! centred on the layout's y axis, and the whole layout centred on the bed's centre.

use nalgebra::{Isometry3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};

/// Where the layout goes, in the meshes' units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bed {
    /// The point of the bed the layout's bounding box is centred on (x, y).
    pub centre: [f64; 2],
    /// Space between neighbouring components' bounding boxes, along x.
    pub gap: f64,
}

/// Rest frame to bed frame per component, in the order given: `meshes[i]`'s positions turned
/// by `rotations[i]` and placed as the module documentation says. A component without
/// positions sits at the layout's cursor.
pub fn lay_out(
    bed: &Bed,
    meshes: &[&[Point3<f64>]],
    rotations: &[Rotation3<f64>],
) -> Vec<Isometry3<f64>> {
    let mut placed = Vec::with_capacity(meshes.len());
    let mut cursor = 0.0;
    for (points, rotation) in meshes.iter().zip(rotations) {
        let (low, high) = bounds(points, rotation);
        let shift = Vector3::new(cursor - low.x, -(low.y + high.y) / 2.0, -low.z);
        cursor += high.x - low.x + bed.gap;
        placed.push((*rotation, shift));
    }
    let width = (cursor - bed.gap).max(0.0);
    let centre = Vector3::new(bed.centre[0] - width / 2.0, bed.centre[1], 0.0);
    placed
        .into_iter()
        .map(|(rotation, shift)| {
            Isometry3::from_parts(
                Translation3::from(shift + centre),
                UnitQuaternion::from_rotation_matrix(&rotation),
            )
        })
        .collect()
}

/// The bounding box of `points` turned by `rotation`; the origin twice when there are none.
fn bounds(points: &[Point3<f64>], rotation: &Rotation3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let mut turned = points.iter().map(|p| (rotation * p).coords);
    let Some(first) = turned.next() else {
        return (Vector3::zeros(), Vector3::zeros());
    };
    turned.fold((first, first), |(low, high), p| (low.inf(&p), high.sup(&p)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_cubes_side_by_side_on_the_bed_centre() {
        let cube: Vec<Point3<f64>> = (0..8)
            .map(|i| {
                Point3::new(
                    f64::from(i & 1) * 10.0,
                    f64::from((i >> 1) & 1) * 10.0,
                    f64::from((i >> 2) & 1) * 10.0 + 5.0,
                )
            })
            .collect();
        let bed = Bed {
            centre: [125.0, 105.0],
            gap: 10.0,
        };
        let placed = lay_out(&bed, &[&cube, &cube], &[Rotation3::identity(); 2]);
        let low = |t: &Isometry3<f64>| {
            cube.iter()
                .map(|p| t * p)
                .fold(Point3::new(f64::MAX, f64::MAX, f64::MAX), |a, p| a.inf(&p))
        };
        let (a, b) = (low(&placed[0]), low(&placed[1]));
        // Width 10 + 10 + 10 = 30, centred on 125: from 110 to 140.
        assert!((a - Point3::new(110.0, 100.0, 0.0)).norm() < 1e-12, "{a}");
        assert!((b - Point3::new(130.0, 100.0, 0.0)).norm() < 1e-12, "{b}");
    }
}
