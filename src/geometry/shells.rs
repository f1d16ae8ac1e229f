//! Whether a closed, oriented mesh bounds a solid its signed volume measures: no two triangles
//! cross, and the winding number is 0 or 1 everywhere off the surface (no shell inside another
//! shell facing the same way, no inward shell with nothing around it).
//!
//! The signed volume and the moments are integrals of the winding number; they are the solid's
//! only when the winding number is 0 outside and 1 inside. Two overlapping cubes (winding 2 in
//! the overlap) or a cube inside a cube both facing outwards (2 inside the inner one) would
//! otherwise get a wrong volume and no word.

use std::f64::consts::PI;

use nalgebra::Point3;

use super::mesh::TriMesh;
use super::winding::solid_angle;
use crate::parallel::map_nodes;

/// A shell of the mesh whose side has a winding number other than 0 or 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShellFault {
    /// The first triangle of the shell, in mesh order.
    pub triangle: u32,
    /// The winding number just inside the shell (or just outside, when that is the wrong one):
    /// 2 or more for a shell inside another that faces the same way, negative for an inward
    /// shell that is inside nothing.
    pub winding: i32,
}

/// What [`check_shells`] found.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct Shells {
    /// Pairs of triangles that cross (an edge of one passes through the other from one side to
    /// the other), ascending.
    pub crossings: Vec<[u32; 2]>,
    /// Shells with a winding number outside {0, 1}; looked for only without crossings.
    pub faults: Vec<ShellFault>,
    /// The work bound was reached before every pair or shell was looked at.
    pub incomplete: bool,
}

/// Triangle pairs and solid angles looked at, at most, per triangle of the mesh (and a fixed
/// allowance for small meshes), so a mesh made to defeat the grid cannot make the check endless.
const WORK_PER_TRIANGLE: usize = 256;
const WORK_ALLOWANCE: usize = 1 << 22;

/// Looks for crossing triangles, then for misnested shells. The mesh must be closed and oriented
/// with every index in range (as [`check_mesh`](super::check_mesh) verifies first). The
/// `degenerate` triangles (zero area: they enclose nothing) are not tested for crossing.
/// Deterministic.
pub(crate) fn check_shells(mesh: &TriMesh, degenerate: &[u32]) -> Shells {
    let mut budget = mesh
        .triangles
        .len()
        .saturating_mul(WORK_PER_TRIANGLE)
        .saturating_add(WORK_ALLOWANCE);
    let mut shells = Shells::default();
    let boxes: Vec<Aabb> = (0..mesh.triangles.len())
        .map(|i| Aabb::of(&mesh.triangle(i)))
        .collect();
    let mut flat = vec![false; mesh.triangles.len()];
    for &t in degenerate {
        flat[t as usize] = true;
    }
    shells.incomplete = !crossings(mesh, &boxes, &flat, &mut budget, &mut shells.crossings);
    if shells.crossings.is_empty() && !shells.incomplete {
        shells.incomplete = !misnested(mesh, &boxes, &mut budget, &mut shells.faults);
    }
    shells
}

#[derive(Debug, Clone, Copy)]
struct Aabb {
    lo: Point3<f64>,
    hi: Point3<f64>,
}

impl Aabb {
    fn of(points: &[Point3<f64>]) -> Aabb {
        points.iter().fold(
            Aabb {
                lo: points[0],
                hi: points[0],
            },
            |b, p| Aabb {
                lo: b.lo.inf(p),
                hi: b.hi.sup(p),
            },
        )
    }

    fn overlaps(&self, other: &Aabb) -> bool {
        (0..3).all(|k| self.lo[k] <= other.hi[k] && other.lo[k] <= self.hi[k])
    }

    fn contains(&self, p: &Point3<f64>) -> bool {
        (0..3).all(|k| self.lo[k] <= p[k] && p[k] <= self.hi[k])
    }
}

/// Grid cells are chosen so that the triangles' boxes cover at most this many cells each on
/// average.
const CELLS_PER_TRIANGLE: f64 = 8.0;

