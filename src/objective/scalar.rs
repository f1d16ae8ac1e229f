//! The numbers the objective is evaluated in (`f64`, or a dual number carrying a gradient) and a
//! 3-vector of them.

use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, Dim, Dyn, Isometry3, Vector3, U1};
use num_dual::{Derivative, DualNum, DualVec};

/// A scalar the smooth objective can be evaluated in: `f64` for values, a `num_dual` dual number
/// for exact gradients.
pub trait Scalar: DualNum<Primitive = f64> + Clone {}

impl<T: DualNum<Primitive = f64> + Clone> Scalar for T {}

/// A computation that runs in any [`Scalar`], as [`with_gradients`] evaluates it.
pub(crate) trait Evaluate {
    /// The outputs at `x`.
    fn evaluate<D: Scalar>(&self, x: &[D]) -> Vec<D>;
}

/// Each output of `f` at `x` with its gradient (length `x.len()`): `f` evaluated once in dual
/// numbers seeded with the unit derivatives (entry `i` carries `∂/∂x_i = 1`).
///
/// Up to 64 unknowns the dual numbers have a fixed width (the least of 8, 16, 24, 32, 48 and 64
/// that holds them, the derivatives past `x.len()` zero), so their arithmetic keeps the derivatives on
/// the stack instead of allocating a vector for every intermediate; past that, vectors of
/// `x.len()`. Every derivative is computed by the same operations whatever the width, so the
/// results are the same bits.
pub(crate) fn with_gradients(x: &[f64], f: &impl Evaluate) -> Vec<(f64, Vec<f64>)> {
    match x.len() {
        0..=8 => in_width(x, Const::<8>, f),
        9..=16 => in_width(x, Const::<16>, f),
        17..=24 => in_width(x, Const::<24>, f),
        25..=32 => in_width(x, Const::<32>, f),
        33..=48 => in_width(x, Const::<48>, f),
        49..=64 => in_width(x, Const::<64>, f),
        _ => in_width(x, Dyn(x.len()), f),
    }
}

/// [`with_gradients`] in dual numbers of `width` derivatives (at least `x.len()`; those past it
/// are never seeded and are dropped).
fn in_width<W: Dim>(x: &[f64], width: W, f: &impl Evaluate) -> Vec<(f64, Vec<f64>)>
where
    DefaultAllocator: Allocator<W>,
    DualVec<f64, W>: Scalar,
{
    let duals: Vec<DualVec<f64, W>> = x
        .iter()
        .enumerate()
        .map(|(i, &xi)| DualVec::new(xi, Derivative::derivative_generic(width, U1, i)))
        .collect();
    f.evaluate(&duals)
        .into_iter()
        .map(|value| {
            let gradient = value.eps.unwrap_generic(width, U1);
            (value.re, gradient.iter().take(x.len()).copied().collect())
        })
        .collect()
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A function of every kind of operation the objective uses, of five unknowns.
    struct Mixed;

    impl Evaluate for Mixed {
        fn evaluate<D: Scalar>(&self, x: &[D]) -> Vec<D> {
            let v = V3::from_slice(x);
            let w = V3([x[3].clone(), x[4].clone(), x[0].clone() * 0.5]);
            let norm = v.sub(&w).norm();
            vec![
                norm.clone() / (x[1].clone() * x[1].clone() + 1.0),
                (x[2].clone() - x[4].clone()).exp() + x[0].clone().atan2(x[3].clone()),
                D::from(2.0),
                v.cross_constant(&Vector3::new(0.3, -1.2, 2.0))
                    .dot(&w)
                    .sqrt(),
            ]
        }
    }

    #[test]
    fn every_width_gives_the_same_bits() {
        let x = [0.7, -1.3, 0.25, 2.5, -0.4];
        let bits = |results: Vec<(f64, Vec<f64>)>| -> Vec<(u64, Vec<u64>)> {
            results
                .into_iter()
                .map(|(v, g)| (v.to_bits(), g.iter().map(|d| d.to_bits()).collect()))
                .collect()
        };
        let reference = bits(in_width(&x, Dyn(x.len()), &Mixed));
        assert_eq!(reference.len(), 4);
        assert!(reference.iter().all(|(_, g)| g.len() == x.len()));
        assert_eq!(bits(in_width(&x, Const::<8>, &Mixed)), reference);
        assert_eq!(bits(in_width(&x, Const::<16>, &Mixed)), reference);
        assert_eq!(bits(in_width(&x, Const::<24>, &Mixed)), reference);
        assert_eq!(bits(in_width(&x, Const::<32>, &Mixed)), reference);
        assert_eq!(bits(in_width(&x, Const::<48>, &Mixed)), reference);
        assert_eq!(bits(in_width(&x, Const::<64>, &Mixed)), reference);
        assert_eq!(bits(with_gradients(&x, &Mixed)), reference);
        // A constant output has a zero gradient.
        assert!(reference[2].1.iter().all(|&d| d == 0));
    }
}
