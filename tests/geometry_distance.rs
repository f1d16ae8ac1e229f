//! Point, segment and triangle distances, and distances to a mesh.

mod geometry_support;

use std::time::Instant;

use ballast::geometry::{
    distance_to_point, distance_to_segment, load_mesh, point_triangle_distance,
    segment_segment_distance, segment_triangle_distance, MeshSelector, TriMesh,
};
use geometry_support::{icosphere, shared_mesh, unit_cube};
use nalgebra::Point3;

fn p(x: f64, y: f64, z: f64) -> Point3<f64> {
    Point3::new(x, y, z)
}

fn assert_close(actual: f64, expected: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= 1e-12 * expected.max(1.0),
        "{what}: {actual} vs {expected}"
    );
}

/// A small deterministic generator (xorshift), mapped to [-2, 2].
struct Noise(u64);
impl Noise {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
    }
    fn point(&mut self) -> Point3<f64> {
        p(self.next(), self.next(), self.next())
    }
}

const TRI: [Point3<f64>; 3] = [
    Point3::new(0.0, 0.0, 0.0),
    Point3::new(1.0, 0.0, 0.0),
    Point3::new(0.0, 1.0, 0.0),
];

#[test]
fn point_triangle_in_each_voronoi_region() {
    let cases = [
        ("face, above", p(0.2, 0.3, 0.7), 0.7),
        ("face, below", p(0.25, 0.25, -2.0), 2.0),
        ("face, in plane", p(0.1, 0.1, 0.0), 0.0),
        ("vertex A", p(-1.0, -1.0, 0.5), (2.25f64).sqrt()),
        ("vertex B", p(2.0, -1.0, 0.0), 2f64.sqrt()),
        ("vertex C", p(-1.0, 2.0, 1.0), 3f64.sqrt()),
        ("edge AB", p(0.5, -2.0, 1.0), 5f64.sqrt()),
        ("edge AC", p(-3.0, 0.5, 0.0), 3.0),
        ("edge BC", p(1.0, 1.0, 2.0), (0.5f64 + 4.0).sqrt()),
        ("edge BC, in plane", p(1.0, 1.0, 0.0), 0.5f64.sqrt()),
    ];
    for (region, q, expected) in cases {
        assert_close(point_triangle_distance(&q, &TRI), expected, region);
        // The same for any vertex order.
        let rotated = [TRI[1], TRI[2], TRI[0]];
        let flipped = [TRI[0], TRI[2], TRI[1]];
        assert_close(point_triangle_distance(&q, &rotated), expected, region);
        assert_close(point_triangle_distance(&q, &flipped), expected, region);
    }
}

#[test]
fn point_to_degenerate_triangles() {
    let collinear = [p(0.0, 0.0, 0.0), p(2.0, 0.0, 0.0), p(1.0, 0.0, 0.0)];
    assert_close(
        point_triangle_distance(&p(1.5, 3.0, 4.0), &collinear),
        5.0,
        "collinear",
    );
    assert_close(
        point_triangle_distance(&p(4.0, 0.0, 0.0), &collinear),
        2.0,
        "collinear end",
    );
    let point = [p(1.0, 1.0, 1.0); 3];
    assert_close(
        point_triangle_distance(&p(1.0, 4.0, 5.0), &point),
        5.0,
        "single point",
    );
}

