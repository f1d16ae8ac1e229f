//! Quickhull's live triangles merged into the hull's flat facets.

use nalgebra::Vector3;

use super::quickhull::Quickhull;
use super::{ConvexHull, HullFacet};
use crate::geometry::polygon::convex_hull_indices;

impl Quickhull<'_> {
    /// The live triangles merged into facets: from the largest triangle down, each facet takes
    /// the triangles reachable across edges whose corners are within `tolerance` of its first
    /// triangle's plane.
    pub(super) fn facets(&self, tolerance: f64) -> ConvexHull {
        let area = |f: usize| {
            let [a, b, c] = self.faces[f].corners.map(|i| self.points[i]);
            (b - a).cross(&(c - a)).norm() / 2.0
        };
        let mut order: Vec<(f64, usize)> = (0..self.faces.len())
            .filter(|&f| self.faces[f].alive)
            .map(|f| (area(f), f))
            .collect();
        order.sort_unstable_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
        let mut taken = vec![false; self.faces.len()];
        let mut facets = Vec::new();
        for &(_, seed) in &order {
            if taken[seed] {
                continue;
            }
            taken[seed] = true;
            let (normal, offset) = (self.faces[seed].normal, self.faces[seed].offset);
            let on_plane = |f: usize| {
                let face = &self.faces[f];
                face.normal.dot(&normal) > 0.0
                    && face
                        .corners
                        .iter()
                        .all(|&i| (normal.dot(&self.points[i].coords) - offset).abs() <= tolerance)
            };
            let mut group = vec![seed];
            let mut k = 0;
            while k < group.len() {
                let neighbours = self.faces[group[k]].neighbours;
                k += 1;
                for neighbour in neighbours {
                    if !taken[neighbour] && on_plane(neighbour) {
                        taken[neighbour] = true;
                        group.push(neighbour);
                    }
                }
            }
            if let Some(facet) = self.facet(&group) {
                facets.push(facet);
            }
        }
        facets.sort_by(|a, b| b.area.total_cmp(&a.area));
        let mut vertices: Vec<usize> = facets
            .iter()
            .flat_map(|f| f.corners.iter().copied())
            .collect();
        vertices.sort_unstable();
        vertices.dedup();
        ConvexHull {
            facets,
            vertices,
            tolerance,
        }
    }

    /// One facet of the triangles `group`: their corners' convex polygon in the plane of their
    /// mean normal. `None` when that polygon has no area.
    fn facet(&self, group: &[usize]) -> Option<HullFacet> {
        let sum: Vector3<f64> = group
            .iter()
            .map(|&f| {
                let [a, b, c] = self.faces[f].corners.map(|i| self.points[i]);
                (b - a).cross(&(c - a))
            })
            .sum();
        let normal = sum.try_normalize(0.0)?;
        let mut corners: Vec<usize> = group.iter().flat_map(|&f| self.faces[f].corners).collect();
        corners.sort_unstable();
        corners.dedup();
        // (u, w, normal) is right-handed, so counter-clockwise in (u, w) is counter-clockwise
        // seen from outside.
        let u = normal.cross(&least_aligned_axis(&normal)).normalize();
        let w = normal.cross(&u);
        let flat: Vec<[f64; 2]> = corners
            .iter()
            .map(|&i| {
                let p = self.points[i].coords;
                [u.dot(&p), w.dot(&p)]
            })
            .collect();
        let polygon: Vec<usize> = convex_hull_indices(&flat);
        if polygon.len() < 3 {
            return None;
        }
        let area = (0..polygon.len())
            .map(|k| {
                let (a, b) = (flat[polygon[k]], flat[polygon[(k + 1) % polygon.len()]]);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum::<f64>()
            / 2.0;
        let corners: Vec<usize> = polygon.iter().map(|&k| corners[k]).collect();
        let offset = corners
            .iter()
            .map(|&i| normal.dot(&self.points[i].coords))
            .fold(f64::NEG_INFINITY, f64::max);
        Some(HullFacet {
            normal,
            offset,
            corners,
            area,
        })
    }
}

/// The coordinate axis most nearly perpendicular to `v`.
fn least_aligned_axis(v: &Vector3<f64>) -> Vector3<f64> {
    let a = v.abs();
    if a.x <= a.y && a.x <= a.z {
        Vector3::x()
    } else if a.y <= a.z {
        Vector3::y()
    } else {
        Vector3::z()
    }
}
