//! Tessellations of the shapes the glTF writer draws besides the components themselves:
//! capsules, balls, markers and arrows.
//!
//! Triangles are counter-clockwise seen from outside. No triangle is degenerate, so viewers and
//! validators see clean meshes.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Point3, UnitQuaternion, Vector3};

/// Segments around the axis of a sphere or capsule drawn for display.
const SEGMENTS: u32 = 32;
/// Latitude bands from pole to equator of a sphere or capsule end drawn for display (a quarter
/// of the segments: the faces are as long as they are wide).
const HALF_RINGS: u32 = SEGMENTS / 4;
/// Below this axis length (relative to the radius) a capsule is drawn as a sphere.
const MIN_AXIS_FRACTION: f64 = 1e-9;

/// A triangle mesh with optional per-vertex normals (empty when flat shading is wanted).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ShapeMesh {
    pub positions: Vec<Point3<f64>>,
    pub normals: Vec<Vector3<f64>>,
    pub triangles: Vec<[u32; 3]>,
}

/// A sphere of radius 1 about the origin, smooth normals.
pub(crate) fn unit_sphere() -> ShapeMesh {
    revolve(&sphere_latitudes(HALF_RINGS), 1.0, SEGMENTS)
}

/// The latitudes of a sphere with `half_rings` bands from each pole to the equator, for
/// [`revolve`].
fn sphere_latitudes(half_rings: u32) -> Vec<(f64, f64)> {
    let rings = 2 * half_rings;
    (1..rings)
        .map(|i| (PI * f64::from(i) / f64::from(rings), 0.0))
        .collect()
}

/// A capsule around the segment `from`-`to` with the given radius, drawn for display: a
/// cylinder capped by two hemispheres, positions baked in the frame of `from` and `to`, smooth
/// normals.
pub(crate) fn capsule(from: &Point3<f64>, to: &Point3<f64>, radius: f64) -> ShapeMesh {
    capsule_of(from, to, radius, SEGMENTS)
}

/// [`capsule`] tessellated finely enough that its surface lies within `tolerance` of the true
/// one everywhere (its vertices on it, its faces at most `tolerance` inside): the void a slicer
/// prints, which the mass model weighs as the true capsule. Never coarser than [`capsule`].
pub(crate) fn capsule_within(
    from: &Point3<f64>,
    to: &Point3<f64>,
    radius: f64,
    tolerance: f64,
) -> ShapeMesh {
    capsule_of(from, to, radius, segments_within(radius, tolerance))
}

/// The fewest segments (a multiple of 4, at least [`SEGMENTS`]) for which a capsule of `radius`
/// tessellated by [`capsule_of`] lies within `tolerance` of the true surface. A face of the ends
/// spans the angle 2π/n along both its edges, so its centre lies `r(1 − cos²(π/n))` inside;
/// the cylinder's faces lie `r(1 − cos(π/n))` inside, less.
fn segments_within(radius: f64, tolerance: f64) -> u32 {
    let radius = radius.abs();
    // A tolerance of nothing (or not a number) asks for the finest mesh; one past the radius
    // for none finer than the display's.
    if radius <= tolerance || radius.is_nan() {
        return SEGMENTS;
    }
    let tolerance = if tolerance > 0.0 { tolerance } else { 0.0 };
    // cos²(π/n) ≥ 1 − tolerance/r.
    let half_angle = (1.0 - tolerance / radius).sqrt().acos();
    let needed = (PI / half_angle).ceil();
    // Beyond a thousand the tolerance is below what a slicer resolves; the cap keeps the
    // mesh bounded for a tolerance of nothing.
    let needed = needed.min(1024.0) as u32;
    needed.div_ceil(4).max(SEGMENTS / 4) * 4
}

