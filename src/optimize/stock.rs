//! Capsule radii snapped to stock balls: the radius of a capsule the optimizer sizes is a listed
//! ball plus the clearance, on the solution file's length grid, so the design it judges is the one
//! that is printed and filled.

use crate::design::Design;
use crate::geometry::TriMesh;
use crate::spec::model::Ball;

/// Digits after the decimal point that keep lengths to about 10⁻⁴ of the model's extent: the
/// solution file's precision.
pub fn length_decimals(meshes: &[TriMesh]) -> usize {
    let extent = meshes
        .iter()
        .filter_map(TriMesh::bounding_box)
        .map(|(lo, hi)| (hi - lo).norm())
        .fold(0.0, f64::max);
    if extent > 0.0 && extent.is_finite() {
        (4.0 - extent.log10().floor()).clamp(0.0, 12.0) as usize
    } else {
        4
    }
}

/// Steps per project unit of the length grid with `decimals` digits: a length on the grid is
/// `k / scale` for a whole `k`, the double its decimal text reads back as.
pub fn grid_scale(decimals: usize) -> f64 {
    10f64.powi(decimals as i32)
}

/// The smallest radius on the grid of `scale` that holds a ball of `ball_radius` with the
/// clearance: `ball.radius_for` of it is `ball_radius` again, so a solution file that holds it
/// reads back with the same ball.
pub fn capsule_radius(ball: &Ball, ball_radius: f64, scale: f64) -> f64 {
    // A product a hair above a whole number is that number, not the next.
    let k = ((ball_radius + ball.clearance) * scale - 1e-9).ceil();
    let radius = k / scale;
    if ball.radius_for(radius) == Some(ball_radius) {
        radius
    } else {
        (k + 1.0) / scale
    }
}

/// The radius of the smallest capsule the optimizer makes: `min_radius`, or the capsule of the
/// smallest listed ball ([`capsule_radius`] on the grid of `scale`) when that is more.
pub fn smallest_capsule_radius(ball: &Ball, min_radius: f64, scale: f64) -> f64 {
    let listed = ball
        .diameters
        .iter()
        .map(|d| d / 2.0)
        .min_by(f64::total_cmp)
        .map(|b| capsule_radius(ball, b, scale));
    match listed {
        Some(radius) => radius.max(min_radius),
        None => min_radius,
    }
}

/// The stock capsule radius for a capsule the optimizer left at `radius`: the largest listed ball
/// that fits, or the next larger one when it is nearer and `allowed` accepts its capsule radius;
/// the next larger one when none fits. Each as [`capsule_radius`], with its ball radius. `None`
/// without a list (any ball size) or when no listed ball is usable at all.
pub fn snap(
    ball: &Ball,
    radius: f64,
    scale: f64,
    allowed: impl Fn(f64) -> bool,
) -> Option<(f64, f64)> {
    let fitting = ball.radius_for(radius).filter(|_| ball.is_listed());
    let larger = ball.next_larger(fitting.unwrap_or(0.0));
    let lower = fitting.map(|b| (capsule_radius(ball, b, scale), b));
    let upper = larger.map(|b| (capsule_radius(ball, b, scale), b));
    match (lower, upper) {
        (Some(lo), Some(hi)) if hi.0 - radius < radius - lo.0 && allowed(hi.0) => Some(hi),
        (Some(lo), _) => Some(lo),
        (None, hi) => hi,
    }
}

