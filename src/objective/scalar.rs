//! The numbers the objective is evaluated in (`f64`, or a dual number carrying a gradient) and a
//! 3-vector of them.

use nalgebra::{Isometry3, Vector3};
use num_dual::{Derivative, DualDVec64, DualNum};

/// A scalar the smooth objective can be evaluated in: `f64` for values, a `num_dual` dual number
/// for exact gradients.
pub trait Scalar: DualNum<Primitive = f64> + Clone {}

impl<T: DualNum<Primitive = f64> + Clone> Scalar for T {}

/// `x` as dual numbers seeded with the unit derivatives: entry `i` carries `∂/∂x_i = 1`.
pub(crate) fn seeded(x: &[f64]) -> Vec<DualDVec64> {
    let n = nalgebra::Dyn(x.len());
    x.iter()
        .enumerate()
        .map(|(i, &xi)| DualDVec64::new(xi, Derivative::derivative_generic(n, nalgebra::U1, i)))
        .collect()
}

/// The value and gradient (length `n`) of a dual number computed from [`seeded`] variables.
pub(crate) fn split(value: DualDVec64, n: usize) -> (f64, Vec<f64>) {
    let gradient = value
        .eps
        .unwrap_generic(nalgebra::Dyn(n), nalgebra::U1)
        .iter()
        .copied()
        .collect();
    (value.re, gradient)
}

/// A 3-vector of [`Scalar`]s: `[x, y, z]`.
#[derive(Debug, Clone)]
pub(crate) struct V3<D>(pub [D; 3]);

impl<D: Scalar> V3<D> {
    /// A constant vector.
    pub fn constant(v: &Vector3<f64>) -> Self {
        V3([D::from(v.x), D::from(v.y), D::from(v.z)])
    }

    /// The vector `x[0..3]`.
    pub fn from_slice(x: &[D]) -> Self {
        V3([x[0].clone(), x[1].clone(), x[2].clone()])
    }

    /// The real part.
    pub fn re(&self) -> Vector3<f64> {
        Vector3::new(self.0[0].re(), self.0[1].re(), self.0[2].re())
    }

    /// `self + other`.
    pub fn add(&self, other: &Self) -> Self {
        V3(std::array::from_fn(|i| self.0[i].clone() + &other.0[i]))
    }

    /// `self − other`.
    pub fn sub(&self, other: &Self) -> Self {
        V3(std::array::from_fn(|i| self.0[i].clone() - &other.0[i]))
    }

    /// `self − v` for a constant `v`.
    pub fn sub_constant(&self, v: &Vector3<f64>) -> Self {
        V3(std::array::from_fn(|i| self.0[i].clone() - v[i]))
    }

    /// `s · self`.
    pub fn scale(&self, s: &D) -> Self {
        V3(std::array::from_fn(|i| self.0[i].clone() * s))
    }

    /// `s · self` for a constant `s`.
    pub fn scale_by(&self, s: f64) -> Self {
        V3(std::array::from_fn(|i| self.0[i].clone() * s))
    }

    /// `self · other`.
    pub fn dot(&self, other: &Self) -> D {
        self.0[0].clone() * &other.0[0]
            + self.0[1].clone() * &other.0[1]
            + self.0[2].clone() * &other.0[2]
    }

    /// `self · v` for a constant `v`.
    pub fn dot_constant(&self, v: &Vector3<f64>) -> D {
        self.0[0].clone() * v.x + self.0[1].clone() * v.y + self.0[2].clone() * v.z
    }

    /// `self × v` for a constant `v`.
    pub fn cross_constant(&self, v: &Vector3<f64>) -> Self {
        let [x, y, z] = &self.0;
        V3([
            y.clone() * v.z - z.clone() * v.y,
            z.clone() * v.x - x.clone() * v.z,
            x.clone() * v.y - y.clone() * v.x,
        ])
    }

    /// `|self|²`.
    pub fn norm_squared(&self) -> D {
        self.dot(self)
    }

    /// `|self|`, with a zero derivative where the vector is exactly zero (the norm has none there).
    pub fn norm(&self) -> D {
        let squared = self.norm_squared();
        if squared.re() > 0.0 {
            squared.sqrt()
        } else {
            D::from(0.0)
        }
    }

    /// The point `self` moved by the rigid transform `frame`.
    pub fn transformed(&self, frame: &Isometry3<f64>) -> Self {
        let rotated = self.rotated(frame);
        let t = frame.translation.vector;
        V3(std::array::from_fn(|i| rotated.0[i].clone() + t[i]))
    }

    /// The direction `self` turned by the rotation of `frame`.
    pub fn rotated(&self, frame: &Isometry3<f64>) -> Self {
        let r = frame.rotation.to_rotation_matrix();
        let m = r.matrix();
        V3(std::array::from_fn(|i| {
            self.0[0].clone() * m[(i, 0)]
                + self.0[1].clone() * m[(i, 1)]
                + self.0[2].clone() * m[(i, 2)]
        }))
    }
}
