//! Outline sides seen from above, and a point's squared distance to them.

/// Straight sides, each as its start, its direction and the inverse of its squared length (0
/// for a side that is a point).
pub(super) struct Sides(Vec<[f64; 5]>);

impl Sides {
    /// The sides from their ends.
    pub(super) fn new(ends: &[[(f64, f64); 2]]) -> Sides {
        Sides(
            ends.iter()
                .map(|&[(u0, v0), (u1, v1)]| {
                    let (du, dv) = (u1 - u0, v1 - v0);
                    let length2 = du * du + dv * dv;
                    let inverse = if length2 > 0.0 { 1.0 / length2 } else { 0.0 };
                    [u0, v0, du, dv, inverse]
                })
                .collect(),
        )
    }

    /// The sides of a convex polygon from its corners in order around it, sides of no length
    /// left out (a walk along the sides could stop at one: see [`Sides::nearest_from`]).
    pub(super) fn of_convex(corners: &[(f64, f64)]) -> Sides {
        let ends: Vec<[(f64, f64); 2]> = (0..corners.len())
            .map(|i| [corners[i], corners[(i + 1) % corners.len()]])
            .filter(|[a, b]| a != b)
            .collect();
        Sides::new(&ends)
    }

    /// Whether there is no side.
    pub(super) fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The squared distance from `(u, v)` to side `s`.
    pub(super) fn distance2(&self, s: usize, (u, v): (f64, f64)) -> f64 {
        let [u0, v0, du, dv, inverse] = self.0[s];
        let t = (((u - u0) * du + (v - v0) * dv) * inverse).clamp(0.0, 1.0);
        let (eu, ev) = (u - u0 - t * du, v - v0 - t * dv);
        eu * eu + ev * ev
    }

    /// The side nearest to `point` (the first of equals) and its squared distance, every side
    /// measured.
    pub(super) fn nearest(&self, point: (f64, f64)) -> (usize, f64) {
        (0..self.0.len())
            .map(|s| (s, self.distance2(s, point)))
            .fold(
                (0, f64::INFINITY),
                |best, (s, d2)| {
                    if d2 < best.1 {
                        (s, d2)
                    } else {
                        best
                    }
                },
            )
    }

    /// Where the foot of `(u, v)` on side `s`'s line falls: 0 at its start, 1 at its end.
    fn along(&self, s: usize, (u, v): (f64, f64)) -> f64 {
        let [u0, v0, du, dv, inverse] = self.0[s];
        ((u - u0) * du + (v - v0) * dv) * inverse
    }

    /// Whether `(u, v)` lies strictly to the right of side `s`'s line, looking along it: outside
    /// a polygon whose corners go anticlockwise.
    fn right_of(&self, s: usize, (u, v): (f64, f64)) -> bool {
        let [u0, v0, du, dv, _] = self.0[s];
        du * (v - v0) - dv * (u - u0) < 0.0
    }

    /// For the sides of a convex polygon with its corners anticlockwise ([`Sides::of_convex`])
    /// and a `point` outside it: the nearest side (one of two sharing the nearest corner) and
    /// its squared distance, found by walking from side `from` towards the nearest point until
    /// that point is certain: the foot of `point` within a side, with `point` outside that side,
    /// or a corner with the foot beyond the end of the side before it and before the start of
    /// the side after it (for a convex polygon, the nearest point is the one where `point` lies
    /// along an outward normal). Where no side gives that within a walk around the polygon
    /// (a point inside it, or on the far side of a thin one), every side is measured. Starting
    /// from the nearest side of a point nearby, one or two sides are looked at.
    pub(super) fn nearest_from(&self, from: usize, point: (f64, f64)) -> (usize, f64) {
        let n = self.0.len();
        let mut s = from % n;
        for _ in 0..n {
            let t = self.along(s, point);
            if t >= 1.0 {
                let next = (s + 1) % n;
                if self.along(next, point) <= 0.0 {
                    return (s, self.distance2(s, point));
                }
                s = next;
            } else if t <= 0.0 {
                let before = (s + n - 1) % n;
                if self.along(before, point) >= 1.0 {
                    return (s, self.distance2(s, point));
                }
                s = before;
            } else if self.right_of(s, point) {
                return (s, self.distance2(s, point));
            } else {
                break;
            }
        }
        self.nearest(point)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walking_from_any_side_finds_the_nearest() {
        // A long stadium with repeated corners, a thin sliver and a regular 48-gon, each
        // walked along rows of points around it as the raster walks them.
        let mut polygons: Vec<Vec<(f64, f64)>> = Vec::new();
        let stadium: Vec<(f64, f64)> = (0..48)
            .map(|k| {
                let angle = std::f64::consts::TAU * k as f64 / 48.0;
                let (c, s) = (angle.cos(), angle.sin());
                // The straight sides are each one direction's farthest point, repeated.
                let centre = if c >= 0.0 { 12.0 } else { -12.0 };
                (centre + 3.0 * c, 3.0 * s)
            })
            .collect();
        // And every sixth corner twice.
        let repeated = stadium
            .iter()
            .enumerate()
            .flat_map(|(k, &corner)| vec![corner; 1 + usize::from(k % 6 == 0)])
            .collect();
        polygons.push(stadium);
        polygons.push(repeated);
        polygons.push(vec![(0.0, 0.0), (30.0, 0.5), (30.0, 0.6), (0.0, 0.2)]);
        polygons.push(
            (0..48)
                .map(|k| {
                    let angle = std::f64::consts::TAU * k as f64 / 48.0;
                    (5.0 * angle.cos() + 1.0, 5.0 * angle.sin() - 2.0)
                })
                .collect(),
        );
        let inside = |corners: &[(f64, f64)], (u, v): (f64, f64)| {
            (0..corners.len()).all(|i| {
                let (a, b) = (corners[i], corners[(i + 1) % corners.len()]);
                (b.0 - a.0) * (v - a.1) - (b.1 - a.1) * (u - a.0) >= 0.0
            })
        };
        for corners in polygons {
            let sides = Sides::of_convex(&corners);
            for row in 0..200 {
                let v = -20.0 + 0.2 * row as f64 + 0.013;
                let mut tracked: Option<usize> = None;
                for column in 0..300 {
                    let point = (-30.0 + 0.2 * column as f64 + 0.007, v);
                    if inside(&corners, point) {
                        tracked = None;
                        continue;
                    }
                    let scanned = sides.nearest(point);
                    let walked = match tracked {
                        Some(s) => sides.nearest_from(s, point),
                        None => scanned,
                    };
                    // Two sides meeting at the nearest corner measure it in other roundings.
                    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + a.abs());
                    assert!(close(walked.1, scanned.1), "{point:?} from {tracked:?}");
                    tracked = Some(walked.0);
                    // From any side, far from the nearest.
                    let far = (walked.0 + column) % 7;
                    assert!(
                        close(sides.nearest_from(far, point).1, scanned.1),
                        "{point:?}"
                    );
                }
            }
        }
    }
}
