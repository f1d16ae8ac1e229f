//! Generalized winding number: inside/outside that tolerates small holes.

use std::f64::consts::PI;

use nalgebra::Point3;

use super::mesh::TriMesh;

/// Generalized winding number of `mesh` at `p` (Jacobson, Kavan, Sorkine-Hornung 2013):
/// the sum of the signed solid angles the triangles subtend at `p`, divided by 4π.
///
/// For a closed, outward-oriented mesh it is 1 inside and 0 outside (−1 inside an inverted
/// mesh); near a small hole it varies smoothly, so `> 0.5` is a robust "inside" test.
/// Each solid angle uses the Van Oosterom–Strackee formula with `atan2`. A point exactly on the
/// surface gets the fraction of a small ball around it that is inside (0.5 on a flat face,
/// 0.25 on a right-angled convex edge): a triangle whose plane contains `p` contributes nothing.
///
/// # Panics
/// If a triangle has an index out of range.
pub fn winding_number(mesh: &TriMesh, p: &Point3<f64>) -> f64 {
    let total: f64 = (0..mesh.triangles.len())
        .map(|i| solid_angle(&mesh.triangle(i), p))
        .sum();
    total / (4.0 * PI)
}

/// Signed solid angle of triangle `tri` seen from `p`: positive when `p` is on the side the
/// counter-clockwise normal points away from (the inside of a closed, outward-oriented mesh).
pub(crate) fn solid_angle(tri: &[Point3<f64>; 3], p: &Point3<f64>) -> f64 {
    let (a, b, c) = (tri[0] - p, tri[1] - p, tri[2] - p);
    let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
    let numerator = a.dot(&b.cross(&c));
    if numerator == 0.0 {
        // `p` is in the triangle's plane: the solid angle is 0, or ±2π across the triangle;
        // take the mean of the two sides.
        return 0.0;
    }
    let denominator = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
    2.0 * numerator.atan2(denominator)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octant_triangle_subtends_an_eighth_of_the_sphere() {
        let tri = [
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 1.0),
        ];
        let omega = solid_angle(&tri, &Point3::origin());
        assert!((omega - 4.0 * PI / 8.0).abs() < 1e-14, "{omega}");
        let flipped = [tri[0], tri[2], tri[1]];
        assert!((solid_angle(&flipped, &Point3::origin()) + omega).abs() < 1e-14);
    }

    #[test]
    fn point_at_a_vertex_gives_a_finite_value() {
        let tri = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ];
        assert!(solid_angle(&tri, &Point3::origin()).is_finite());
    }
}
