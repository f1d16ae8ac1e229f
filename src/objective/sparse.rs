//! The constraints that read the unknowns of one capsule, or of two, with their gradients from
//! dual numbers of those unknowns alone: 7 or 14 derivatives carried through each operation
//! instead of the whole design's (48 for the T's six capsules), scattered into gradients of the
//! design's length. Each derivative is computed by the same operations on the same values as
//! in dual numbers of every unknown, so the values and the derivatives the constraint has are
//! the same bits; the derivatives it does not have are zeros.

use super::constraints::{capsule_constraints, insertion_constraint, pair_constraints};
use super::layout::CAPSULE_STRIDE;
use super::mass::CapsuleVars;
use super::scalar::{with_gradients, Evaluate, Scalar};
use super::Objective;

/// The unknowns of design capsule `j`, in the design vector.
fn unknowns(j: usize) -> std::ops::Range<usize> {
    j * CAPSULE_STRIDE..(j + 1) * CAPSULE_STRIDE
}

/// Each output of `f` evaluated at the entries `indices` of `x`, with its gradient over all of
/// `x` (zero but at `indices`).
fn scattered(x: &[f64], indices: &[usize], f: &impl Evaluate) -> Vec<(f64, Vec<f64>)> {
    let local: Vec<f64> = indices.iter().map(|&i| x[i]).collect();
    with_gradients(&local, f)
        .into_iter()
        .map(|(value, local)| {
            let mut gradient = vec![0.0; x.len()];
            for (&i, d) in indices.iter().zip(local) {
                gradient[i] = d;
            }
            (value, gradient)
        })
        .collect()
}

/// Constraints 1 of [`Objective::constraints`], capsule by capsule.
pub(super) fn capsule_gradients(objective: &Objective, x: &[f64]) -> Vec<(f64, Vec<f64>)> {
    /// One capsule's constraints, from its unknowns.
    struct One<'a>(&'a Objective, usize);
    impl Evaluate for One<'_> {
        fn evaluate<D: Scalar>(&self, x: &[D]) -> Vec<D> {
            let mut out = Vec::new();
            let capsule = CapsuleVars::at(x, self.1);
            capsule_constraints(&[capsule], &self.0.poses, &self.0.limits, &mut out);
            out
        }
    }
    let mut out = Vec::new();
    for (j, &component) in objective.layout.components.iter().enumerate() {
        let at: Vec<usize> = unknowns(j).collect();
        out.extend(scattered(x, &at, &One(objective, component)));
    }
    out
}

/// Constraints 2 of [`Objective::constraints`], pair by pair in the same order.
pub(super) fn pair_gradients(objective: &Objective, x: &[f64]) -> Vec<(f64, Vec<f64>)> {
    /// One pair's constraint, from the two capsules' unknowns one after the other.
    struct Two<'a>(&'a Objective, usize);
    impl Evaluate for Two<'_> {
        fn evaluate<D: Scalar>(&self, x: &[D]) -> Vec<D> {
            let mut out = Vec::new();
            let pair = [
                CapsuleVars::at(x, self.1),
                CapsuleVars::at(&x[CAPSULE_STRIDE..], self.1),
            ];
            pair_constraints(&pair, &self.0.limits, &mut out);
            out
        }
    }
    let components = &objective.layout.components;
    let mut out = Vec::new();
    for (i, &a) in components.iter().enumerate() {
        for (j, &b) in components.iter().enumerate().skip(i + 1) {
            if a != b {
                continue;
            }
            let at: Vec<usize> = unknowns(i).chain(unknowns(j)).collect();
            out.extend(scattered(x, &at, &Two(objective, a)));
        }
    }
    out
}

/// Constraints 6 of [`Objective::constraints`] (none without an insertion), capsule by capsule.
pub(super) fn insertion_gradients(objective: &Objective, x: &[f64]) -> Vec<(f64, Vec<f64>)> {
    /// One capsule's insertion constraint, from its unknowns.
    struct One<'a>(&'a super::Insertion, usize, nalgebra::Vector3<f64>);
    impl Evaluate for One<'_> {
        fn evaluate<D: Scalar>(&self, x: &[D]) -> Vec<D> {
            vec![insertion_constraint(
                &CapsuleVars::at(x, self.1),
                &self.2,
                self.0,
            )]
        }
    }
    let Some(insertion) = &objective.insertion else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (j, (&component, up)) in objective
        .layout
        .components
        .iter()
        .zip(&insertion.up)
        .enumerate()
    {
        if let Some(up) = up {
            let at: Vec<usize> = unknowns(j).collect();
            out.extend(scattered(x, &at, &One(insertion, component, *up)));
        }
    }
    out
}
