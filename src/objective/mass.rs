//! Smooth mass properties of a posed design (paper eq. 7-13 with the ball of eq. 19-21).

use nalgebra::Vector3;

use super::layout::{DesignLayout, CAPSULE_STRIDE, P, Q, R};
use super::scalar::{Scalar, V3};
use super::setup::PoseSetup;
use super::smooth::sigmoid;

/// One capsule's variables.
#[derive(Debug, Clone)]
pub(crate) struct CapsuleVars<D> {
    /// The `from` end, rest frame of the component.
    pub p: V3<D>,
    /// The `to` end.
    pub q: V3<D>,
    /// The void radius.
    pub r: D,
    /// The component holding it.
    pub component: usize,
}

/// The capsules of `x` laid out by `layout`; `x` must have `layout.len()` entries.
pub(crate) fn capsules<D: Scalar>(layout: &DesignLayout, x: &[D]) -> Vec<CapsuleVars<D>> {
    layout
        .components
        .iter()
        .enumerate()
        .map(|(j, &component)| {
            let base = j * CAPSULE_STRIDE;
            CapsuleVars {
                p: V3::from_slice(&x[base + P..]),
                q: V3::from_slice(&x[base + Q..]),
                r: x[base + R].clone(),
                component,
            }
        })
        .collect()
}

/// The densities the mass sums need.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Densities {
    /// Printed material at full infill, g per cubic project unit.
    pub material: f64,
    /// Balls, g per cubic project unit.
    pub ball: f64,
    /// Ball clearance, project units.
    pub clearance: f64,
    /// Thickness of the solid shell printed around every capsule, project units
    /// ([`capsule_shell`](crate::balance::capsule_shell)).
    pub shell: f64,
}

/// Mass (grams) and centre of mass (world) of a posed design.
#[derive(Debug, Clone)]
pub(crate) struct SmoothTotals<D> {
    /// Grams.
    pub mass: D,
    /// World.
    pub centre: V3<D>,
}

/// `z` of eq. 20: the cosine between the capsule axis and `gravity` (unit, component frame);
/// 0 for a zero-length axis.
pub(crate) fn axis_cosine<D: Scalar>(capsule: &CapsuleVars<D>, gravity: &Vector3<f64>) -> D {
    let axis = capsule.q.sub(&capsule.p);
    let length = axis.norm();
    if length.re() > 0.0 {
        axis.dot_constant(gravity) / length
    } else {
        D::from(0.0)
    }
}

/// The ball's centre in its component's rest frame (eq. 19 with the sigmoid of eq. 21):
/// `(1 − κ) p + κ q + (r − b) g` with `κ = σ(γ z)`. The last term lets the ball rest against the
/// bottom of the end cap, as the exact evaluation places it; `r − b` is the clearance (the whole
/// radius when the capsule is narrower than the clearance).
pub(crate) fn ball_centre<D: Scalar>(
    capsule: &CapsuleVars<D>,
    gravity: &Vector3<f64>,
    clearance: f64,
    sharpness: f64,
) -> V3<D> {
    let kappa = sigmoid(axis_cosine(capsule, gravity) * sharpness);
    let drop = if capsule.r.re() > clearance {
        D::from(clearance)
    } else {
        capsule.r.clone()
    };
    capsule
        .p
        .add(&capsule.q.sub(&capsule.p).scale(&kappa))
        .add(&V3::constant(gravity).scale(&drop))
}

/// The ball radius `b = r − clearance`, 0 when the capsule is no wider than the clearance.
pub(crate) fn ball_radius<D: Scalar>(r: &D, clearance: f64) -> D {
    if r.re() > clearance {
        r.clone() - clearance
    } else {
        D::from(0.0)
    }
}

/// Mass and centre of mass (eq. 12-13), as the exact evaluation sums them: each body's solid
/// part at the material's density and its sparse part at `infill ×` that; per capsule, the
/// capsule dilated by the shell thickness `t` loses its sparse material and gains its shell solid,
/// `(1 − infill) πR²(L + 4/3 R) − πr²(L + 4/3 r)` with `R = r + t` and `L = |q − p|`, at the axis
/// midpoint, and the ball (`4/3 πb³` of ball density at [`ball_centre`]) is added. Capsules
/// whose component has no body are left out. When the mass cancels, the centre is the setup's
/// fallback.
pub(crate) fn totals<D: Scalar>(
    setup: &PoseSetup,
    capsules: &[CapsuleVars<D>],
    infill: &D,
    densities: Densities,
    sharpness: f64,
) -> SmoothTotals<D> {
    let pi = std::f64::consts::PI;
    let mut mass = D::from(0.0);
    let mut moment = V3::constant(&Vector3::zeros());
    let mut magnitude = 0.0;
    for [(solid, solid_centre), (sparse, sparse_centre)] in &setup.printed {
        let solid_mass = D::from(densities.material * *solid);
        let sparse_mass = infill.clone() * (densities.material * *sparse);
        magnitude += solid_mass.re().abs() + sparse_mass.re().abs();
        moment = moment
            .add(&V3::constant(&solid_centre.coords).scale(&solid_mass))
            .add(&V3::constant(&sparse_centre.coords).scale(&sparse_mass));
        mass += solid_mass + sparse_mass;
    }
    let capsule_volume =
        |length: &D, r: &D| r.clone() * r * pi * (length.clone() + r.clone() * (4.0 / 3.0));
    for capsule in capsules {
        if capsule.component >= setup.printed.len() {
            continue;
        }
        let frame = setup.frame(capsule.component);
        let r = &capsule.r;
        let length = capsule.q.sub(&capsule.p).norm();
        let dilated = capsule_volume(&length, &(r.clone() + densities.shell));
        let void = capsule_volume(&length, r);
        let change = ((-infill.clone() + 1.0) * dilated - void) * densities.material;
        let middle = capsule.p.add(&capsule.q).scale_by(0.5).transformed(&frame);
        let b = ball_radius(r, densities.clearance);
        let ball_mass = b.powi(3) * (4.0 / 3.0 * pi * densities.ball);
        let gravity = setup.gravity_in(capsule.component);
        let ball =
            ball_centre(capsule, &gravity, densities.clearance, sharpness).transformed(&frame);
        magnitude += change.re().abs() + ball_mass.re().abs();
        moment = moment
            .add(&middle.scale(&change))
            .add(&ball.scale(&ball_mass));
        mass += change + ball_mass;
    }
    let cancelled = mass.re().abs() <= 1e-12 * magnitude || mass.re() == 0.0;
    let centre = if cancelled {
        V3::constant(&setup.fallback_centre.coords)
    } else {
        moment.scale(&mass.recip())
    };
    SmoothTotals { mass, centre }
}
