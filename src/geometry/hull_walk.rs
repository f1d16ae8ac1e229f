//! The extent of a convex hull along any direction, by walking its edges.
//!
//! A linear function on a convex polytope has no local minimum but its global one: from any
//! vertex that is not lowest, some edge leads down. So the lowest vertex along a direction is
//! found by stepping to the lowest neighbour until none is lower, which visits a path of
//! vertices instead of all of them. Starting each walk where the last one ended makes a series
//! of nearby directions cheap, so the extents along every facet normal of a hull of `n`
//! vertices cost far less than the `n` per direction of a scan.

use nalgebra::{Point3, Vector3};

use super::convex_hull::ConvexHull;

/// A hull's vertices and the edges of its facets between them.
#[derive(Debug, Clone)]
pub struct HullWalk {
    /// The hull's vertices, indices into the points of the hull.
    vertices: Vec<usize>,
    /// Vertex `v`'s neighbours along the facets' edges (indices into `vertices`, ascending) are
    /// `adjacent[starts[v]..starts[v + 1]]`.
    starts: Vec<usize>,
    adjacent: Vec<usize>,
}

impl HullWalk {
    /// The walk over `hull`'s vertices and facet edges.
    pub fn new(hull: &ConvexHull) -> HullWalk {
        let vertices = hull.vertices.clone();
        // Each point's index among the vertices, `NONE` for a point that is none.
        const NONE: usize = usize::MAX;
        let mut local = vec![NONE; vertices.last().map_or(0, |&last| last + 1)];
        for (v, &point) in vertices.iter().enumerate() {
            local[point] = v;
        }
        let local = |point: usize| local.get(point).copied().filter(|&v| v != NONE);
        let edges = || {
            hull.facets.iter().flat_map(move |facet| {
                let n = facet.corners.len();
                (0..n).filter_map(move |k| {
                    Some((local(facet.corners[k])?, local(facet.corners[(k + 1) % n])?))
                })
            })
        };
        // Every edge counted at both ends, then placed, then each vertex's list sorted and its
        // repeats (an edge seen from both of its facets) dropped.
        let mut starts = vec![0; vertices.len() + 1];
        for (a, b) in edges() {
            starts[a + 1] += 1;
            starts[b + 1] += 1;
        }
        for v in 0..vertices.len() {
            starts[v + 1] += starts[v];
        }
        let mut filled = starts.clone();
        let mut adjacent = vec![0; starts[vertices.len()]];
        for (a, b) in edges() {
            adjacent[filled[a]] = b;
            filled[a] += 1;
            adjacent[filled[b]] = a;
            filled[b] += 1;
        }
        let mut kept = 0;
        for v in 0..vertices.len() {
            let list = &mut adjacent[starts[v]..starts[v + 1]];
            list.sort_unstable();
            let mut previous = None;
            let start = kept;
            for k in starts[v]..starts[v + 1] {
                let neighbour = adjacent[k];
                if previous != Some(neighbour) {
                    adjacent[kept] = neighbour;
                    kept += 1;
                    previous = Some(neighbour);
                }
            }
            starts[v] = start;
        }
        starts[vertices.len()] = kept;
        adjacent.truncate(kept);
        HullWalk {
            vertices,
            starts,
            adjacent,
        }
    }

    /// The index among the walk's vertices of the hull's vertex `point` (an index into the points
    /// the hull was made of), to start a walk from; `None` when `point` is not a hull vertex.
    pub fn vertex(&self, point: usize) -> Option<usize> {
        self.vertices.binary_search(&point).ok()
    }

    /// The lowest and the highest of `direction · p` over the hull's vertices `p` (`points` are
    /// those the hull was made of): those of every point within the hull's tolerance, since a
    /// point that close to a facet need not be its corner, nor a vertex where a walk stops
    /// exactly the lowest when its neighbours' values differ from its own by rounding. The two
    /// walks start from the vertices `start` holds (indices into the hull's vertices), and
    /// `start` is set to where they ended. `None` for a hull without vertices.
    pub fn extent(
        &self,
        points: &[Point3<f64>],
        direction: &Vector3<f64>,
        start: &mut (usize, usize),
    ) -> Option<(f64, f64)> {
        if self.vertices.is_empty() {
            return None;
        }
        let at = |v: usize| direction.dot(&points[self.vertices[v]].coords);
        let (low, high) = (
            start.0.min(self.vertices.len() - 1),
            start.1.min(self.vertices.len() - 1),
        );
        let low = self.descend(low, &|v| at(v));
        let high = self.descend(high, &|v| -at(v));
        *start = (low, high);
        Some((at(low), at(high)))
    }

    /// The vertex reached from `from` by stepping to the neighbour with the lowest `value`
    /// while it is lower than the current one.
    fn descend(&self, from: usize, value: &dyn Fn(usize) -> f64) -> usize {
        let mut current = from;
        let mut here = value(current);
        loop {
            let next = self.adjacent[self.starts[current]..self.starts[current + 1]]
                .iter()
                .map(|&v| (v, value(v)))
                .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            match next {
                Some((v, lower)) if lower < here => {
                    current = v;
                    here = lower;
                }
                _ => return current,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::convex_hull;

    /// Points on a sphere, spread by the golden angle, and a few inside it.
    fn sphere(n: usize) -> Vec<Point3<f64>> {
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let mut points: Vec<Point3<f64>> = (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
                let r = (1.0 - z * z).sqrt();
                let a = golden * i as f64;
                Point3::new(3.0 * r * a.cos(), 2.0 * r * a.sin(), z)
            })
            .collect();
        points.extend([Point3::origin(), Point3::new(0.5, 0.2, 0.1)]);
        points
    }

    #[test]
    fn the_walk_finds_the_extent_a_scan_finds() {
        let points = sphere(2000);
        let hull = convex_hull(&points).expect("a hull");
        let walk = HullWalk::new(&hull);
        let mut start = (0, 0);
        for facet in &hull.facets {
            let d = facet.normal;
            let scan = points.iter().map(|p| d.dot(&p.coords));
            let low = scan.clone().fold(f64::INFINITY, f64::min);
            let high = scan.fold(f64::NEG_INFINITY, f64::max);
            let (walked_low, walked_high) = walk.extent(&points, &d, &mut start).expect("vertices");
            // Points within the coplanarity tolerance of a merged facet are not its corners.
            assert!(
                walked_low >= low && walked_low - low <= hull.tolerance,
                "along {d:?}"
            );
            assert!(
                walked_high <= high && high - walked_high <= hull.tolerance,
                "along {d:?}"
            );
        }
    }
}
