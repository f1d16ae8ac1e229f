//! Convex hull of points in the plane (Andrew's monotone chain).

/// The convex hull of `points`, counter-clockwise, starting from the point with the smallest x
/// (then the smallest y).
///
/// Repeated points count once; points on an edge between two corners are left out; non-finite
/// points are ignored. So the result has no two equal points and no three collinear ones: it is
/// empty, one point, the two ends of a segment (when all points are collinear), or a polygon with
/// strictly left turns. Deterministic: the points are sorted with a total order first.
pub(crate) fn convex_hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    convex_hull_indices(points)
        .into_iter()
        .map(|i| points[i])
        .collect()
}

/// [`convex_hull`] as indices into `points`: of repeated points, the first.
pub(crate) fn convex_hull_indices(points: &[[f64; 2]]) -> Vec<usize> {
    let (mut sorted, mut hull) = (Vec::new(), Vec::new());
    convex_hull_indices_into(points, &mut sorted, &mut hull);
    hull
}

/// [`convex_hull_indices`] written into `hull`, with `sorted` as working space: both are
/// cleared first, so a caller making many hulls allocates them once.
pub(crate) fn convex_hull_indices_into(
    points: &[[f64; 2]],
    sorted: &mut Vec<usize>,
    hull: &mut Vec<usize>,
) {
    sorted.clear();
    hull.clear();
    sorted.extend((0..points.len()).filter(|&i| points[i].iter().all(|x| x.is_finite())));
    let order = |a: &usize, b: &usize| {
        let (p, q) = (points[*a], points[*b]);
        p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1]))
    };
    sorted.sort_by(|a, b| order(a, b).then(a.cmp(b)));
    sorted.dedup_by(|later, earlier| points[*later] == points[*earlier]);
    if sorted.len() < 3 {
        hull.extend_from_slice(sorted);
        return;
    }
    hull.reserve(sorted.len() + 1);
    for &p in sorted.iter() {
        pop_right_turns(points, hull, 2, p);
        hull.push(p);
    }
    let lower_len = hull.len();
    for &p in sorted.iter().rev().skip(1) {
        pop_right_turns(points, hull, lower_len + 1, p);
        hull.push(p);
    }
    // The upper chain ends where the lower one started.
    hull.pop();
}

/// Pops the last point of `hull` (indices into `points`) while it has at least `keep` points and
/// the last two do not turn strictly left towards `points[next]`.
fn pop_right_turns(points: &[[f64; 2]], hull: &mut Vec<usize>, keep: usize, next: usize) {
    let next = points[next];
    while hull.len() >= keep {
        let a = points[hull[hull.len() - 2]];
        let b = points[hull[hull.len() - 1]];
        let cross = (b[0] - a[0]) * (next[1] - a[1]) - (b[1] - a[1]) * (next[0] - a[0]);
        if cross > 0.0 {
            break;
        }
        hull.pop();
    }
}

#[cfg(test)]
mod tests {
    use super::convex_hull;

    #[test]
    fn square_with_inner_edge_and_repeated_points() {
        let points = [
            [1.0, 1.0],
            [0.0, 0.0],
            [0.5, 0.5],
            [1.0, 0.0],
            [0.5, 0.0],
            [0.0, 1.0],
            [1.0, 1.0],
            [0.0, 0.0],
        ];
        assert_eq!(
            convex_hull(&points),
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
        );
    }

    #[test]
    fn collinear_points_give_a_segment() {
        let points = [[2.0, 2.0], [0.0, 0.0], [1.0, 1.0], [3.0, 3.0], [1.0, 1.0]];
        assert_eq!(convex_hull(&points), vec![[0.0, 0.0], [3.0, 3.0]]);
    }

    #[test]
    fn vertical_collinear_points_give_a_segment() {
        let points = [[0.0, 2.0], [0.0, 0.0], [0.0, 1.0]];
        assert_eq!(convex_hull(&points), vec![[0.0, 0.0], [0.0, 2.0]]);
    }

    #[test]
    fn one_repeated_point() {
        assert_eq!(convex_hull(&[[1.0, 2.0]; 4]), vec![[1.0, 2.0]]);
    }

    #[test]
    fn empty_and_non_finite() {
        assert!(convex_hull(&[]).is_empty());
        assert_eq!(
            convex_hull(&[[f64::NAN, 0.0], [1.0, f64::INFINITY], [3.0, 4.0]]),
            vec![[3.0, 4.0]]
        );
    }

    #[test]
    fn order_of_input_does_not_matter() {
        let mut points: Vec<[f64; 2]> = (0..12)
            .map(|i| {
                let t = f64::from(i) * 0.5;
                [t.cos(), t.sin()]
            })
            .collect();
        let forward = convex_hull(&points);
        points.reverse();
        assert_eq!(convex_hull(&points), forward);
        // Counter-clockwise: positive signed area.
        let area: f64 = (0..forward.len())
            .map(|i| {
                let (a, b) = (forward[i], forward[(i + 1) % forward.len()]);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum();
        assert!(area > 0.0);
        assert_eq!(forward.len(), 12);
    }
}
