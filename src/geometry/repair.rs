//! The repairs a slicer makes to a mesh before slicing it, made the same way at load so the solid
//! ballast weighs is the one that is printed: triangles with two corners at one point dropped,
//! repeated triangles dropped, flipped patches turned to agree with their neighbours, holes
//! capped, and a mesh that is inside out turned right side out.
//!
//! Each repair keeps what is already right: a closed, consistently oriented mesh comes out with
//! the same positions and triangles, in the same order.

use std::collections::{BTreeMap, HashMap};

use nalgebra::Point3;

use super::edge_sort::sort_by_lower_corner;
use super::mass;
use super::mesh::TriMesh;

/// What `repair` changed in a mesh.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Repairs {
    /// Triangles (0-based, in the file's order) whose corners fall on fewer than three points:
    /// no area, no volume, and no edge a neighbour needs, so they are left out.
    pub collapsed_triangles: Vec<usize>,
    /// Triangles left out because an earlier one has the same corners: turning the same way (a
    /// doubled face, counted once), or the opposite way (the two enclose nothing; both left out).
    pub repeated_triangles: usize,
    /// Triangles turned over to agree with the most of the triangles they connect to across
    /// edges (a flipped patch).
    pub flipped_triangles: usize,
    /// The holes in the surface, each capped with a fan of triangles.
    pub holes: Vec<Hole>,
    /// The whole mesh enclosed a negative volume (its triangles faced inwards) and every triangle
    /// was turned over.
    pub turned_inside_out: bool,
}

/// A hole in a mesh's surface (a loop of edges with a triangle on one side only), capped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hole {
    /// The edges around the hole.
    pub edges: usize,
    /// How wide it is: four times the cap's area over the length around it (the diameter of a
    /// round hole, twice the width of a long crack). Mesh units.
    pub width: f64,
    /// The mean of the corners around it.
    pub centre: Point3<f64>,
}

/// `mesh` repaired as [`Repairs`] lists, in that order; triangles kept keep their order, and
/// the points a cap adds come after the mesh's own. Deterministic.
///
/// The mesh's indices must be in range (as every loader guarantees).
pub(crate) fn repair(mut mesh: TriMesh) -> (TriMesh, Repairs) {
    let mut repairs = Repairs {
        collapsed_triangles: drop_collapsed(&mut mesh),
        ..Repairs::default()
    };
    let mut edges = half_edges(&mesh);
    if edges
        .chunk_by(|a, b| a.edge == b.edge)
        .any(|run| !matches!(run, [a, b] if a.forward != b.forward))
    {
        repairs.repeated_triangles = drop_repeated(&mut mesh, &edges);
        if repairs.repeated_triangles > 0 {
            edges = half_edges(&mesh);
        }
        repairs.flipped_triangles = orient_patches(&mut mesh, &mut edges);
        repairs.holes = cap_holes(&mut mesh, &edges);
    }
    let volume = mass::integrate(
        mass::reference_point(&mesh),
        (0..mesh.triangles.len()).map(|i| mesh.triangle(i)),
    )
    .volume;
    if volume < 0.0 {
        for triangle in &mut mesh.triangles {
            triangle.swap(1, 2);
        }
        repairs.turned_inside_out = true;
    }
    (mesh, repairs)
}

/// Leaves out the triangles that repeat a corner, and returns their indices.
fn drop_collapsed(mesh: &mut TriMesh) -> Vec<usize> {
    let mut collapsed = Vec::new();
    let mut index = 0;
    mesh.triangles.retain(|&[a, b, c]| {
        let keep = a != b && b != c && c != a;
        if !keep {
            collapsed.push(index);
        }
        index += 1;
        keep
    });
    collapsed
}

/// One use of an undirected edge by a triangle.
#[derive(Debug, Clone, Copy)]
struct HalfEdge {
    /// The edge's two corners, the lower index in the high half.
    edge: u64,
    /// The triangle using it.
    triangle: u32,
    /// Whether the triangle runs along it from the lower corner to the higher.
    forward: bool,
}

