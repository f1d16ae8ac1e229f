//! Quickhull's live triangles merged into the hull's flat facets.

use std::sync::Arc;

use nalgebra::Vector3;

use super::quickhull::Quickhull;
use super::{ConvexHull, HullFacet};
use crate::geometry::polygon::convex_hull_indices_into;

/// What merging one facet works with, kept from one facet to the next: a hull of a million
/// triangles has about as many facets.
#[derive(Default)]
struct Scratch {
    /// The facet's triangles.
    group: Vec<usize>,
    /// Their corners, ascending, once each.
    corners: Vec<usize>,
    /// The corners in the facet's plane.
    flat: Vec<[f64; 2]>,
    /// The plane hull's working space and result (indices into `flat`).
    sorted: Vec<usize>,
    polygon: Vec<usize>,
}

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
        let mut scratch = Scratch::default();
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
            let group = &mut scratch.group;
            group.clear();
            group.push(seed);
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
            if let Some(facet) = self.facet(&mut scratch) {
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

    /// One facet of the triangles `scratch.group`: their corners' convex polygon in the plane of
    /// their mean normal. `None` when that polygon has no area.
    fn facet(&self, scratch: &mut Scratch) -> Option<HullFacet> {
        let Scratch {
            group,
            corners,
            flat,
            sorted,
            polygon,
        } = scratch;
        let sum: Vector3<f64> = group
            .iter()
            .map(|&f| {
                let [a, b, c] = self.faces[f].corners.map(|i| self.points[i]);
                (b - a).cross(&(c - a))
            })
            .sum();
        let normal = sum.try_normalize(0.0)?;
        corners.clear();
        corners.extend(group.iter().flat_map(|&f| self.faces[f].corners));
        corners.sort_unstable();
        corners.dedup();
        // (u, w, normal) is right-handed, so counter-clockwise in (u, w) is counter-clockwise
        // seen from outside.
        let u = normal.cross(&least_aligned_axis(&normal)).normalize();
        let w = normal.cross(&u);
        flat.clear();
        flat.extend(corners.iter().map(|&i| {
            let p = self.points[i].coords;
            [u.dot(&p), w.dot(&p)]
        }));
        convex_hull_indices_into(flat, sorted, polygon);
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
        let corners: Arc<[usize]> = polygon.iter().map(|&k| corners[k]).collect();
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