#[test]
fn segment_segment_cases() {
    let x0 = p(0.0, 0.0, 0.0);
    let x1 = p(1.0, 0.0, 0.0);
    let cases = [
        ("skew, interior", p(0.5, -1.0, 2.0), p(0.5, 1.0, 2.0), 2.0),
        (
            "skew, endpoint",
            p(2.0, -1.0, 1.0),
            p(2.0, 1.0, 1.0),
            2f64.sqrt(),
        ),
        ("intersecting", p(0.5, -1.0, 0.0), p(0.5, 1.0, 0.0), 0.0),
        (
            "touching at an end",
            p(1.0, 0.0, 0.0),
            p(1.0, 5.0, 0.0),
            0.0,
        ),
        (
            "parallel, overlapping",
            p(0.5, 1.0, 0.0),
            p(1.5, 1.0, 0.0),
            1.0,
        ),
        (
            "parallel, reversed",
            p(1.5, 0.0, 3.0),
            p(-0.5, 0.0, 3.0),
            3.0,
        ),
        (
            "parallel, apart",
            p(2.0, 1.0, 0.0),
            p(3.0, 1.0, 0.0),
            2f64.sqrt(),
        ),
        ("collinear, apart", p(3.0, 0.0, 0.0), p(4.0, 0.0, 0.0), 2.0),
        (
            "collinear, overlapping",
            p(0.5, 0.0, 0.0),
            p(4.0, 0.0, 0.0),
            0.0,
        ),
        ("point vs segment", p(0.5, 1.0, 0.0), p(0.5, 1.0, 0.0), 1.0),
        (
            "point past the end",
            p(-3.0, 4.0, 0.0),
            p(-3.0, 4.0, 0.0),
            5.0,
        ),
    ];
    for (case, y0, y1, expected) in cases {
        assert_close(segment_segment_distance(&x0, &x1, &y0, &y1), expected, case);
        assert_close(segment_segment_distance(&y0, &y1, &x0, &x1), expected, case);
        assert_close(segment_segment_distance(&x1, &x0, &y1, &y0), expected, case);
    }
    let a = p(1.0, 2.0, 3.0);
    let b = p(1.0, 2.0, 7.0);
    assert_close(segment_segment_distance(&a, &a, &b, &b), 4.0, "two points");
    // Nearly parallel, with the lines' closest points far outside both segments.
    let d = segment_segment_distance(&x0, &x1, &p(0.0, 1.0, 0.0), &p(1.0, 1.0 + 1e-9, 0.0));
    assert_close(d, 1.0, "nearly parallel");
}