/// A capsule of `segments` around its axis (a multiple of 4), `segments / 4` latitude bands from
/// each pole to the equator.
fn capsule_of(from: &Point3<f64>, to: &Point3<f64>, radius: f64, segments: u32) -> ShapeMesh {
    let half_rings = segments / 4;
    let axis = to - from;
    let length = axis.norm();
    let canonical = if length <= radius.abs() * MIN_AXIS_FRACTION {
        revolve(&sphere_latitudes(half_rings), radius, segments)
    } else {
        // Along +Z: the `to` hemisphere on top at z = length, the `from` hemisphere below at z = 0.
        let top =
            (1..=half_rings).map(|i| (FRAC_PI_2 * f64::from(i) / f64::from(half_rings), length));
        let bottom = (0..half_rings).map(|i| {
            (
                FRAC_PI_2 + FRAC_PI_2 * f64::from(i) / f64::from(half_rings),
                0.0,
            )
        });
        let latitudes: Vec<(f64, f64)> = top.chain(bottom).collect();
        revolve(&latitudes, radius, segments)
    };
    let rotation = rotation_from_z(&axis);
    ShapeMesh {
        positions: canonical
            .positions
            .iter()
            .map(|p| from + rotation * p.coords)
            .collect(),
        normals: canonical.normals.iter().map(|n| rotation * n).collect(),
        triangles: canonical.triangles,
    }
}

/// A regular octahedron of circumradius 1 about the origin, flat shaded (no normals).
pub(crate) fn unit_octahedron() -> ShapeMesh {
    let positions = vec![
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(-1.0, 0.0, 0.0),
        Point3::new(0.0, 1.0, 0.0),
        Point3::new(0.0, -1.0, 0.0),
        Point3::new(0.0, 0.0, 1.0),
        Point3::new(0.0, 0.0, -1.0),
    ];
    let triangles = vec![
        [4, 0, 2],
        [4, 2, 1],
        [4, 1, 3],
        [4, 3, 0],
        [5, 2, 0],
        [5, 1, 2],
        [5, 3, 1],
        [5, 0, 3],
    ];
    ShapeMesh {
        positions,
        normals: Vec::new(),
        triangles,
    }
}

/// Segments around a thin tube (arrow shaft, string, support polygon edge).
const TUBE_SEGMENTS: u32 = 12;
/// Radius of an arrow's shaft, as a fraction of its length.
const ARROW_SHAFT: f64 = 0.015;
/// Radius and length of an arrow's head, as fractions of its length.
const ARROW_HEAD_RADIUS: f64 = 0.05;
const ARROW_HEAD_LENGTH: f64 = 0.15;

/// A thin solid arrow of length 1 from the origin along `direction`: a shaft and a conical head,
/// flat shaded (no normals), so every renderer draws it (line primitives are not always drawn).
pub(crate) fn unit_arrow(direction: &Vector3<f64>) -> ShapeMesh {
    let d = direction.normalize();
    let neck = Point3::from(d * (1.0 - ARROW_HEAD_LENGTH));
    let mut mesh = tube(&Point3::origin(), &neck, ARROW_SHAFT);
    append(&mut mesh, cone(&neck, &Point3::from(d), ARROW_HEAD_RADIUS));
    mesh
}

/// A thin tube of length 1 from the origin along `direction`, its radius `radius`.
pub(crate) fn unit_line(direction: &Vector3<f64>, radius: f64) -> ShapeMesh {
    tube(
        &Point3::origin(),
        &Point3::from(direction.normalize()),
        radius,
    )
}

/// Thin tubes of radius `radius` along the edges of the closed polygon `points` (one tube for two
/// points, none for fewer).
pub(crate) fn polygon_tubes(points: &[Point3<f64>], radius: f64) -> ShapeMesh {
    let mut mesh = ShapeMesh {
        positions: Vec::new(),
        normals: Vec::new(),
        triangles: Vec::new(),
    };
    let edges = match points.len() {
        0 | 1 => 0,
        2 => 1,
        n => n,
    };
    for i in 0..edges {
        let (a, b) = (points[i], points[(i + 1) % points.len()]);
        if (b - a).norm() > 0.0 {
            append(&mut mesh, tube(&a, &b, radius));
        }
    }
    mesh
}

