//! Smooth stand-ins for the non-smooth functions of the objective: maximum, minimum, step and
//! angle.

use nalgebra::Vector3;

use super::scalar::{Scalar, V3};

/// The log-sum-exp smooth maximum `m + ln Σ exp(s (vᵢ − m)) / s`, with `m` the largest value
/// (the shift keeps the exponentials in range for any sharpness `s`).
///
/// It bounds the true maximum from above and exceeds it by at most `ln(n) / s` for `n` values,
/// so it tends to the maximum as `s` grows. Every value gets a positive weight in the gradient
/// (the weights are a softmax and sum to 1). An empty list gives 0; a sharpness that is not
/// positive and finite, or an infinite largest value, gives the plain maximum.
pub fn smooth_max<D: Scalar>(values: &[D], sharpness: f64) -> D {
    let Some(largest) = values
        .iter()
        .reduce(|a, b| if b.re() > a.re() { b } else { a })
    else {
        return D::from(0.0);
    };
    // An infinite largest value is the maximum (shifting by it would give ∞ − ∞ = NaN).
    if !(sharpness > 0.0 && sharpness.is_finite()) || largest.re().is_infinite() {
        return largest.clone();
    }
    let shift = largest.re();
    let sum: D = values
        .iter()
        .map(|v| ((v.clone() - shift) * sharpness).exp())
        .sum();
    sum.ln() / sharpness + shift
}

/// The smooth minimum `−smooth_max(−v, s)`: at most the true minimum, by at most `ln(n) / s`.
pub fn smooth_min<D: Scalar>(values: &[D], sharpness: f64) -> D {
    let negated: Vec<D> = values.iter().map(|v| -v.clone()).collect();
    -smooth_max(&negated, sharpness)
}

/// The logistic function `1 / (1 + e^(−t))`, evaluated without overflow for any `t`.
pub(crate) fn sigmoid<D: Scalar>(t: D) -> D {
    if t.re() >= 0.0 {
        ((-t).exp() + 1.0).recip()
    } else {
        let e = t.exp();
        e.clone() / (e + 1.0)
    }
}

/// `atan2(y, x)`, with a zero derivative at the origin (where it has none) instead of NaN.
pub(crate) fn atan2<D: Scalar>(y: D, x: D) -> D {
    let r2 = y.re() * y.re() + x.re() * x.re();
    if r2 >= f64::MIN_POSITIVE {
        y.atan2(x)
    } else {
        D::from(y.re().atan2(x.re()))
    }
}

/// `√(t² + ε²)`: `|t|` rounded off over `|t| ≲ ε`.
pub(crate) fn soft_abs<D: Scalar>(t: D, epsilon: f64) -> D {
    (t.clone() * t + epsilon * epsilon).sqrt()
}

/// The angle between `v` and the unit vector `direction`, radians in [0, π], as
/// `atan2(√(|v × d|² + ε²), v·d)`.
///
/// The `ε` (a length, positive) rounds off the cone point where `v` is parallel to `direction`:
/// there `arccos` and the plain `atan2` form both have an unbounded derivative. The angle is off by
/// at most `ε / |v|` radians, and is π/2 (neutral, as the exact evaluation reports) when `v = 0`.
pub(crate) fn angle_to<D: Scalar>(v: &V3<D>, direction: &Vector3<f64>, epsilon: f64) -> D {
    let across = v.cross_constant(direction).norm_squared() + epsilon * epsilon;
    let sine = if across.re() > 0.0 {
        across.sqrt()
    } else {
        D::from(0.0)
    };
    atan2(sine, v.dot_constant(direction))
}