/// Every triangle's three half-edges, sorted by edge (then triangle).
fn half_edges(mesh: &TriMesh) -> Vec<HalfEdge> {
    let mut edges = Vec::with_capacity(mesh.triangles.len() * 3);
    for (t, &[a, b, c]) in mesh.triangles.iter().enumerate() {
        for (u, v) in [(a, b), (b, c), (c, a)] {
            edges.push(HalfEdge {
                edge: (u64::from(u.min(v)) << 32) | u64::from(u.max(v)),
                triangle: t as u32,
                forward: u < v,
            });
        }
    }
    sort_by_lower_corner(
        &mut edges,
        |h| (h.edge >> 32) as u32,
        |h| (h.edge, h.triangle),
    );
    edges
}

/// Leaves out the triangles that repeat another's corners where that leaves the surface more
/// closed: of a face and its reverse (which enclose nothing), both; of a face repeated turning the
/// same way, each copy (in order) whose leaving brings the uses of its three edges closer to
/// pairing up, as many along each as against (a doubled face, or a doubled patch; where two
/// closed shells share a face, its edges pair up already and both copies stay). Returns how many
/// went.
fn drop_repeated(mesh: &mut TriMesh, edges: &[HalfEdge]) -> usize {
    // The corners turned so the lowest index comes first: equal for the same triangle whichever
    // corner it starts from.
    let canonical = |[a, b, c]: [u32; 3]| {
        if a < b && a < c {
            [a, b, c]
        } else if b < c {
            [b, c, a]
        } else {
            [c, a, b]
        }
    };
    let mut kept: HashMap<[u32; 3], usize> = HashMap::with_capacity(mesh.triangles.len());
    let mut keep = vec![true; mesh.triangles.len()];
    let mut repeats = Vec::new();
    for (index, &triangle) in mesh.triangles.iter().enumerate() {
        let key = canonical(triangle);
        if kept.contains_key(&key) {
            repeats.push(index);
        } else if let Some(earlier) = kept.remove(&[key[0], key[2], key[1]]) {
            keep[index] = false;
            keep[earlier] = false;
        } else {
            kept.insert(key, index);
        }
    }
    // Uses along each edge of a repeat, less those against, less the copies already left out.
    let mut left_out: HashMap<(u32, u32), i64> = HashMap::new();
    let net = |u: u32, v: u32, left_out: &HashMap<(u32, u32), i64>| {
        let key = (u64::from(u.min(v)) << 32) | u64::from(u.max(v));
        let start = edges.partition_point(|h| h.edge < key);
        let along: i64 = edges[start..]
            .iter()
            .take_while(|h| h.edge == key)
            .map(|h| if h.forward == (u < v) { 1 } else { -1 })
            .sum();
        along - left_out.get(&(u, v)).copied().unwrap_or(0)
            + left_out.get(&(v, u)).copied().unwrap_or(0)
    };
    // A copy inside a doubled patch pairs up only once its neighbours are out: pass again while
    // a pass leaves one out.
    let mut left = true;
    while left {
        left = false;
        for &index in &repeats {
            if !keep[index] {
                continue;
            }
            let [a, b, c] = mesh.triangles[index];
            let sides = [(a, b), (b, c), (c, a)];
            let nets = sides.map(|(u, v)| net(u, v, &left_out));
            let unpaired: i64 = nets.iter().map(|n| n.abs()).sum();
            let unpaired_without: i64 = nets.iter().map(|n| (n - 1).abs()).sum();
            if unpaired_without < unpaired {
                keep[index] = false;
                left = true;
                for side in sides {
                    *left_out.entry(side).or_default() += 1;
                }
            }
        }
    }
    let mut index = 0;
    mesh.triangles.retain(|_| {
        index += 1;
        keep[index - 1]
    });
    keep.iter().filter(|&&k| !k).count()
}