/// A closed cylinder around the segment `from`-`to`, flat shaded.
fn tube(from: &Point3<f64>, to: &Point3<f64>, radius: f64) -> ShapeMesh {
    let axis = to - from;
    let rotation = rotation_from_z(&axis);
    let length = axis.norm();
    let ring = |z: f64| {
        (0..TUBE_SEGMENTS).map(move |j| {
            let phi = 2.0 * PI * f64::from(j) / f64::from(TUBE_SEGMENTS);
            Vector3::new(radius * phi.cos(), radius * phi.sin(), z)
        })
    };
    // Bottom centre, bottom ring, top ring, top centre.
    let local: Vec<Vector3<f64>> = std::iter::once(Vector3::zeros())
        .chain(ring(0.0))
        .chain(ring(length))
        .chain(std::iter::once(Vector3::new(0.0, 0.0, length)))
        .collect();
    let n = TUBE_SEGMENTS;
    let top_centre = 2 * n + 1;
    let mut triangles = Vec::new();
    for j in 0..n {
        let (b0, b1) = (1 + j, 1 + (j + 1) % n);
        let (t0, t1) = (b0 + n, b1 + n);
        triangles.push([0, b1, b0]);
        triangles.push([b0, b1, t1]);
        triangles.push([b0, t1, t0]);
        triangles.push([top_centre, t0, t1]);
    }
    ShapeMesh {
        positions: local.iter().map(|v| from + rotation * v).collect(),
        normals: Vec::new(),
        triangles,
    }
}

/// A closed cone with its base of radius `radius` at `base` and its apex at `apex`, flat shaded.
fn cone(base: &Point3<f64>, apex: &Point3<f64>, radius: f64) -> ShapeMesh {
    let axis = apex - base;
    let rotation = rotation_from_z(&axis);
    let length = axis.norm();
    let local: Vec<Vector3<f64>> = std::iter::once(Vector3::zeros())
        .chain((0..TUBE_SEGMENTS).map(|j| {
            let phi = 2.0 * PI * f64::from(j) / f64::from(TUBE_SEGMENTS);
            Vector3::new(radius * phi.cos(), radius * phi.sin(), 0.0)
        }))
        .chain(std::iter::once(Vector3::new(0.0, 0.0, length)))
        .collect();
    let n = TUBE_SEGMENTS;
    let tip = n + 1;
    let mut triangles = Vec::new();
    for j in 0..n {
        let (b0, b1) = (1 + j, 1 + (j + 1) % n);
        triangles.push([0, b1, b0]);
        triangles.push([b0, b1, tip]);
    }
    ShapeMesh {
        positions: local.iter().map(|v| base + rotation * v).collect(),
        normals: Vec::new(),
        triangles,
    }
}

/// Adds `other`'s vertices and triangles to `mesh` (flat shaded meshes only).
fn append(mesh: &mut ShapeMesh, other: ShapeMesh) {
    let offset = u32::try_from(mesh.positions.len()).expect("small shapes");
    mesh.positions.extend(other.positions);
    mesh.triangles
        .extend(other.triangles.iter().map(|t| t.map(|i| i + offset)));
}

/// The rotation taking +Z onto `axis` (identity for a zero axis).
fn rotation_from_z(axis: &Vector3<f64>) -> UnitQuaternion<f64> {
    if axis.norm() == 0.0 {
        return UnitQuaternion::identity();
    }
    UnitQuaternion::rotation_between(&Vector3::z(), axis).unwrap_or_else(|| {
        // Antiparallel: half a turn about any perpendicular axis.
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI)
    })
}

