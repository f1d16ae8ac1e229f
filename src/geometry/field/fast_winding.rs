//! Hierarchical generalized winding number (Barill et al. 2018, first order): exact solid angles
//! for nearby triangles, one dipole per distant cluster.

use nalgebra::{Point3, Vector3};

use super::super::tree::TriangleTree;
use super::super::winding::solid_angle;

/// A cluster is replaced by its dipole when the query is farther than `ACCURACY` times the
/// cluster's radius from its centre.
const ACCURACY: f64 = 2.0;

/// A cluster of triangles: its dipole (area-weighted centre and summed area vector) and extent.
#[derive(Debug, Clone)]
struct Cluster {
    centre: Point3<f64>,
    radius: f64,
    area_vector: Vector3<f64>,
}

/// Dipoles over the clusters of a [`TriangleTree`], for fast winding numbers.
#[derive(Debug, Clone)]
pub(super) struct WindingTree<'t> {
    tree: &'t TriangleTree,
    /// One per node of `tree`, same index.
    clusters: Vec<Cluster>,
}

impl<'t> WindingTree<'t> {
    /// The dipole of every node of `tree`: the area-weighted centre of its triangles (the centre
    /// of their bounding box when their area is zero), the radius of the ball around it holding
    /// them, and their summed area vector.
    pub(super) fn new(tree: &'t TriangleTree) -> WindingTree<'t> {
        let clusters = (0..tree.node_count())
            .map(|index| cluster(&tree.triangles()[tree.triangle_range(index)]))
            .collect();
        WindingTree { tree, clusters }
    }

    /// Approximate winding number at `p`: exact near the surface's nearby triangles, with a
    /// relative error of order `(1 / ACCURACY)²` per far cluster. 0 without triangles.
    pub(super) fn winding_number(&self, p: &Point3<f64>) -> f64 {
        let mut total = 0.0;
        let mut stack = if self.clusters.is_empty() {
            Vec::new()
        } else {
            vec![0]
        };
        while let Some(index) = stack.pop() {
            let cluster = &self.clusters[index];
            let offset = cluster.centre - p;
            let distance = offset.norm();
            if distance > ACCURACY * cluster.radius {
                total += cluster.area_vector.dot(&offset) / distance.powi(3);
            } else if let Some([left, right]) = self.tree.children(index) {
                stack.push(right);
                stack.push(left);
            } else {
                total += self.tree.triangles()[self.tree.triangle_range(index)]
                    .iter()
                    .map(|tri| solid_angle(tri, p))
                    .sum::<f64>();
            }
        }
        total / (4.0 * std::f64::consts::PI)
    }
}

/// The dipole and extent of `triangles`.
fn cluster(triangles: &[[Point3<f64>; 3]]) -> Cluster {
    let mut area_vector = Vector3::zeros();
    let mut weighted = Vector3::zeros();
    let mut total_area = 0.0;
    let mut lo = Point3::from(Vector3::repeat(f64::INFINITY));
    let mut hi = Point3::from(Vector3::repeat(f64::NEG_INFINITY));
    for &[a, b, c] in triangles {
        let area = (b - a).cross(&(c - a)) / 2.0;
        area_vector += area;
        total_area += area.norm();
        weighted += (a.coords + b.coords + c.coords) / 3.0 * area.norm();
        for v in [a, b, c] {
            lo = lo.inf(&v);
            hi = hi.sup(&v);
        }
    }
    let centre = if total_area > 0.0 {
        Point3::from(weighted / total_area)
    } else {
        Point3::from((lo.coords + hi.coords) / 2.0)
    };
    let radius = triangles
        .iter()
        .flatten()
        .map(|v| (v - centre).norm())
        .fold(0.0, f64::max);
    Cluster {
        centre,
        radius,
        area_vector,
    }
}