/// Turns triangles over so that, across every edge two triangles share, they run along it in
/// opposite directions: in each patch connected that way, the fewer of the two orientations is
/// turned (the patch's first triangle's when as many). A patch that cannot agree (a Möbius
/// strip) keeps what does not. Updates `edges` to the new directions; returns how many turned.
fn orient_patches(mesh: &mut TriMesh, edges: &mut [HalfEdge]) -> usize {
    const NONE: u32 = u32::MAX;
    let n = mesh.triangles.len();
    // Each triangle's neighbours across its two-triangle edges, and whether they agree.
    let mut neighbours = vec![[(NONE, false); 3]; n];
    for run in edges.chunk_by(|a, b| a.edge == b.edge) {
        if let [a, b] = run {
            if a.triangle != b.triangle {
                let agree = a.forward != b.forward;
                for (from, to) in [(a.triangle, b.triangle), (b.triangle, a.triangle)] {
                    if let Some(slot) = neighbours[from as usize].iter_mut().find(|s| s.0 == NONE) {
                        *slot = (to, agree);
                    }
                }
            }
        }
    }
    // Whether each triangle turns, relative to its patch's first triangle.
    let mut turn: Vec<Option<bool>> = vec![None; n];
    let mut turned = vec![false; n];
    let mut total = 0;
    let mut patch = Vec::new();
    for first in 0..n {
        if turn[first].is_some() {
            continue;
        }
        turn[first] = Some(false);
        patch.clear();
        patch.push(first);
        let mut next = 0;
        while next < patch.len() {
            let t = patch[next];
            next += 1;
            let flip = turn[t] == Some(true);
            for &(other, agree) in &neighbours[t] {
                if other != NONE && turn[other as usize].is_none() {
                    turn[other as usize] = Some(flip == agree);
                    patch.push(other as usize);
                }
            }
        }
        let against = patch.iter().filter(|&&t| turn[t] == Some(true)).count();
        let majority_turns = against * 2 > patch.len();
        for &t in &patch {
            turned[t] = (turn[t] == Some(true)) != majority_turns;
        }
        total += if majority_turns {
            patch.len() - against
        } else {
            against
        };
    }
    if total > 0 {
        for (triangle, _) in mesh.triangles.iter_mut().zip(&turned).filter(|(_, &t)| t) {
            triangle.swap(1, 2);
        }
        for half in edges.iter_mut() {
            half.forward ^= turned[half.triangle as usize];
        }
    }
    total
}

/// Caps every hole: the edges whose triangles' uses do not cancel (as many along it as against)
/// are chained into loops, and each loop gets a fan of triangles turning the other way (one
/// triangle for three edges, else a fan around a new point at the loop's mean).
fn cap_holes(mesh: &mut TriMesh, edges: &[HalfEdge]) -> Vec<Hole> {
    // The surface's boundary: each edge as often as its uses along it outnumber those against.
    let mut leaving: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for run in edges.chunk_by(|a, b| a.edge == b.edge) {
        let net: i64 = run.iter().map(|h| if h.forward { 1 } else { -1 }).sum();
        let (low, high) = ((run[0].edge >> 32) as u32, run[0].edge as u32);
        let (from, to) = if net > 0 { (low, high) } else { (high, low) };
        for _ in 0..net.unsigned_abs() {
            leaving.entry(from).or_default().push(to);
        }
    }
    for ends in leaving.values_mut() {
        // Taken from the back: the lowest first.
        ends.sort_unstable_by(|a, b| b.cmp(a));
    }
    let mut holes = Vec::new();
    while let Some((&start, _)) = leaving.first_key_value() {
        let mut corners = vec![start];
        let mut at = start;
        let closed = loop {
            let Some(ends) = leaving.get_mut(&at) else {
                break false;
            };
            let end = ends.pop().expect("an empty list is removed");
            if ends.is_empty() {
                leaving.remove(&at);
            }
            if end == start {
                break true;
            }
            corners.push(end);
            at = end;
        };
        if closed && corners.len() >= 3 {
            holes.push(cap(mesh, &corners));
        }
    }
    holes
}

