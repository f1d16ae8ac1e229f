//! Exact distances between points, segments and triangles, and to a mesh surface.

use nalgebra::{Point3, Vector3};

use super::mesh::TriMesh;

/// Distance from `p` to the segment `a`–`b` (a point when `a == b`).
pub(crate) fn point_segment_distance(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).norm()
}

/// Closest point of the triangle to `p` (Ericson, "Real-Time Collision Detection" §5.1.5),
/// or `None` when the triangle has zero area.
fn closest_point_on_triangle(p: &Point3<f64>, tri: &[Point3<f64>; 3]) -> Option<Point3<f64>> {
    let [a, b, c] = tri;
    let (ab, ac) = (b - a, c - a);
    if ab.cross(&ac).norm_squared() == 0.0 {
        return None;
    }
    let ap = p - a;
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return Some(*a);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return Some(*b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return Some(a + ab * (d1 / (d1 - d3)));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return Some(*c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return Some(a + ac * (d2 / (d2 - d6)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return Some(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    }
    let denom = 1.0 / (va + vb + vc);
    Some(a + ab * (vb * denom) + ac * (vc * denom))
}

/// Distance from `p` to the triangle `tri` (its interior, edges and corners). Exact up to
/// rounding in every Voronoi region; a zero-area triangle is treated as its edges.
pub fn point_triangle_distance(p: &Point3<f64>, tri: &[Point3<f64>; 3]) -> f64 {
    match closest_point_on_triangle(p, tri) {
        Some(q) if q.iter().all(|c| c.is_finite()) => (q - p).norm(),
        _ => edges(tri)
            .iter()
            .map(|(u, v)| point_segment_distance(p, u, v))
            .fold(f64::INFINITY, f64::min),
    }
}

fn edges(tri: &[Point3<f64>; 3]) -> [(Point3<f64>, Point3<f64>); 3] {
    [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])]
}

/// Distance between the segments `a0`–`a1` and `b0`–`b1`. Robust for parallel, collinear and
/// zero-length segments: the minimum over the four endpoint-to-segment distances and, when the
/// lines are not parallel and their closest points fall inside both segments, the line-to-line
/// distance.
pub fn segment_segment_distance(
    a0: &Point3<f64>,
    a1: &Point3<f64>,
    b0: &Point3<f64>,
    b1: &Point3<f64>,
) -> f64 {
    let mut best = point_segment_distance(a0, b0, b1)
        .min(point_segment_distance(a1, b0, b1))
        .min(point_segment_distance(b0, a0, a1))
        .min(point_segment_distance(b1, a0, a1));
    let (d1, d2, r) = (a1 - a0, b1 - b0, a0 - b0);
    let (a, e, b) = (d1.norm_squared(), d2.norm_squared(), d1.dot(&d2));
    let denom = a * e - b * b;
    // Not parallel (relative to the lengths): the interior critical point.
    if denom > 1e-14 * a * e {
        let (c, f) = (d1.dot(&r), d2.dot(&r));
        let s = (b * f - c * e) / denom;
        let t = (a * f - b * c) / denom;
        if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
            best = best.min(((a0 + d1 * s) - (b0 + d2 * t)).norm());
        }
    }
    best
}

/// Whether the segment `a`–`b` passes through the triangle (not counting a segment that lies
/// in the triangle's plane; such contacts are found through the edges).
fn segment_crosses_triangle(a: &Point3<f64>, b: &Point3<f64>, tri: &[Point3<f64>; 3]) -> bool {
    let [v0, v1, v2] = tri;
    let n = (v1 - v0).cross(&(v2 - v0));
    let (da, db) = (n.dot(&(a - v0)), n.dot(&(b - v0)));
    if (da > 0.0 && db > 0.0) || (da < 0.0 && db < 0.0) || (da == 0.0 && db == 0.0) {
        return false;
    }
    let q = a + (b - a) * (da / (da - db));
    let inside = |u: &Point3<f64>, v: &Point3<f64>| (v - u).cross(&(q - u)).dot(&n) >= 0.0;
    inside(v0, v1) && inside(v1, v2) && inside(v2, v0)
}

/// Distance from the segment `a`–`b` to the triangle `tri`; 0 when the segment crosses or
/// touches the triangle.
pub fn segment_triangle_distance(a: &Point3<f64>, b: &Point3<f64>, tri: &[Point3<f64>; 3]) -> f64 {
    if segment_crosses_triangle(a, b, tri) {
        return 0.0;
    }
    // Otherwise the closest pair involves a segment endpoint or a triangle edge.
    edges(tri)
        .iter()
        .map(|(u, v)| segment_segment_distance(a, b, u, v))
        .fold(
            point_triangle_distance(a, tri).min(point_triangle_distance(b, tri)),
            f64::min,
        )
}

/// Unsigned distance from `p` to the surface of `mesh` (`+∞` for a mesh without triangles).
///
/// Exact (the minimum over all triangles); triangles whose bounding box is farther than the
/// best distance so far are skipped.
///
/// # Panics
/// If a triangle has an index out of range.
pub fn distance_to_point(mesh: &TriMesh, p: &Point3<f64>) -> f64 {
    min_over_triangles(
        mesh,
        |[a, b, c]| {
            let lo = a.inf(b).inf(c);
            let hi = a.sup(b).sup(c);
            let gap = (lo - p).sup(&(p - hi)).sup(&Vector3::zeros());
            gap.norm()
        },
        |tri| point_triangle_distance(p, tri),
    )
}

/// Distance from the segment `a`–`b` to the surface of `mesh`: 0 when the segment crosses the
/// surface (`+∞` for a mesh without triangles).
///
/// Exact (the minimum over all triangles); triangles whose bounding sphere is farther than the
/// best distance so far are skipped.
///
/// # Panics
/// If a triangle has an index out of range.
pub fn distance_to_segment(mesh: &TriMesh, a: &Point3<f64>, b: &Point3<f64>) -> f64 {
    min_over_triangles(
        mesh,
        |tri| {
            let centre = Point3::from((tri[0].coords + tri[1].coords + tri[2].coords) / 3.0);
            let radius = tri.iter().map(|v| (v - centre).norm()).fold(0.0, f64::max);
            point_segment_distance(&centre, a, b) - radius
        },
        |tri| segment_triangle_distance(a, b, tri),
    )
}

/// The minimum of `exact` over the triangles, skipping any whose `lower_bound` (never more
/// than `exact`) cannot beat the best so far. The triangle with the smallest bound goes first.
fn min_over_triangles(
    mesh: &TriMesh,
    lower_bound: impl Fn(&[Point3<f64>; 3]) -> f64,
    exact: impl Fn(&[Point3<f64>; 3]) -> f64,
) -> f64 {
    let bounds: Vec<f64> = (0..mesh.triangles.len())
        .map(|i| lower_bound(&mesh.triangle(i)))
        .collect();
    let Some(first) = (0..bounds.len()).min_by(|&i, &j| bounds[i].total_cmp(&bounds[j])) else {
        return f64::INFINITY;
    };
    let mut best = exact(&mesh.triangle(first));
    for (i, &bound) in bounds.iter().enumerate() {
        if bound < best && i != first {
            best = best.min(exact(&mesh.triangle(i)));
            if best == 0.0 {
                break;
            }
        }
    }
    best
}
