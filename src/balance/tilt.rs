//! The tilt margin with rolling balls: the smallest tilt of the ground, in any direction, at which
//! the posed model's state changes (a standing model topples, a toppling one comes to stand), every
//! ball rolling to the end of its capsule that the tilted gravity sends it to as the tilt grows.
//!
//! # The model
//!
//! The ground tilts by `θ` so that it descends towards the horizontal unit vector `d`; seen from
//! the model, which rests on its support without sliding, gravity turns to
//! `g(θ) = −cos θ·up + sin θ·d`. The tilt grows slowly (quasi-static): at every `θ` each ball rests
//! at the end of its axis `a` that `g` points to (`to` when `a·g > 0`), against the bottom of that
//! end's cap (`end + (r − b)·g`). A ball changes end once at most per direction, where
//! `a·g(θ) = 0`, i.e. at `tan θ = (a·up)/(a·d)`. The model stands at `θ` while the line through the
//! centre of mass along `g` meets the ground strictly inside the support polygon: at
//! `c⊥ + h tan θ·d`, with `c⊥` the centre's foot and `h` its height above the ground.
//!
//! The margin in direction `d` is the first `θ` in `[0°, 90°]` at which that verdict differs from
//! the one at `θ = 0`. The tilt margin is its minimum over every direction: positive, the smallest
//! tilt that topples the model; negative, minus the smallest tilt that would make a toppling model
//! stand. With the balls held still this is the classic minimum over the polygon's edges of
//! `atan2(−distance, h)`; a rolling ball can only lower a standing model's margin where it moves
//! before the model topples.
//!
//! The minimum over directions is found by evaluating every two degrees of azimuth and every edge
//! normal and capsule axis direction, then refining the lowest candidates by golden-section search
//! within one sample spacing, to about 10⁻⁶ degrees.

use nalgebra::{Point3, Vector2, Vector3};

use super::support::GroundPlane;
use super::BallRest;

/// A ball free to roll along its capsule's axis, world frame.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RollingBall {
    /// The capsule's `from` end of the axis, world.
    pub from: Point3<f64>,
    /// The capsule's `to` end of the axis, world.
    pub to: Point3<f64>,
    /// How far the ball's centre sits below the end point along gravity: capsule radius less ball
    /// radius.
    pub drop: f64,
    /// Grams.
    pub mass: f64,
}

/// The posed model on its support, as the tilt sees it.
pub(crate) struct TiltedModel<'a> {
    /// The ground's frame.
    pub plane: &'a GroundPlane,
    /// Height of the ground along up.
    pub ground: f64,
    /// The support polygon, counter-clockwise in the plane's coordinates, at least three points
    /// with no three collinear.
    pub polygon: &'a [Vector2<f64>],
    /// Mass of everything but the balls, grams.
    pub fixed_mass: f64,
    /// Σ m·x of everything but the balls, gram · project units, world.
    pub fixed_moment: Vector3<f64>,
    /// The balls that roll.
    pub balls: &'a [RollingBall],
}

/// A ball changing end while the ground tilts.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Move {
    /// Index of the ball in [`TiltedModel::balls`].
    pub ball: usize,
    /// The tilt at which it rolls, degrees.
    pub tilt: f64,
    /// The end it rolls to.
    pub to: BallRest,
}

/// The worst tilt of one support.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Tilt {
    /// Degrees: positive, the smallest tilt that topples the model; negative, minus the smallest
    /// tilt that makes it stand; 0 when a tilt of 0 is already on the edge.
    pub margin: f64,
    /// The horizontal unit vector, world, towards which the ground descends at that tilt.
    pub direction: Vector3<f64>,
    /// The balls that roll before the state changes in that direction, in order.
    pub moves: Vec<Move>,
}

/// Samples of the azimuth over the full circle.
const AZIMUTH_SAMPLES: usize = 180;
/// Sampled directions refined by golden-section search.
const REFINED: usize = 4;
/// Golden-section iterations: each shrinks the bracket by 0.618, so 45 take the bracket of two
/// sample spacings (4°) below 10⁻⁸ degrees.
const GOLDEN_ITERATIONS: usize = 45;
/// Fixed-point rounds for a centre of mass that moves with gravity (balls against their caps).
const CAP_ROUNDS: usize = 4;

