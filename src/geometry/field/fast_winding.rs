//! Hierarchical generalized winding number (Barill et al. 2018, first order): exact solid angles
//! for nearby triangles, one dipole per distant cluster.

use nalgebra::{Point3, Vector3};

use super::super::mesh::TriMesh;
use super::super::winding::solid_angle;

/// Triangles per leaf.
const LEAF_SIZE: usize = 8;
/// A cluster is replaced by its dipole when the query is farther than `ACCURACY` times the
/// cluster's radius from its centre.
const ACCURACY: f64 = 2.0;

/// A cluster of triangles: its dipole (area-weighted centre and summed area vector) and extent.
#[derive(Debug, Clone)]
struct Cluster {
    centre: Point3<f64>,
    radius: f64,
    area_vector: Vector3<f64>,
    children: Option<[usize; 2]>,
    first: usize,
    count: usize,
}

/// A cluster tree over one mesh's triangles for fast winding numbers.
#[derive(Debug, Clone)]
pub(super) struct WindingTree {
    triangles: Vec<[Point3<f64>; 3]>,
    clusters: Vec<Cluster>,
}

impl WindingTree {
    /// Builds the tree (median split along the longest axis of the centroids; ties by index,
    /// so the result is deterministic).
    pub(super) fn new(mesh: &TriMesh) -> WindingTree {
        let all: Vec<[Point3<f64>; 3]> = (0..mesh.triangles.len())
            .map(|i| mesh.triangle(i))
            .collect();
        let mut order: Vec<usize> = (0..all.len()).collect();
        let mut clusters = Vec::new();
        if !all.is_empty() {
            build(&all, &mut order, 0, &mut clusters);
        }
        let triangles = order.iter().map(|&i| all[i]).collect();
        WindingTree {
            triangles,
            clusters,
        }
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
            } else if let Some([left, right]) = cluster.children {
                stack.push(right);
                stack.push(left);
            } else {
                total += self.triangles[cluster.first..cluster.first + cluster.count]
                    .iter()
                    .map(|tri| solid_angle(tri, p))
                    .sum::<f64>();
            }
        }
        total / (4.0 * std::f64::consts::PI)
    }
}

/// Builds the cluster over `order[start..start + slice.len()]`, children first-in-order, and
/// returns its index. Leaves refer to positions in `order` (the final triangle order).
fn build(
    all: &[[Point3<f64>; 3]],
    order: &mut [usize],
    start: usize,
    clusters: &mut Vec<Cluster>,
) -> usize {
    let mut area_vector = Vector3::zeros();
    let mut weighted = Vector3::zeros();
    let mut total_area = 0.0;
    let mut lo = Point3::from(Vector3::repeat(f64::INFINITY));
    let mut hi = Point3::from(Vector3::repeat(f64::NEG_INFINITY));
    for &i in order.iter() {
        let [a, b, c] = all[i];
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
    let radius = order
        .iter()
        .flat_map(|&i| all[i])
        .map(|v| (v - centre).norm())
        .fold(0.0, f64::max);
    let index = clusters.len();
    clusters.push(Cluster {
        centre,
        radius,
        area_vector,
        children: None,
        first: start,
        count: order.len(),
    });
    if order.len() > LEAF_SIZE {
        let extent = hi - lo;
        let axis = extent.imax();
        let key = |i: usize| all[i].iter().map(|v| v[axis]).sum::<f64>();
        let middle = order.len() / 2;
        order.select_nth_unstable_by(middle, |&x, &y| key(x).total_cmp(&key(y)).then(x.cmp(&y)));
        let (left_order, right_order) = order.split_at_mut(middle);
        let left = build(all, left_order, start, clusters);
        let right = build(all, right_order, start + middle, clusters);
        clusters[index].children = Some([left, right]);
    }
    index
}
