//! Eq. 15's distance field from one signed distance grid per component.

use std::sync::Arc;

use nalgebra::{Point3, Vector3};

use super::interior::InteriorDistance;
use crate::geometry::DistanceGrid;

/// One [`DistanceGrid`] per component, in component order, as an [`InteriorDistance`].
#[derive(Debug, Clone)]
pub struct GridInterior {
    /// The grids, indexed by component; shared, since one grid serves many optimizations.
    pub grids: Vec<Arc<DistanceGrid>>,
}

impl InteriorDistance for GridInterior {
    /// The negated grid interpolant (the grid is negative inside, the trait positive inside) and
    /// its exact gradient. A component without a grid is everywhere outside: `−∞`, zero gradient.
    fn distance(&self, component: usize, point: &Point3<f64>) -> (f64, Vector3<f64>) {
        match self.grids.get(component) {
            Some(grid) => {
                let (value, gradient) = grid.value_and_gradient(point);
                (-value, -gradient)
            }
            None => (f64::NEG_INFINITY, Vector3::zeros()),
        }
    }
}

impl InteriorDistance for Arc<GridInterior> {
    /// As for the shared [`GridInterior`].
    fn distance(&self, component: usize, point: &Point3<f64>) -> (f64, Vector3<f64>) {
        self.as_ref().distance(component, point)
    }
}