/// Caps the hole whose boundary runs through `corners` (each to the next, the last to the
/// first) with triangles turning the other way.
fn cap(mesh: &mut TriMesh, corners: &[u32]) -> Hole {
    let k = corners.len();
    let centre = Point3::from(
        corners.iter().fold(nalgebra::Vector3::zeros(), |s, &i| {
            s + mesh.positions[i as usize].coords
        }) / k as f64,
    );
    let mut fan: Vec<[u32; 3]> = Vec::with_capacity(k);
    if k == 3 {
        fan.push([corners[2], corners[1], corners[0]]);
    } else {
        let middle = mesh.positions.len() as u32;
        mesh.positions.push(centre);
        for i in 0..k {
            fan.push([corners[(i + 1) % k], corners[i], middle]);
        }
    }
    let point = |i: u32| mesh.positions[i as usize];
    let area: f64 = fan
        .iter()
        .map(|&[a, b, c]| (point(b) - point(a)).cross(&(point(c) - point(a))).norm() / 2.0)
        .sum();
    let length: f64 = (0..k)
        .map(|i| (point(corners[(i + 1) % k]) - point(corners[i])).norm())
        .sum();
    mesh.triangles.extend(fan);
    Hole {
        edges: k,
        width: if length > 0.0 {
            4.0 * area / length
        } else {
            0.0
        },
        centre,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube, 8 corners and 12 triangles facing out.
    fn cube() -> TriMesh {
        let positions = (0..8)
            .map(|i| Point3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
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
        TriMesh {
            positions,
            triangles,
        }
    }

    fn volume(mesh: &TriMesh) -> f64 {
        mass::mass_properties(mesh).volume
    }

    #[test]
    fn a_clean_mesh_is_unchanged() {
        let (mesh, repairs) = repair(cube());
        assert_eq!(mesh, cube());
        assert_eq!(repairs, Repairs::default());
    }

    #[test]
    fn a_flipped_triangle_turns_back() {
        let mut broken = cube();
        broken.triangles[3].swap(0, 1);
        let (mesh, repairs) = repair(broken);
        assert_eq!(repairs.flipped_triangles, 1);
        assert_eq!(mesh.triangles[3], [7, 6, 5]);
        assert!((volume(&mesh) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn an_inside_out_mesh_is_turned() {
        let mut broken = cube();
        for t in &mut broken.triangles {
            t.swap(0, 1);
        }
        let (mesh, repairs) = repair(broken);
        assert!(repairs.turned_inside_out);
        assert_eq!(repairs.flipped_triangles, 0);
        assert!((volume(&mesh) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn repeats_go_and_opposite_pairs_cancel() {
        let mut broken = cube();
        // A doubled face, and a wall of no thickness through the middle (both sides).
        broken.triangles.push([2, 1, 0]);
        broken.triangles.push([0, 3, 5]);
        broken.triangles.push([5, 3, 0]);
        let (mesh, repairs) = repair(broken);
        assert_eq!(repairs.repeated_triangles, 3);
        assert_eq!(repairs.flipped_triangles, 0);
        assert!(repairs.holes.is_empty());
        assert_eq!(mesh, cube());
    }

    #[test]
    fn holes_are_capped_and_measured() {
        let mut broken = cube();
        // The top face (z = 1): a square hole of side 1.
        broken.triangles.retain(|t| t.iter().any(|&i| i < 4));
        let (mesh, repairs) = repair(broken);
        assert_eq!(repairs.holes.len(), 1);
        let hole = repairs.holes[0];
        assert_eq!(hole.edges, 4);
        assert!((hole.width - 1.0).abs() < 1e-12, "{}", hole.width);
        assert!((hole.centre - Point3::new(0.5, 0.5, 1.0)).norm() < 1e-12);
        assert_eq!(mesh.positions.len(), 9);
        assert!((volume(&mesh) - 1.0).abs() < 1e-12);
        let repaired = super::super::check_mesh(&mesh);
        assert!(
            repaired.is_closed() && repaired.is_oriented(),
            "{repaired:?}"
        );
    }
}