/// Appends every crossing pair to `out`, sorted. False when the budget ran out first.
fn crossings(
    mesh: &TriMesh,
    boxes: &[Aabb],
    flat: &[bool],
    budget: &mut usize,
    out: &mut Vec<[u32; 2]>,
) -> bool {
    let n = boxes.len();
    if n < 2 {
        return true;
    }
    let cell = cell_size(boxes);
    // Cell indices in 32 bits keep an entry at 16 bytes (the sort of 8 entries a triangle is
    // most of this check's time on a large mesh). A mesh whose extent spans more than 2³¹
    // cells has its far cells saturate into one: more pairs share a cell, each still tested
    // for overlap, so only the work (counted against the budget) grows.
    let index = |x: f64| (x / cell).floor() as i32;
    let mut entries: Vec<([i32; 3], u32)> = Vec::new();
    for (t, b) in boxes.iter().enumerate().filter(|&(t, _)| !flat[t]) {
        let (lo, hi) = (b.lo.map(index), b.hi.map(index));
        for i in lo.x..=hi.x {
            for j in lo.y..=hi.y {
                for k in lo.z..=hi.z {
                    entries.push(([i, j, k], t as u32));
                }
            }
        }
    }
    entries.sort_unstable();
    // Whether triangles `s` and `t`, both in the cell `key`, cross there: each pair is tested
    // once, in the cell holding the low corner of the boxes' overlap.
    let cross_in = |key: [i32; 3], s: u32, t: u32| {
        let (bs, bt) = (&boxes[s as usize], &boxes[t as usize]);
        bs.overlaps(bt) && {
            let corner = bs.lo.sup(&bt.lo).map(index);
            [corner.x, corner.y, corner.z] == key
                && triangles_cross(&mesh.triangle(s as usize), &mesh.triangle(t as usize))
        }
    };
    let runs: Vec<&[([i32; 3], u32)]> = entries.chunk_by(|a, b| a.0 == b.0).collect();
    let pairs = runs
        .iter()
        .map(|run| run.len() * (run.len() - 1) / 2)
        .fold(0, usize::saturating_add);
    if pairs <= *budget {
        // Every pair within the budget: the cells are independent, looked at on every core.
        *budget -= pairs;
        let found = map_nodes(runs.len(), |r| {
            pairs_in(runs[r])
                .filter(|&(key, s, t)| cross_in(key, s, t))
                .map(|(_, s, t)| [s.min(t), s.max(t)])
                .collect::<Vec<_>>()
        });
        out.extend(found.into_iter().flatten());
        out.sort_unstable();
        return true;
    }
    let mut complete = true;
    for (key, s, t) in runs.into_iter().flat_map(pairs_in) {
        if *budget == 0 {
            complete = false;
            break;
        }
        *budget -= 1;
        if cross_in(key, s, t) {
            out.push([s.min(t), s.max(t)]);
        }
    }
    out.sort_unstable();
    complete
}

/// Every pair of triangles in one cell's run of grid entries, with the cell: `(cell, s, t)`, `s`
/// before `t` in the run.
fn pairs_in(run: &[([i32; 3], u32)]) -> impl Iterator<Item = ([i32; 3], u32, u32)> + '_ {
    run.iter()
        .enumerate()
        .flat_map(move |(x, &(key, s))| run[x + 1..].iter().map(move |&(_, t)| (key, s, t)))
}

/// A cell edge for which the boxes cover about [`CELLS_PER_TRIANGLE`] cells each: from the largest
/// box extent (at most 8 cells per box), halved while that still holds.
fn cell_size(boxes: &[Aabb]) -> f64 {
    let largest = boxes
        .iter()
        .map(|b| (b.hi - b.lo).max())
        .fold(0.0, f64::max);
    let mut cell = if largest > 0.0 { largest } else { 1.0 };
    let covered = |cell: f64| -> f64 {
        boxes
            .iter()
            .map(|b| {
                (0..3)
                    .map(|k| (b.hi[k] / cell).floor() - (b.lo[k] / cell).floor() + 1.0)
                    .product::<f64>()
            })
            .sum()
    };
    let allowed = CELLS_PER_TRIANGLE * boxes.len() as f64;
    for _ in 0..64 {
        if covered(cell / 2.0) > allowed {
            break;
        }
        cell /= 2.0;
    }
    cell
}

/// Whether an edge of one triangle passes through the other (its inside or its edges) from one
/// side of its plane to the other: the two surfaces cross. Touching (an end on the other's
/// plane, a shared edge or vertex, a shared plane) is not crossing.
fn triangles_cross(a: &[Point3<f64>; 3], b: &[Point3<f64>; 3]) -> bool {
    (straddles(a, b) && (0..3).any(|i| edge_pierces(&a[i], &a[(i + 1) % 3], b)))
        || (straddles(b, a) && (0..3).any(|i| edge_pierces(&b[i], &b[(i + 1) % 3], a)))
}