/// Minimum distance over a dense sampling of the first segment to the second: an upper bound
/// that the exact result must not exceed, and must come close to.
fn sampled_segment_segment(
    a0: &Point3<f64>,
    a1: &Point3<f64>,
    b0: &Point3<f64>,
    b1: &Point3<f64>,
) -> f64 {
    let n = 400;
    (0..=n)
        .map(|i| {
            let s = f64::from(i) / f64::from(n);
            let q = a0 + (a1 - a0) * s;
            (0..=n)
                .map(|j| {
                    let t = f64::from(j) / f64::from(n);
                    (q - (b0 + (b1 - b0) * t)).norm()
                })
                .fold(f64::INFINITY, f64::min)
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn segment_segment_matches_sampling() {
    let mut noise = Noise(0x9e37_79b9_7f4a_7c15);
    for _ in 0..40 {
        let (a0, a1, b0, b1) = (noise.point(), noise.point(), noise.point(), noise.point());
        let exact = segment_segment_distance(&a0, &a1, &b0, &b1);
        let sampled = sampled_segment_segment(&a0, &a1, &b0, &b1);
        assert!(exact <= sampled + 1e-12, "{exact} > {sampled}");
        // Sampling step ≤ 4·√3/400 per segment.
        assert!(sampled - exact < 0.04, "{exact} vs {sampled}");
    }
}

#[test]
fn segment_triangle_cases() {
    let cases = [
        (
            "crossing the face",
            p(0.2, 0.2, -1.0),
            p(0.2, 0.2, 1.0),
            0.0,
        ),
        (
            "ending on the face",
            p(0.2, 0.2, 1.0),
            p(0.2, 0.2, 0.0),
            0.0,
        ),
        (
            "crossing the plane outside",
            p(2.0, 2.0, -1.0),
            p(2.0, 2.0, 1.0),
            4.5f64.sqrt(),
        ),
        ("parallel above", p(0.1, 0.1, 0.5), p(0.3, 0.2, 0.5), 0.5),
        (
            "in plane, through edge",
            p(-1.0, 0.3, 0.0),
            p(2.0, 0.3, 0.0),
            0.0,
        ),
        (
            "in plane, outside",
            p(-1.0, -1.0, 0.0),
            p(2.0, -1.0, 0.0),
            1.0,
        ),
        (
            "skew to an edge",
            p(0.5, -1.0, -1.0),
            p(0.5, -1.0, 1.0),
            1.0,
        ),
        (
            "above, over an edge",
            p(-1.0, 0.5, 2.0),
            p(2.0, 0.5, 2.0),
            2.0,
        ),
        (
            "degenerate segment",
            p(0.2, 0.2, 3.0),
            p(0.2, 0.2, 3.0),
            3.0,
        ),
    ];
    for (case, a, b, expected) in cases {
        assert_close(segment_triangle_distance(&a, &b, &TRI), expected, case);
        assert_close(segment_triangle_distance(&b, &a, &TRI), expected, case);
    }
}

#[test]
fn segment_triangle_matches_sampling() {
    let mut noise = Noise(0x0123_4567_89ab_cdef);
    for _ in 0..30 {
        let tri = [noise.point(), noise.point(), noise.point()];
        let (a, b) = (noise.point(), noise.point());
        let exact = segment_triangle_distance(&a, &b, &tri);
        let n = 300;
        let sampled = (0..=n)
            .map(|i| point_triangle_distance(&(a + (b - a) * (f64::from(i) / f64::from(n))), &tri))
            .fold(f64::INFINITY, f64::min);
        assert!(exact <= sampled + 1e-12, "{exact} > {sampled}");
        assert!(sampled - exact < 0.03, "{exact} vs {sampled}");
    }
}

#[test]
fn segments_and_points_against_a_cube() {
    let cube = unit_cube();
    assert_eq!(
        distance_to_segment(&cube, &p(-1.0, 0.5, 0.5), &p(2.0, 0.4, 0.6)),
        0.0
    );
    assert_eq!(
        distance_to_segment(&cube, &p(0.5, 0.5, 0.5), &p(0.5, 0.5, 7.0)),
        0.0
    );
    // Inside, parallel to the face z = 0 at height 0.1; other faces are farther.
    assert_close(
        distance_to_segment(&cube, &p(0.3, 0.4, 0.1), &p(0.7, 0.6, 0.1)),
        0.1,
        "gap",
    );
    // Outside, parallel to the face x = 1.
    assert_close(
        distance_to_segment(&cube, &p(1.25, 0.2, 0.2), &p(1.25, 0.8, 0.9)),
        0.25,
        "outside gap",
    );
    assert_close(distance_to_point(&cube, &p(0.5, 0.5, 0.5)), 0.5, "centre");
    assert_close(distance_to_point(&cube, &p(0.5, 0.2, 0.6)), 0.2, "inside");
    assert_close(
        distance_to_point(&cube, &p(2.0, 2.0, 2.0)),
        3f64.sqrt(),
        "corner",
    );
    assert_close(distance_to_point(&cube, &p(0.5, -3.0, 0.5)), 3.0, "face");
    let empty = TriMesh {
        positions: vec![],
        triangles: vec![],
    };
    assert_eq!(distance_to_point(&empty, &Point3::origin()), f64::INFINITY);
}

/// The minimum over all triangles, without any skipping.
fn brute_point(mesh: &TriMesh, q: &Point3<f64>) -> f64 {
    (0..mesh.triangles.len())
        .map(|i| point_triangle_distance(q, &mesh.triangle(i)))
        .fold(f64::INFINITY, f64::min)
}

fn brute_segment(mesh: &TriMesh, a: &Point3<f64>, b: &Point3<f64>) -> f64 {
    (0..mesh.triangles.len())
        .map(|i| segment_triangle_distance(a, b, &mesh.triangle(i)))
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn skipping_triangles_does_not_change_the_result() {
    let sphere = icosphere(4, 1.0, p(0.1, 0.2, 0.3));
    let mut noise = Noise(0xdead_beef_cafe_f00d);
    for _ in 0..20 {
        let q = noise.point();
        assert_eq!(distance_to_point(&sphere, &q), brute_point(&sphere, &q));
        let (a, b) = (noise.point() * 0.3, noise.point() * 0.3);
        assert_eq!(
            distance_to_segment(&sphere, &a, &b),
            brute_segment(&sphere, &a, &b)
        );
    }
}

#[test]
fn large_mesh_queries_are_fast_and_exact() {
    let Some(path) = shared_mesh("large/hammer_240k.obj") else {
        return;
    };
    let mesh = load_mesh(&path, &MeshSelector::Whole).unwrap();
    assert!(mesh.triangles.len() > 200_000);
    let queries = [
        (p(0.0, 0.0, 0.0), p(0.0, 0.0, 2.0)),
        (p(0.3, 0.05, -3.5), p(-0.3, 0.0, -3.0)),
        (p(2.0, 1.0, 5.0), p(3.0, 1.0, 5.0)),
    ];
    for (a, b) in queries {
        let start = Instant::now();
        let d_seg = distance_to_segment(&mesh, &a, &b);
        let d_pt = distance_to_point(&mesh, &a);
        let elapsed = start.elapsed();
        eprintln!("segment {d_seg}, point {d_pt}: {elapsed:?} for both queries");
        if !cfg!(debug_assertions) {
            assert!(elapsed.as_secs_f64() < 0.5, "{elapsed:?}");
        }
        assert_eq!(d_seg, brute_segment(&mesh, &a, &b));
        assert_eq!(d_pt, brute_point(&mesh, &a));
    }
}