/// A surface of revolution about +Z: a pole on top, one ring of `segments` vertices per
/// latitude `(polar angle, z offset)` in order from top to bottom, and a pole at the bottom.
/// Each vertex sits at `radius * direction + offset`, its normal is `direction`.
fn revolve(latitudes: &[(f64, f64)], radius: f64, segments: u32) -> ShapeMesh {
    let first_offset = latitudes.first().map_or(0.0, |l| l.1);
    let last_offset = latitudes.last().map_or(0.0, |l| l.1);
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut push = |direction: Vector3<f64>, offset: f64| {
        positions.push(Point3::from(direction * radius + Vector3::z() * offset));
        normals.push(direction);
    };

    push(Vector3::z(), first_offset);
    for &(theta, offset) in latitudes {
        for j in 0..segments {
            let phi = 2.0 * PI * f64::from(j) / f64::from(segments);
            let (s, c) = theta.sin_cos();
            push(Vector3::new(s * phi.cos(), s * phi.sin(), c), offset);
        }
    }
    push(-Vector3::z(), last_offset);

    let ring = |k: u32, j: u32| 1 + k * segments + j % segments;
    let rings = u32::try_from(latitudes.len()).expect("few latitudes");
    let bottom_pole = 1 + rings * segments;
    let mut triangles = Vec::new();
    for j in 0..segments {
        triangles.push([0, ring(0, j), ring(0, j + 1)]);
    }
    for k in 0..rings.saturating_sub(1) {
        for j in 0..segments {
            let (a, b) = (ring(k, j), ring(k, j + 1));
            let (c, d) = (ring(k + 1, j), ring(k + 1, j + 1));
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
    }
    for j in 0..segments {
        triangles.push([bottom_pole, ring(rings - 1, j + 1), ring(rings - 1, j)]);
    }
    ShapeMesh {
        positions,
        normals,
        triangles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Signed volume by the divergence theorem: positive when triangles face outward.
    fn volume(mesh: &ShapeMesh) -> f64 {
        mesh.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize].coords);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum()
    }

    fn min_triangle_area(mesh: &ShapeMesh) -> f64 {
        mesh.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                (b - a).cross(&(c - a)).norm() / 2.0
            })
            .fold(f64::INFINITY, f64::min)
    }

    fn assert_closed(mesh: &ShapeMesh) {
        // Every directed edge appears once and its reverse once: closed and consistently wound.
        let mut edges = std::collections::BTreeMap::new();
        for t in &mesh.triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1, "edge {a}-{b} used {n} times");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}-{b} has no twin");
        }
    }

    #[test]
    fn sphere_is_closed_outward_and_close_to_the_true_volume() {
        let sphere = unit_sphere();
        assert_closed(&sphere);
        let v = volume(&sphere);
        let exact = 4.0 / 3.0 * PI;
        assert!(v > 0.95 * exact && v < exact, "volume {v}");
        assert!(min_triangle_area(&sphere) > 1e-4);
        for (p, n) in sphere.positions.iter().zip(&sphere.normals) {
            assert!((p.coords.norm() - 1.0).abs() < 1e-12);
            assert!((p.coords - n).norm() < 1e-12);
        }
    }

    #[test]
    fn capsule_spans_its_segment_and_faces_outward() {
        let from = Point3::new(1.0, 2.0, 3.0);
        let to = Point3::new(1.0, 12.0, 3.0);
        let r = 2.0;
        let mesh = capsule(&from, &to, r);
        assert_closed(&mesh);
        let exact = PI * r * r * 10.0 + 4.0 / 3.0 * PI * r.powi(3);
        let v = volume(&mesh);
        assert!(v > 0.95 * exact && v < exact, "volume {v} vs {exact}");
        assert!(min_triangle_area(&mesh) > 1e-4);
        // Every vertex lies at distance r from the segment, its normal pointing away from it.
        let axis = (to - from).normalize();
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            let t = (p - from).dot(&axis).clamp(0.0, 10.0);
            let nearest = from + axis * t;
            assert!(((p - nearest).norm() - r).abs() < 1e-9);
            assert!(((p - nearest) / r - n).norm() < 1e-9);
        }
        let max_y = mesh.positions.iter().map(|p| p.y).fold(f64::MIN, f64::max);
        let min_y = mesh.positions.iter().map(|p| p.y).fold(f64::MAX, f64::min);
        assert!((max_y - 14.0).abs() < 1e-9 && (min_y - 0.0).abs() < 1e-9);
    }

    #[test]
    fn capsule_within_a_tolerance_lies_within_it_of_the_true_surface() {
        let from = Point3::new(1.0, 2.0, 3.0);
        for (r, to) in [
            (3.0, Point3::new(1.0, 12.0, 3.0)),
            (11.42, Point3::new(30.3, 2.04, 57.5)),
            (40.0, Point3::new(41.0, -10.0, 3.0)),
            (5.0, from),
        ] {
            let tolerance = 0.01;
            let mesh = capsule_within(&from, &to, r, tolerance);
            assert_closed(&mesh);
            assert!(mesh.triangles.len() >= capsule(&from, &to, r).triangles.len());
            let axis = to - from;
            let distance = |p: &Point3<f64>| {
                let t = if axis.norm() > 0.0 {
                    ((p - from).dot(&axis) / axis.norm_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (p - (from + axis * t)).norm()
            };
            // A face's nearest point to the axis is its circumcentre or on an edge; each face is
            // half of a planar quad whose centre is the midpoint of the shared diagonal.
            let mut deepest = f64::INFINITY;
            for t in &mesh.triangles {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                for p in [
                    Point3::from((a.coords + b.coords + c.coords) / 3.0),
                    Point3::from((a.coords + b.coords) / 2.0),
                    Point3::from((b.coords + c.coords) / 2.0),
                    Point3::from((c.coords + a.coords) / 2.0),
                ] {
                    deepest = deepest.min(distance(&p));
                }
            }
            assert!(
                deepest >= r - tolerance && deepest < r - tolerance / 10.0,
                "r {r}: deepest {deepest}"
            );
            let exact = PI * r * r * axis.norm() + 4.0 / 3.0 * PI * r.powi(3);
            let v = volume(&mesh);
            assert!(
                v < exact && v > exact * (1.0 - 2.0 * tolerance / r),
                "r {r}: {v} vs {exact}"
            );
        }
    }

    #[test]
    fn capsule_pointing_down_z_and_degenerate_capsule() {
        let down = capsule(&Point3::origin(), &Point3::new(0.0, 0.0, -5.0), 1.0);
        assert_closed(&down);
        assert!(volume(&down) > 0.0);
        let min_z = down.positions.iter().map(|p| p.z).fold(f64::MAX, f64::min);
        assert!((min_z + 6.0).abs() < 1e-9);

        let point = capsule(
            &Point3::new(1.0, 1.0, 1.0),
            &Point3::new(1.0, 1.0, 1.0),
            0.5,
        );
        assert_closed(&point);
        assert!(min_triangle_area(&point) > 1e-6);
        assert!((volume(&point) - volume(&unit_sphere()) * 0.125).abs() < 1e-9);
    }

    #[test]
    fn octahedron_is_closed_and_outward() {
        let o = unit_octahedron();
        assert_closed(&o);
        assert!((volume(&o) - 4.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn arrow_and_tubes_are_closed_thin_solids_along_their_direction() {
        let d = Vector3::new(0.0, 0.0, -1.0);
        let arrow = unit_arrow(&d);
        // Shaft and head are each closed and outward.
        assert!(volume(&arrow) > 0.0);
        assert!(min_triangle_area(&arrow) > 1e-6);
        let lowest = arrow.positions.iter().map(|p| p.z).fold(f64::MAX, f64::min);
        assert!((lowest + 1.0).abs() < 1e-12);
        for p in &arrow.positions {
            assert!(p.z <= 1e-12 && p.coords.xy().norm() <= ARROW_HEAD_RADIUS + 1e-12);
        }

        let line = unit_line(&Vector3::new(0.0, 3.0, 0.0), 0.01);
        assert_closed(&line);
        let exact = PI * 0.01 * 0.01;
        assert!((volume(&line) - exact).abs() < 0.05 * exact);
        let top = line.positions.iter().map(|p| p.y).fold(f64::MIN, f64::max);
        assert!((top - 1.0).abs() < 1e-12);

        let square = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ];
        let tubes = polygon_tubes(&square, 0.01);
        assert_eq!(
            tubes.triangles.len(),
            4 * unit_line(&d, 0.01).triangles.len()
        );
        assert!((volume(&tubes) - 4.0 * exact).abs() < 0.2 * exact);
        assert_eq!(
            polygon_tubes(&square[..2], 0.01).triangles.len(),
            line.triangles.len()
        );
        assert!(polygon_tubes(&square[..1], 0.01).triangles.is_empty());
    }
}