impl TiltedModel<'_> {
    /// The tilt margin over every direction, or `None` when the total mass is not positive or the
    /// centre of mass is not above the ground.
    pub(crate) fn worst_tilt(&self) -> Option<Tilt> {
        let total = self.fixed_mass + self.balls.iter().map(|b| b.mass).sum::<f64>();
        if total.is_nan() || total <= 0.0 || total.is_infinite() || self.polygon.len() < 3 {
            return None;
        }
        let n = self.polygon.len();
        let search = Search {
            model: self,
            lines: (0..n)
                .map(|i| edge_line(self.polygon[i], self.polygon[(i + 1) % n]))
                .collect(),
            cap_rounds: if self.balls.iter().any(|b| b.drop != 0.0) {
                CAP_ROUNDS
            } else {
                1
            },
        };
        search.worst_tilt()
    }
}

/// A [`TiltedModel`] with its polygon's edge lines precomputed.
struct Search<'a> {
    model: &'a TiltedModel<'a>,
    /// Per edge: a point and the outward unit normal.
    lines: Vec<(Vector2<f64>, Vector2<f64>)>,
    /// Fixed-point rounds in `change_within`: one when no ball sits against a cap.
    cap_rounds: usize,
}

impl Search<'_> {
    /// See [`TiltedModel::worst_tilt`].
    fn worst_tilt(&self) -> Option<Tilt> {
        let rest = self.centre(&self.rest_ends(), &-self.model.plane.up);
        let height = self.model.plane.height(&rest) - self.model.ground;
        if height.is_nan() || height <= 0.0 {
            return None;
        }
        let standing = self.inside(&rest, &-self.model.plane.up);
        let mut candidates: Vec<(f64, f64)> = self
            .azimuths()
            .into_iter()
            .map(|phi| (self.first_change(phi, standing).0, phi))
            .collect();
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let spacing = std::f64::consts::TAU / AZIMUTH_SAMPLES as f64;
        // The best sample first, so that a refinement only replaces it when strictly lower.
        let (theta, phi) = candidates
            .first()
            .copied()
            .into_iter()
            .chain(
                candidates
                    .iter()
                    .take(REFINED)
                    .map(|&(_, phi)| self.refine(phi - spacing, phi + spacing, standing)),
            )
            .reduce(|best, next| if next.0 < best.0 { next } else { best })?;
        let (_, moves) = self.first_change(phi, standing);
        let sign = if standing { 1.0 } else { -1.0 };
        Some(Tilt {
            margin: sign * theta.to_degrees() + 0.0,
            direction: self.direction(phi),
            moves,
        })
    }

    /// The azimuths to sample: every two degrees, each edge's outward normal, and each capsule axis's
    /// horizontal direction both ways.
    fn azimuths(&self) -> Vec<f64> {
        let mut out: Vec<f64> = (0..AZIMUTH_SAMPLES)
            .map(|k| std::f64::consts::TAU * k as f64 / AZIMUTH_SAMPLES as f64)
            .collect();
        for (_, normal) in &self.lines {
            out.push(normal.y.atan2(normal.x));
        }
        for ball in self.model.balls {
            let axis = ball.to - ball.from;
            let (x, y) = (
                axis.dot(&self.model.plane.e1),
                axis.dot(&self.model.plane.e2),
            );
            if x != 0.0 || y != 0.0 {
                out.push(y.atan2(x));
                out.push((-y).atan2(-x));
            }
        }
        out
    }

    /// Golden-section search for the smallest first change over azimuths in `[lo, hi]`; returns
    /// `(θ, φ)`, θ in radians.
    fn refine(&self, mut lo: f64, mut hi: f64, standing: bool) -> (f64, f64) {
        let ratio = (5f64.sqrt() - 1.0) / 2.0;
        let value = |phi: f64| self.first_change(phi, standing).0;
        let mut a = hi - ratio * (hi - lo);
        let mut b = lo + ratio * (hi - lo);
        let (mut fa, mut fb) = (value(a), value(b));
        for _ in 0..GOLDEN_ITERATIONS {
            if fa <= fb {
                hi = b;
                b = a;
                fb = fa;
                a = hi - ratio * (hi - lo);
                fa = value(a);
            } else {
                lo = a;
                a = b;
                fa = fb;
                b = lo + ratio * (hi - lo);
                fb = value(b);
            }
        }
        if fa <= fb {
            (fa, a)
        } else {
            (fb, b)
        }
    }

    /// The horizontal unit vector of azimuth `phi`, world.
    fn direction(&self, phi: f64) -> Vector3<f64> {
        self.model.plane.e1 * phi.cos() + self.model.plane.e2 * phi.sin()
    }

    /// The first tilt (radians, at most π/2) towards azimuth `phi` at which the model's verdict
    /// is no longer `standing`, with the balls that rolled before it.
    fn first_change(&self, phi: f64, standing: bool) -> (f64, Vec<Move>) {
        let d = self.direction(phi);
        let up = self.model.plane.up;
        let mut ends = self.rest_ends();
        // Where each ball changes end in this direction: a·g(θ) = −cos θ A + sin θ B = 0.
        let mut events: Vec<(f64, usize)> = Vec::new();
        for (i, ball) in self.model.balls.iter().enumerate() {
            let axis = ball.to - ball.from;
            let (along_up, along_d) = (axis.dot(&up), axis.dot(&d));
            if along_up == 0.0 {
                // Horizontal at rest: the slightest tilt sends it towards the lower end.
                if along_d != 0.0 {
                    ends[i] = along_d > 0.0;
                }
            } else if along_d != 0.0 && along_up.signum() == along_d.signum() {
                events.push(((along_up / along_d).atan(), i));
            }
        }
        events.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let quarter = std::f64::consts::FRAC_PI_2;
        let mut moves = Vec::new();
        let mut start = 0.0;
        for k in 0..=events.len() {
            let end = events.get(k).map_or(quarter, |e| e.0);
            if let Some(theta) = self.change_within(&ends, &d, start, end, standing) {
                return (theta, moves);
            }
            let Some(&(theta, ball)) = events.get(k) else {
                break;
            };
            ends[ball] = !ends[ball];
            moves.push(Move {
                ball,
                tilt: theta.to_degrees(),
                to: if ends[ball] {
                    BallRest::To
                } else {
                    BallRest::From
                },
            });
            start = theta;
        }
        (quarter, moves)
    }

    /// With the balls at `ends` throughout, the first tilt in `[start, end)` towards `d` at which
    /// the verdict is no longer `standing`.
    fn change_within(
        &self,
        ends: &[bool],
        d: &Vector3<f64>,
        start: f64,
        end: f64,
        standing: bool,
    ) -> Option<f64> {
        let gravity = |theta: f64| -self.model.plane.up * theta.cos() + d * theta.sin();
        if self.inside(&self.centre(ends, &gravity(start)), &gravity(start)) != standing {
            return Some(start);
        }
        // The centre moves with gravity only through the balls resting against their caps: a
        // few fixed-point rounds of the closed form for a fixed centre.
        let mut theta = start;
        for _ in 0..self.cap_rounds {
            let centre = self.centre(ends, &gravity(theta));
            theta = self.crossing(&centre, d, standing)?.max(start);
        }
        (theta < end).then_some(theta)
    }

    /// For a fixed centre of mass, the tilt (radians) towards `d` at which the foot of the line
    /// along gravity crosses the polygon's boundary out of (when `standing`) or into it; `None`
    /// when it never does below 90°.
    fn crossing(&self, centre: &Point3<f64>, d: &Vector3<f64>, standing: bool) -> Option<f64> {
        let height = self.model.plane.height(centre) - self.model.ground;
        let foot = self.model.plane.project(centre);
        let along = Vector2::new(d.dot(&self.model.plane.e1), d.dot(&self.model.plane.e2));
        // The foot at distance t along d is inside while (foot + t·along − o)·n < 0 for every
        // edge: clip t to an interval.
        let (mut t_lo, mut t_hi) = (0.0_f64, f64::INFINITY);
        for (o, normal) in &self.lines {
            let offset = (foot - o).dot(normal);
            let rate = along.dot(normal);
            if rate > 0.0 {
                t_hi = t_hi.min(-offset / rate);
            } else if rate < 0.0 {
                t_lo = t_lo.max(offset / -rate);
            } else if offset >= 0.0 {
                t_hi = -1.0;
            }
        }
        let t = if standing {
            t_hi
        } else if t_lo < t_hi {
            t_lo
        } else {
            return None;
        };
        (t.is_finite() && t >= 0.0 && height > 0.0).then(|| (t / height).atan())
    }

    /// Whether the line through `centre` along `gravity` meets the ground strictly inside the
    /// polygon.
    fn inside(&self, centre: &Point3<f64>, gravity: &Vector3<f64>) -> bool {
        let down = -gravity.dot(&self.model.plane.up);
        if down <= 0.0 {
            return false;
        }
        let height = self.model.plane.height(centre) - self.model.ground;
        let foot_point = centre + gravity * (height / down);
        let foot = self.model.plane.project(&foot_point);
        self.lines
            .iter()
            .all(|(o, normal)| (foot - o).dot(normal) < 0.0)
    }

    /// Each ball's end at rest, `true` for `to`: the end its axis descends to under `−up`; a
    /// horizontal axis counts as `from` (the tilt decides it, see `first_change`).
    fn rest_ends(&self) -> Vec<bool> {
        self.model
            .balls
            .iter()
            .map(|ball| (ball.to - ball.from).dot(&self.model.plane.up) < 0.0)
            .collect()
    }

    /// The centre of mass with the balls at `ends` under `gravity` (unit).
    fn centre(&self, ends: &[bool], gravity: &Vector3<f64>) -> Point3<f64> {
        let mut mass = self.model.fixed_mass;
        let mut moment = self.model.fixed_moment;
        for (ball, &at_to) in self.model.balls.iter().zip(ends) {
            let end = if at_to { ball.to } else { ball.from };
            moment += (end.coords + gravity * ball.drop) * ball.mass;
            mass += ball.mass;
        }
        Point3::from(moment / mass)
    }
}

