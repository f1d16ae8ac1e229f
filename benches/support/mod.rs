//! What every benchmark harness shares: the baseline every time is divided by, and how a ratio
//! is printed. Each harness includes this module and uses part of it.
#![allow(dead_code)]

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use ballast::geometry::TriMesh;

/// The repository's root.
pub fn manifest() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The baseline: one pass over the vertices, summing every coordinate.
pub fn sum_coordinates(mesh: &TriMesh) -> f64 {
    mesh.positions.iter().map(|p| p.x + p.y + p.z).sum()
}

/// The baseline's time, seconds: the median of 201 timed passes after a few to warm up.
pub fn baseline(mesh: &TriMesh) -> f64 {
    for _ in 0..20 {
        black_box(sum_coordinates(black_box(mesh)));
    }
    let mut times: Vec<f64> = (0..201)
        .map(|_| {
            let clock = Instant::now();
            black_box(sum_coordinates(black_box(mesh)));
            clock.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// Seconds as a ratio to the baseline, about three significant digits (`k` thousands, `M`
/// millions).
pub fn ratio(seconds: f64, baseline: f64) -> String {
    let r = seconds / baseline;
    if r >= 1e6 {
        format!("{:.2}M", r / 1e6)
    } else if r >= 1e4 {
        format!("{:.0}k", r / 1e3)
    } else if r >= 1e3 {
        format!("{:.1}k", r / 1e3)
    } else {
        format!("{r:.0}")
    }
}
