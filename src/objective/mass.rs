//! Smooth mass properties of a posed design (paper eq. 7-13 with the ball of eq. 19-21).

use nalgebra::{Isometry3, Vector3};

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

/// Mass and centre of mass (eq. 12-13): material of density `infill × material` over every
/// body, less each capsule's void (`πr²(|q − p| + 4/3 r)` at the axis midpoint), plus each ball
/// (`4/3 πb³` of ball density at [`ball_centre`]). Capsules whose component has no body are left
/// out, as in the exact evaluation. When the mass cancels, the centre is the setup's fallback.
pub(crate) fn totals<D: Scalar>(
    setup: &PoseSetup,
    capsules: &[CapsuleVars<D>],
    infill: &D,
    densities: Densities,
    sharpness: f64,
) -> SmoothTotals<D> {
    let material = infill.clone() * densities.material;
    let mut sums = bodies(setup, &material);
    for capsule in capsules {
        if capsule.component >= setup.bodies.len() {
            continue;
        }
        let frame = setup.frame(capsule.component);
        let (void_mass, middle) = void(capsule, &frame, &material);
        let ball_mass = ball_mass(&capsule.r, densities);
        let gravity = setup.gravity_in(capsule.component);
        let ball =
            ball_centre(capsule, &gravity, densities.clearance, sharpness).transformed(&frame);
        sums.magnitude += void_mass.re().abs() + ball_mass.re().abs();
        sums.moment = sums
            .moment
            .add(&middle.scale(&void_mass))
            .add(&ball.scale(&ball_mass));
        sums.mass += void_mass + ball_mass;
    }
    SmoothTotals {
        centre: sums.centre(setup),
        mass: sums.mass,
    }
}

/// Mass of the ball of a capsule of radius `r`, grams: `4/3 πb³` of ball density.
pub(crate) fn ball_mass<D: Scalar>(r: &D, densities: Densities) -> D {
    let pi = std::f64::consts::PI;
    ball_radius(r, densities.clearance).powi(3) * (4.0 / 3.0 * pi * densities.ball)
}

/// The material of a posed design without its balls: every body at `infill × material`, less
/// each capsule's void at its axis midpoint (capsules of components without a body left out).
pub(crate) fn material<D: Scalar>(
    setup: &PoseSetup,
    capsules: &[CapsuleVars<D>],
    infill: &D,
    densities: Densities,
) -> Sums<D> {
    let material = infill.clone() * densities.material;
    let mut sums = bodies(setup, &material);
    for capsule in capsules {
        if capsule.component >= setup.bodies.len() {
            continue;
        }
        let (void_mass, middle) = void(capsule, &setup.frame(capsule.component), &material);
        sums.add(&void_mass, &middle);
    }
    sums
}

/// Every body of `setup` at `density` (grams per cubic unit).
fn bodies<D: Scalar>(setup: &PoseSetup, density: &D) -> Sums<D> {
    let mut sums = Sums {
        mass: D::from(0.0),
        moment: V3::constant(&Vector3::zeros()),
        magnitude: 0.0,
    };
    for (volume, centroid) in &setup.bodies {
        sums.add(
            &(density.clone() * *volume),
            &V3::constant(&centroid.coords),
        );
    }
    sums
}

/// The (negative) mass of the material a capsule's void removes, `density × πr²(|q − p| + 4/3 r)`,
/// and the void's centre (axis midpoint), world.
fn void<D: Scalar>(capsule: &CapsuleVars<D>, frame: &Isometry3<f64>, density: &D) -> (D, V3<D>) {
    let pi = std::f64::consts::PI;
    let r = &capsule.r;
    let length = capsule.q.sub(&capsule.p).norm();
    let void = r.clone() * r * pi * (length + r.clone() * (4.0 / 3.0));
    let middle = capsule.p.add(&capsule.q).scale_by(0.5).transformed(frame);
    (-(density.clone() * void), middle)
}

/// A running sum of masses at points, world.
#[derive(Debug, Clone)]
pub(crate) struct Sums<D> {
    /// Σ m, grams.
    pub mass: D,
    /// Σ m·x.
    pub moment: V3<D>,
    /// Σ |m| of the values, to tell a total that cancelled from one that is merely small.
    magnitude: f64,
}

impl<D: Scalar> Sums<D> {
    /// Adds `mass` at `at`.
    pub fn add(&mut self, mass: &D, at: &V3<D>) {
        self.magnitude += mass.re().abs();
        self.moment = self.moment.add(&at.scale(mass));
        self.mass += mass.clone();
    }

    /// The centre of mass, or the setup's fallback when the mass cancels.
    pub fn centre(&self, setup: &PoseSetup) -> V3<D> {
        let cancelled = self.mass.re().abs() <= 1e-12 * self.magnitude || self.mass.re() == 0.0;
        if cancelled {
            V3::constant(&setup.fallback_centre.coords)
        } else {
            self.moment.scale(&self.mass.recip())
        }
    }
}
