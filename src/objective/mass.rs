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

impl<D: Scalar> CapsuleVars<D> {
    /// The capsule of `component` whose unknowns are `x[0..CAPSULE_STRIDE]`.
    pub fn at(x: &[D], component: usize) -> CapsuleVars<D> {
        CapsuleVars {
            p: V3::from_slice(&x[P..]),
            q: V3::from_slice(&x[Q..]),
            r: x[R].clone(),
            component,
        }
    }
}

/// The capsules of `x` laid out by `layout`; `x` must have `layout.len()` entries.
pub(crate) fn capsules<D: Scalar>(layout: &DesignLayout, x: &[D]) -> Vec<CapsuleVars<D>> {
    layout
        .components
        .iter()
        .enumerate()
        .map(|(j, &component)| CapsuleVars::at(&x[j * CAPSULE_STRIDE..], component))
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
    let mut sums = material(setup, capsules, infill, densities);
    for capsule in capsules {
        if capsule.component >= setup.printed.len() {
            continue;
        }
        let frame = setup.frame(capsule.component);
        let ball_mass = ball_mass(&capsule.r, densities);
        let gravity = setup.gravity_in(capsule.component);
        let ball =
            ball_centre(capsule, &gravity, densities.clearance, sharpness).transformed(&frame);
        sums.add(&ball_mass, &ball);
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

/// The material of a posed design without its balls: every body's solid part at the material's
/// density and its sparse part at `infill ×` that, changed by each capsule and its shell (see
/// [`totals`]; capsules of components without a body left out).
pub(crate) fn material<D: Scalar>(
    setup: &PoseSetup,
    capsules: &[CapsuleVars<D>],
    infill: &D,
    densities: Densities,
) -> Sums<D> {
    let mut sums = bodies(setup, infill, densities);
    for capsule in capsules {
        if capsule.component >= setup.printed.len() {
            continue;
        }
        let (change, middle) = void(capsule, &setup.frame(capsule.component), infill, densities);
        sums.add(&change, &middle);
    }
    sums
}

/// Every body of `setup`: its solid part at the material's density, its sparse part at
/// `infill ×` that.
fn bodies<D: Scalar>(setup: &PoseSetup, infill: &D, densities: Densities) -> Sums<D> {
    let mut sums = Sums {
        mass: D::from(0.0),
        moment: V3::constant(&Vector3::zeros()),
        magnitude: 0.0,
    };
    for [(solid, solid_centre), (sparse, sparse_centre)] in &setup.printed {
        sums.add(
            &D::from(densities.material * *solid),
            &V3::constant(&solid_centre.coords),
        );
        sums.add(
            &(infill.clone() * (densities.material * *sparse)),
            &V3::constant(&sparse_centre.coords),
        );
    }
    sums
}

/// The mass a capsule's void and its shell change, `((1 − infill) πR²(L + 4/3 R) − πr²(L + 4/3 r))`
/// of material density with `R = r + t` (`t` the shell) and `L = |q − p|`, and where it acts (the
/// axis midpoint), world.
fn void<D: Scalar>(
    capsule: &CapsuleVars<D>,
    frame: &Isometry3<f64>,
    infill: &D,
    densities: Densities,
) -> (D, V3<D>) {
    let pi = std::f64::consts::PI;
    let volume =
        |length: &D, r: &D| r.clone() * r * pi * (length.clone() + r.clone() * (4.0 / 3.0));
    let r = &capsule.r;
    let length = capsule.q.sub(&capsule.p).norm();
    let dilated = volume(&length, &(r.clone() + densities.shell));
    let void = volume(&length, r);
    let change = ((-infill.clone() + 1.0) * dilated - void) * densities.material;
    let middle = capsule.p.add(&capsule.q).scale_by(0.5).transformed(frame);
    (change, middle)
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
