//! Checks that a triangle mesh bounds a printable solid.

use nalgebra::Point3;

use super::edge_sort::sort_by_lower_corner;
use super::mass::{self, MassProperties};
use super::mesh::TriMesh;
use super::print::{overlap, Overlap};
use super::shells::{check_shells, ShellFault};

/// What is wrong with a mesh as a printable solid. Edges are vertex index pairs `[min, max]`,
/// listed in ascending order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshCheck {
    /// Undirected edges used by exactly one triangle (holes in the surface).
    pub boundary_edges: Vec<[u32; 2]>,
    /// Undirected edges used by more than two triangles, not as often along the edge as against
    /// it. (Where as many triangles run each way, as where two shells touch along an edge, the
    /// uses pair up and the surface still encloses a solid: such edges are not listed.)
    pub non_manifold_edges: Vec<[u32; 2]>,
    /// Edges used by exactly two triangles, both in the same direction: the two triangles
    /// disagree about which side is outside.
    pub misoriented_edges: Vec<[u32; 2]>,
    /// Indices of triangles with (numerically) zero area, a repeated vertex index, or an index
    /// past the positions. Those with a repeated or out-of-range index are left out of the
    /// edge lists and the volume; the others (three distinct corners on a line) enclose nothing
    /// and close the surface like any other, but are left out of the crossing check.
    pub degenerate_triangles: Vec<u32>,
    /// Signed volume of the enclosed solid (units³); negative means inside out.
    pub signed_volume: f64,
    /// Pairs of triangles whose surfaces cross (an edge of one passes through the other from one
    /// side to the other), ascending: the mesh intersects itself, or two of its shells overlap.
    /// Looked for only in a closed, oriented mesh whose every index is in range.
    pub crossing_triangles: Vec<[u32; 2]>,
    /// Shells beside which the winding number is not 0 or 1: a shell inside another that faces
    /// the same way, or an inward shell inside nothing. Looked for only when no triangles cross.
    pub shell_faults: Vec<ShellFault>,
    /// The crossing and shell checks stopped at their work bound before the end (a mesh built to
    /// defeat them); what they found so far is listed.
    pub shells_unchecked: bool,
    /// For a mesh whose triangles cross or whose shells do not nest right: how much its shells
    /// overlap, beside the volume of their union ([`overlap`]).
    pub overlap: Option<Overlap>,
}

impl MeshCheck {
    /// Every edge's uses pair up: no holes, no non-manifold edges that leave the surface open.
    pub fn is_closed(&self) -> bool {
        self.boundary_edges.is_empty() && self.non_manifold_edges.is_empty()
    }

    /// Neighbouring triangles agree on their orientation (no edge is used twice in the
    /// same direction).
    pub fn is_oriented(&self) -> bool {
        self.misoriented_edges.is_empty()
    }

    /// The triangles face inwards: the signed volume is negative.
    pub fn is_inverted(&self) -> bool {
        self.signed_volume < 0.0
    }

    /// The signed volume is the volume of one solid: no triangles cross and every shell is
    /// nested right (the winding number is 0 or 1 everywhere off the surface).
    pub fn is_solid(&self) -> bool {
        self.crossing_triangles.is_empty() && self.shell_faults.is_empty()
    }

    /// The mass properties of the solid `mesh` (the mesh this check is of) bounds as a slicer
    /// prints it: the union of its shells, their [`overlap`](Self::overlap) taken away from the
    /// closed form.
    pub fn solid(&self, mesh: &TriMesh) -> MassProperties {
        let whole = mass::mass_properties(mesh);
        let Some(overlap) = &self.overlap else {
            return whole;
        };
        let volume = whole.volume - overlap.volume;
        let first = whole.centroid.coords * whole.volume - overlap.first_moment;
        MassProperties {
            volume,
            centroid: if volume != 0.0 {
                Point3::from(first / volume)
            } else {
                whole.centroid
            },
            second_moment: whole.second_moment - overlap.second_moment,
        }
    }
}

/// A triangle counts as zero-area when twice its area is at most this fraction of its longest
/// edge squared (its smallest angle is below about 1e-12 radians).
const DEGENERATE_RATIO: f64 = 1e-12;

/// Checks the topology and orientation of `mesh`, and, when it is closed and oriented, that its
/// surface does not cross itself and its shells nest right.
/// Deterministic: edge and pair lists are sorted ascending, triangle lists are in mesh order.
/// Never panics, even on out-of-range indices.
pub fn check_mesh(mesh: &TriMesh) -> MeshCheck {
    let n = mesh.positions.len();
    let mut degenerate_triangles = Vec::new();
    // Every use of an undirected edge (min, max), and whether it runs max→min; sorted below so
    // that each edge's uses lie together.
    let mut uses: Vec<(u64, bool)> = Vec::with_capacity(mesh.triangles.len() * 3);
    let mut valid = Vec::with_capacity(mesh.triangles.len());
    for (i, t @ &[a, b, c]) in mesh.triangles.iter().enumerate() {
        let in_range = t.iter().all(|&v| (v as usize) < n);
        if !in_range || a == b || b == c || c == a {
            degenerate_triangles.push(i as u32);
            continue;
        }
        valid.push(i);
        let [p, q, r] = mesh.triangle(i);
        let (ab, ac, bc) = (q - p, r - p, r - q);
        let longest = ab
            .norm_squared()
            .max(ac.norm_squared())
            .max(bc.norm_squared());
        if ab.cross(&ac).norm() <= DEGENERATE_RATIO * longest {
            degenerate_triangles.push(i as u32);
        }
        for (u, v) in [(a, b), (b, c), (c, a)] {
            uses.push(((u64::from(u.min(v)) << 32) | u64::from(u.max(v)), u > v));
        }
    }

    let mut check = MeshCheck {
        degenerate_triangles,
        signed_volume: mass::integrate(
            mass::reference_point(mesh),
            valid.iter().map(|&i| mesh.triangle(i)),
        )
        .volume,
        ..MeshCheck::default()
    };
    sort_by_lower_corner(&mut uses, |&(edge, _)| (edge >> 32) as u32, |&use_| use_);
    for run in uses.chunk_by(|a, b| a.0 == b.0) {
        let edge = [(run[0].0 >> 32) as u32, run[0].0 as u32];
        let backward = run.iter().filter(|&&(_, backward)| backward).count();
        let forward = run.len() - backward;
        match forward + backward {
            1 => check.boundary_edges.push(edge),
            2 if forward != 1 => check.misoriented_edges.push(edge),
            2 => {}
            _ if forward == backward => {}
            _ => check.non_manifold_edges.push(edge),
        }
    }
    check.boundary_edges.sort_unstable();
    check.non_manifold_edges.sort_unstable();
    check.misoriented_edges.sort_unstable();
    let indices_in_range = mesh.triangles.iter().flatten().all(|&v| (v as usize) < n);
    if check.is_closed() && check.is_oriented() && indices_in_range {
        let shells = check_shells(mesh, &check.degenerate_triangles);
        check.crossing_triangles = shells.crossings;
        check.shell_faults = shells.faults;
        check.shells_unchecked = shells.incomplete;
        if !check.is_solid() {
            check.overlap = overlap(mesh);
        }
    }
    check
}