/// Whether corners of `a` lie strictly on both sides of the plane of `t`, as [`edge_pierces`]
/// measures it: when not, no edge of `a` pierces `t` (its ends must be on opposite sides beyond
/// a tolerance), which two triangles of a smooth surface show most of the time.
fn straddles(a: &[Point3<f64>; 3], t: &[Point3<f64>; 3]) -> bool {
    let normal = (t[1] - t[0]).cross(&(t[2] - t[0]));
    let side = a.map(|p| normal.dot(&(p - t[0])));
    side.iter().any(|&s| s > 0.0) && side.iter().any(|&s| s < 0.0)
}

/// Whether the segment `p`–`q` crosses the plane of `t` strictly between its ends, at a point of
/// `t` (its edges included: a crossing through the edge two triangles share is one of both).
fn edge_pierces(p: &Point3<f64>, q: &Point3<f64>, t: &[Point3<f64>; 3]) -> bool {
    let scale = [p, q, &t[0], &t[1], &t[2]]
        .iter()
        .map(|x| (*x - t[0]).norm())
        .fold(0.0, f64::max);
    let tolerance = 1e-12 * scale.powi(3);
    let orient = |a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>, d: &Point3<f64>| {
        (b - a).cross(&(c - a)).dot(&(d - a))
    };
    let (dp, dq) = (
        orient(&t[0], &t[1], &t[2], p),
        orient(&t[0], &t[1], &t[2], q),
    );
    if !((dp > tolerance && dq < -tolerance) || (dp < -tolerance && dq > tolerance)) {
        return false;
    }
    let sides = [
        orient(p, q, &t[0], &t[1]),
        orient(p, q, &t[1], &t[2]),
        orient(p, q, &t[2], &t[0]),
    ];
    sides.iter().all(|&s| s >= -tolerance) || sides.iter().all(|&s| s <= tolerance)
}

/// Appends every shell whose sides are not at winding 0 and 1. Without crossings, each shell is a
/// closed surface; the winding number just outside it is that of the other shells at a point of
/// it, and just inside one more (one less for an inward shell). False when the budget ran out.
fn misnested(
    mesh: &TriMesh,
    boxes: &[Aabb],
    budget: &mut usize,
    out: &mut Vec<ShellFault>,
) -> bool {
    let shells = shell_triangles(mesh);
    if shells.len() < 2 {
        return true;
    }
    let shell_boxes: Vec<Aabb> = shells
        .iter()
        .map(|tris| {
            let corners: Vec<Point3<f64>> = tris
                .iter()
                .flat_map(|&t| [boxes[t].lo, boxes[t].hi])
                .collect();
            Aabb::of(&corners)
        })
        .collect();
    for (s, tris) in shells.iter().enumerate() {
        let first = mesh.triangle(tris[0]);
        let at = Point3::from((first[0].coords + first[1].coords + first[2].coords) / 3.0);
        let mut total = 0.0;
        for (other, others) in shells.iter().enumerate() {
            if other == s || !shell_boxes[other].contains(&at) {
                continue;
            }
            if *budget < others.len() {
                return false;
            }
            *budget -= others.len();
            total += others
                .iter()
                .map(|&t| solid_angle(&mesh.triangle(t), &at))
                .sum::<f64>();
        }
        let outside = (total / (4.0 * PI)).round() as i32;
        let inside = outside
            + if shell_volume(mesh, tris) < 0.0 {
                -1
            } else {
                1
            };
        let wrong = [inside, outside].into_iter().find(|w| !(0..=1).contains(w));
        if let Some(winding) = wrong {
            out.push(ShellFault {
                triangle: tris[0] as u32,
                winding,
            });
        }
    }
    true
}

/// The triangles of each shell (connected through shared vertices), shells in the order of their
/// first triangle, triangles in mesh order.
fn shell_triangles(mesh: &TriMesh) -> Vec<Vec<usize>> {
    let mut parent: Vec<u32> = (0..mesh.positions.len() as u32).collect();
    fn find(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            let up = parent[parent[v as usize] as usize];
            parent[v as usize] = up;
            v = up;
        }
        v
    }
    for &[a, b, c] in &mesh.triangles {
        for (u, v) in [(a, b), (a, c)] {
            let (ru, rv) = (find(&mut parent, u), find(&mut parent, v));
            parent[ru.max(rv) as usize] = ru.min(rv);
        }
    }
    let mut shell_of_root = std::collections::BTreeMap::new();
    let mut shells: Vec<Vec<usize>> = Vec::new();
    for (t, &[a, _, _]) in mesh.triangles.iter().enumerate() {
        let root = find(&mut parent, a);
        let shell = *shell_of_root.entry(root).or_insert_with(|| {
            shells.push(Vec::new());
            shells.len() - 1
        });
        shells[shell].push(t);
    }
    shells
}

