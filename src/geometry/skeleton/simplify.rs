//! Douglas-Peucker simplification of a skeleton branch into straight pieces.

use nalgebra::Point3;

/// Distance from `p` to the segment `a`–`b` (to `a` when the segment has no length).
fn distance_to_chord(p: &Point3<f64>, a: &Point3<f64>, b: &Point3<f64>) -> f64 {
    let ab = b - a;
    let length2 = ab.norm_squared();
    if length2 == 0.0 {
        return (p - a).norm();
    }
    let t = ((p - a).dot(&ab) / length2).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

/// Indices of the points of `points` kept by Douglas-Peucker: the first, the last, and the
/// farthest point of every chord that strays more than `tolerance` from the points it replaces
/// or whose midpoint fails `accept` (for instance, lies outside the solid). A polyline that
/// returns to its start is split at its farthest point first.
pub(super) fn douglas_peucker(
    points: &[Point3<f64>],
    tolerance: f64,
    accept: impl Fn(&Point3<f64>) -> bool,
) -> Vec<usize> {
    if points.len() < 2 {
        return (0..points.len()).collect();
    }
    let mut kept = vec![false; points.len()];
    kept[0] = true;
    kept[points.len() - 1] = true;
    let mut stack = vec![(0, points.len() - 1)];
    while let Some((first, last)) = stack.pop() {
        if last <= first + 1 {
            continue;
        }
        let (a, b) = (&points[first], &points[last]);
        let (far, deviation) = (first + 1..last)
            .map(|i| (i, distance_to_chord(&points[i], a, b)))
            .fold(
                (first + 1, -1.0),
                |best, c| if c.1 > best.1 { c } else { best },
            );
        let closed = a == b;
        if closed || deviation > tolerance || !accept(&nalgebra::center(a, b)) {
            kept[far] = true;
            stack.push((far, last));
            stack.push((first, far));
        }
    }
    (0..points.len()).filter(|&i| kept[i]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bend_is_kept_and_a_wobble_is_not() {
        let points: Vec<Point3<f64>> = (0..=20)
            .map(|i| {
                let wobble = if i % 2 == 0 { 0.1 } else { -0.1 };
                if i <= 10 {
                    Point3::new(i as f64, wobble, 0.0)
                } else {
                    Point3::new(10.0 + wobble, (i - 10) as f64, 0.0)
                }
            })
            .collect();
        assert_eq!(douglas_peucker(&points, 0.5, |_| true), vec![0, 10, 20]);
        assert_eq!(douglas_peucker(&points[..11], 0.5, |_| true), vec![0, 10]);
    }
}