/// A point and the outward unit normal of the counter-clockwise edge `a`→`b`.
fn edge_line(a: Vector2<f64>, b: Vector2<f64>) -> (Vector2<f64>, Vector2<f64>) {
    let edge = b - a;
    (a, Vector2::new(edge.y, -edge.x) / edge.norm())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::model::Axis;

    fn square(half: f64) -> Vec<Vector2<f64>> {
        vec![
            Vector2::new(-half, -half),
            Vector2::new(half, -half),
            Vector2::new(half, half),
            Vector2::new(-half, half),
        ]
    }

    #[test]
    fn fixed_centre_gives_the_edge_angle() {
        let plane = GroundPlane::new(Axis::Z);
        let polygon = square(10.0);
        // The centre at (6, 0, 20): 4 inside the +x edge.
        let model = TiltedModel {
            plane: &plane,
            ground: 0.0,
            polygon: &polygon,
            fixed_mass: 2.0,
            fixed_moment: Vector3::new(12.0, 0.0, 40.0),
            balls: &[],
        };
        let tilt = model.worst_tilt().unwrap();
        assert!((tilt.margin - 4f64.atan2(20.0).to_degrees()).abs() < 1e-9);
        assert!((tilt.direction - Vector3::x()).norm() < 1e-9);
        assert!(tilt.moves.is_empty());
    }

    #[test]
    fn a_corner_is_farther_than_either_edge_for_a_toppling_model() {
        let plane = GroundPlane::new(Axis::Z);
        let polygon = square(10.0);
        // Outside past the corner (10, 10) by (3, 4): the edges say 4, the corner 5.
        let model = TiltedModel {
            plane: &plane,
            ground: 0.0,
            polygon: &polygon,
            fixed_mass: 1.0,
            fixed_moment: Vector3::new(13.0, 14.0, 10.0),
            balls: &[],
        };
        let tilt = model.worst_tilt().unwrap();
        assert!((tilt.margin + 5f64.atan2(10.0).to_degrees()).abs() < 1e-6);
    }
}