/// The signed volume one shell encloses, about its first vertex.
fn shell_volume(mesh: &TriMesh, triangles: &[usize]) -> f64 {
    let origin = mesh.triangle(triangles[0])[0];
    triangles
        .iter()
        .map(|&t| {
            let [a, b, c] = mesh.triangle(t);
            (a - origin).dot(&(b - origin).cross(&(c - origin))) / 6.0
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::SplitMix64;

    fn tri(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [Point3<f64>; 3] {
        [a.into(), b.into(), c.into()]
    }

    #[test]
    fn crossing_triangles_cross_and_touching_ones_do_not() {
        let flat = tri([0., 0., 0.], [4., 0., 0.], [0., 4., 0.]);
        let through = tri([1., 1., -1.], [1., 1., 1.], [2., 2., 1.]);
        assert!(triangles_cross(&flat, &through));
        // Resting on the plane, and sharing an edge.
        let resting = tri([1., 1., 0.], [1., 1., 1.], [2., 2., 1.]);
        assert!(!triangles_cross(&flat, &resting));
        let neighbour = tri([4., 0., 0.], [0., 0., 0.], [0., 0., 3.]);
        assert!(!triangles_cross(&flat, &neighbour));
        // Coplanar and overlapping: touching, not crossing.
        let coplanar = tri([1., 1., 0.], [5., 1., 0.], [1., 5., 0.]);
        assert!(!triangles_cross(&flat, &coplanar));
        // Beside it.
        let beside = tri([5., 5., -1.], [5., 5., 1.], [6., 6., 1.]);
        assert!(!triangles_cross(&flat, &beside));
    }

    /// 400 triangles of random sizes scattered in a 10 mm box (a fixed generator).
    fn scattered_triangles() -> TriMesh {
        let mut random = SplitMix64::new(0x2545_f491_4f6c_dd1d);
        let mut next = || random.unit();
        let mut mesh = TriMesh {
            positions: Vec::new(),
            triangles: Vec::new(),
        };
        for t in 0..400u32 {
            let centre = [next() * 10.0, next() * 10.0, next() * 10.0];
            let size = 0.2 + 2.0 * next();
            for _ in 0..3 {
                let offset = [next() - 0.5, next() - 0.5, next() - 0.5];
                mesh.positions.push(Point3::from(std::array::from_fn(|k| {
                    centre[k] + size * offset[k]
                })));
            }
            mesh.triangles.push([3 * t, 3 * t + 1, 3 * t + 2]);
        }
        mesh
    }

    #[test]
    fn the_grid_finds_every_crossing_pair_and_counts_every_pair_it_looks_at() {
        let mesh = scattered_triangles();
        let boxes: Vec<Aabb> = (0..mesh.triangles.len())
            .map(|i| Aabb::of(&mesh.triangle(i)))
            .collect();
        let flat = vec![false; boxes.len()];
        let mut every = Vec::new();
        for s in 0..boxes.len() {
            for t in s + 1..boxes.len() {
                if triangles_cross(&mesh.triangle(s), &mesh.triangle(t)) {
                    every.push([s as u32, t as u32]);
                }
            }
        }
        assert!(every.len() > 20, "{} crossing pairs", every.len());
        let mut budget = usize::MAX / 2;
        let mut found = Vec::new();
        assert!(crossings(&mesh, &boxes, &flat, &mut budget, &mut found));
        assert_eq!(found, every);
        // With exactly the pairs it looked at, it still finishes; with one fewer it stops short
        // and says so.
        let looked_at = usize::MAX / 2 - budget;
        let mut exact = looked_at;
        let mut again = Vec::new();
        assert!(crossings(&mesh, &boxes, &flat, &mut exact, &mut again));
        assert_eq!((exact, &again), (0, &every));
        let mut short = looked_at - 1;
        let mut partial = Vec::new();
        assert!(!crossings(&mesh, &boxes, &flat, &mut short, &mut partial));
        assert_eq!(short, 0);
        assert!(partial.iter().all(|pair| every.contains(pair)));
    }
}