/// `design` as the solution file holds it, on the grid of `scale`: the ends of every capsule not
/// `pinned` (by design index) at the nearest step; its radius a stock ball plus the clearance
/// ([`capsule_radius`], on the grid already) or, with any ball size, on the grid below it and one
/// step further down when rounding moved an end, so that rounding brings no capsule closer to the
/// surface or to another capsule than it was; a ranged infill (`ranged_infill`) to six decimals.
/// A design already on the grid comes back as it is.
pub fn on_file_grid(
    mut design: Design,
    pinned: &[bool],
    ball: &Ball,
    scale: f64,
    ranged_infill: bool,
) -> Design {
    let round = |v: f64| (v * scale).round() / scale;
    for (j, capsule) in design.capsules.iter_mut().enumerate() {
        if pinned.get(j).copied().unwrap_or(false) {
            continue;
        }
        let (from, to) = (capsule.from.map(round), capsule.to.map(round));
        let moved = from != capsule.from || to != capsule.to;
        (capsule.from, capsule.to) = (from, to);
        let stock = ball
            .radius_for(capsule.radius)
            .filter(|_| ball.is_listed())
            .map(|b| (capsule_radius(ball, b, scale), b));
        match stock {
            Some((radius, b)) => {
                capsule.radius = radius;
                capsule.ball_radius = b;
            }
            None => {
                let steps = if round(capsule.radius) == capsule.radius {
                    (capsule.radius * scale).round()
                } else {
                    (capsule.radius * scale).floor()
                };
                capsule.radius = (steps - f64::from(u8::from(moved))) / scale;
                if let Some(b) = ball.radius_for(capsule.radius) {
                    capsule.ball_radius = b;
                }
            }
        }
    }
    if ranged_infill {
        design.infill = (design.infill * 1e6).round() / 1e6;
    }
    design
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::PlacedCapsule;
    use nalgebra::Point3;

    fn ball(diameters: &[f64], clearance: f64) -> Ball {
        Ball {
            density: 7.85,
            clearance,
            pause_clearance: 0.2,
            min_angle: 3.0,
            diameters: diameters.to_vec(),
        }
    }

    #[test]
    fn the_capsule_radius_is_on_the_grid_and_holds_its_ball_with_the_clearance() {
        let b = ball(&[4.0, 6.35, 8.0], 0.2);
        // 2 + 0.2 is on the 0.01 grid; 3.175 + 0.2 is not, and rounds up to 3.38.
        assert_eq!(capsule_radius(&b, 2.0, 100.0), 2.2);
        assert_eq!(capsule_radius(&b, 3.175, 100.0), 3.38);
        for &d in &b.diameters {
            let r = capsule_radius(&b, d / 2.0, 100.0);
            assert_eq!(b.radius_for(r), Some(d / 2.0));
            assert!(r - d / 2.0 - 0.2 < 0.01 + 1e-12);
        }
    }

    #[test]
    fn the_largest_ball_that_fits_unless_the_next_is_nearer_and_allowed() {
        let b = ball(&[4.0, 5.0, 6.0], 0.2);
        let yes = |_| true;
        let no = |_| false;
        // 2.3: 4 mm (2.2) is nearer than 5 mm (2.7).
        assert_eq!(snap(&b, 2.3, 100.0, yes), Some((2.2, 2.0)));
        // 2.6: 5 mm (2.7) is nearer, when the larger capsule is allowed.
        assert_eq!(snap(&b, 2.6, 100.0, yes), Some((2.7, 2.5)));
        assert_eq!(snap(&b, 2.6, 100.0, no), Some((2.2, 2.0)));
        // Wider than the largest ball: the largest.
        assert_eq!(snap(&b, 9.0, 100.0, yes), Some((3.2, 3.0)));
        // Narrower than the smallest ball needs: the smallest, whatever `allowed` says.
        assert_eq!(snap(&b, 1.0, 100.0, no), Some((2.2, 2.0)));
        // Any size: nothing to snap to.
        assert_eq!(snap(&ball(&[], 0.2), 2.6, 100.0, yes), None);
    }

    #[test]
    fn inch_projects_snap_to_inch_balls_on_a_finer_grid() {
        let mm = 1.0 / 25.4;
        let b = ball(&[0.25, 0.3125, 8.0 * mm], 0.2 * mm);
        let (radius, ball_radius) = snap(&b, 0.17, 1e4, |_| true).unwrap();
        // 8 mm = 0.31496 in fits under 0.17 − 0.00787; 5/16" = 0.3125 does too but is smaller.
        assert_eq!(ball_radius, 4.0 * mm);
        assert_eq!(radius, 0.1654);
        assert_eq!(b.radius_for(radius), Some(ball_radius));
    }

    fn design(radius: f64, from: [f64; 3], to: [f64; 3]) -> Design {
        Design {
            capsules: vec![PlacedCapsule {
                name: "c".into(),
                component: 0,
                from: Point3::from(from),
                to: Point3::from(to),
                radius,
                ball_radius: 0.0,
            }],
            infill: 0.2,
        }
    }

    #[test]
    fn a_design_on_the_file_grid_keeps_its_capsules_no_closer_to_anything() {
        let any = ball(&[], 0.2);
        let reached = design(2.3456, [1.234, -0.005, 3.0], [7.0001, 2.0, 3.5]);
        let written = on_file_grid(reached.clone(), &[false], &any, 100.0, true);
        let c = &written.capsules[0];
        assert_eq!(c.from, Point3::new(1.23, -0.01, 3.0));
        assert_eq!(c.to, Point3::new(7.0, 2.0, 3.5));
        // Floored to 2.34, then a step down for the moved ends: at least the ends' move narrower.
        assert_eq!(c.radius, 2.33);
        assert!(reached.capsules[0].radius - c.radius >= 0.5 * 3f64.sqrt() / 100.0);
        assert_eq!(any.radius_for(c.radius), Some(c.ball_radius));
        assert_eq!(written.infill, 0.2);
        // Written again, it is unchanged: a judge of the written design can be trusted.
        assert_eq!(
            on_file_grid(written.clone(), &[false], &any, 100.0, true),
            written
        );
        // A radius narrowed off the grid with the ends on it is only floored.
        let mut narrowed = written.clone();
        narrowed.capsules[0].radius = 2.1789;
        let again = on_file_grid(narrowed, &[false], &any, 100.0, true);
        assert_eq!(again.capsules[0].radius, 2.17);
        assert_eq!(again.capsules[0].from, c.from);
    }

    #[test]
    fn stock_and_pinned_capsules_on_the_file_grid() {
        let stock = ball(&[4.0, 5.0], 0.2);
        let reached = design(2.2, [0.123, 0.0, 0.0], [5.0, 0.0, 0.0]);
        let written = on_file_grid(reached.clone(), &[false], &stock, 100.0, false);
        // The stock radius is on the grid already and kept, whatever the ends did.
        assert_eq!(written.capsules[0].radius, 2.2);
        assert_eq!(written.capsules[0].ball_radius, 2.0);
        assert_eq!(written.capsules[0].from, Point3::new(0.12, 0.0, 0.0));
        // A pinned capsule is left as written.
        assert_eq!(
            on_file_grid(reached.clone(), &[true], &stock, 100.0, false),
            reached
        );
    }
}
