//! Where the slicer put a part, found from its extrusions: the outer perimeter of a few layers
//! fitted to the part's outline at those layers' heights.
//!
//! For each fitted layer the planned part (its mesh through `to_bed`) is cut at the height of the
//! layer's material centre, giving its outline on the bed. The extrusions of the layer are
//! sampled along their length; those whose centre line runs about the outer perimeter's inset
//! inside the outline (within half an extrusion width of it; inner perimeters and infill lie
//! further in) are its outer perimeter. The translation `t` and the inset `c` minimise
//! `Σ (distance(p − t, outline) − c)²` over those samples, weighted by the length each stands
//! for (Gauss–Newton, the samples chosen again at each step). The outline is the model's at each
//! layer, so a sloped face shifts nothing, as it does a bounding box.

use std::collections::HashMap;

use nalgebra::{Matrix3, Point2, Point3, Vector2, Vector3};
use serde::Serialize;

/// Layers fitted per part, spread evenly between its first and its last (both left out: the
/// first is squashed onto the bed, the last is a top skin).
pub(super) const FIT_LAYERS: usize = 8;
/// The fewest layers a trusted fit has outer perimeter on.
pub const MIN_FIT_LAYERS: usize = 3;
/// The largest residual (root mean square distance of the perimeter samples from the fitted
/// inset outline) a trusted fit has, as a fraction of the extrusion width.
pub const MAX_FIT_RESIDUAL: f64 = 0.2;
/// The least coverage (the length of outer perimeter fitted over the length of the model's
/// outline at the fitted layers) a trusted fit has.
pub const MIN_FIT_COVERAGE: f64 = 0.5;
/// The least spread (see [`PlacementFit::spread`]) a trusted fit has.
pub const MIN_FIT_SPREAD: f64 = 0.05;
/// Samples along an extrusion, at most this far apart, mm.
const SAMPLE_SPACING_MM: f64 = 0.5;
/// Gauss–Newton steps at most; the fit stops sooner when a step moves less than 1e-9 of the
/// extrusion width.
const MAX_STEPS: usize = 50;

/// How a part's place on the bed was found from the file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlacementFit {
    /// The offset found, x and y, project units: where the part is less where the plan put it.
    pub shift: [f64; 2],
    /// Root mean square distance of the fitted perimeter samples from the fitted outline,
    /// project units.
    pub residual: f64,
    /// How far inside the model's outline the outer perimeter's centre line runs, project units
    /// (about half an extrusion width).
    pub inset: f64,
    /// Layers with outer perimeter fitted.
    pub layers: usize,
    /// Perimeter samples fitted.
    pub samples: usize,
    /// Length of outer perimeter fitted over the length of the model's outline at those layers.
    pub coverage: f64,
    /// How well the fitted perimeter fixes the part in every direction: the smallest eigenvalue
    /// of the mean of `n nᵀ` over the samples, `n` the outline's normal (0 for straight walls
    /// all one way, 0.5 for a circle or a square).
    pub spread: f64,
}

impl PlacementFit {
    /// Why the fit cannot be trusted, when it cannot, for a print of extrusion width `width`
    /// (project units): too few layers, too little of the outline, or too large a residual.
    pub fn doubt(&self, width: f64) -> Option<String> {
        if self.layers < MIN_FIT_LAYERS {
            Some(format!(
                "outer perimeter found on {} layer{} (at least {MIN_FIT_LAYERS} needed)",
                self.layers,
                if self.layers == 1 { "" } else { "s" }
            ))
        } else if self.coverage < MIN_FIT_COVERAGE {
            Some(format!(
                "the extrusions follow {:.0}% of the part's outline (at least {:.0}% needed)",
                self.coverage * 100.0,
                MIN_FIT_COVERAGE * 100.0
            ))
        } else if self.spread < MIN_FIT_SPREAD {
            Some(format!(
                "the outer perimeter does not fix the part in every direction (spread {:.3}, at \
                 least {MIN_FIT_SPREAD} needed)",
                self.spread
            ))
        } else if self.residual > MAX_FIT_RESIDUAL * width {
            Some(format!(
                "the outer perimeter lies {:.3} from the fitted outline on average (at most \
                 {:.3}, {MAX_FIT_RESIDUAL} of an extrusion width)",
                self.residual,
                MAX_FIT_RESIDUAL * width
            ))
        } else {
            None
        }
    }
}

/// The layers (indices into the file's layers) fitted for an object extruding on layers
/// `first` to `last`.
pub(super) fn fit_layers(first: usize, last: usize) -> Vec<usize> {
    let (low, high) = if last >= first + 2 {
        (first + 1, last - 1)
    } else {
        (first, last)
    };
    let span = high - low;
    let mut layers: Vec<usize> = (0..FIT_LAYERS)
        .map(|k| low + span * k / (FIT_LAYERS - 1).max(1))
        .collect();
    layers.dedup();
    layers
}

/// Samples along the centre line from `a` to `b` (bed, project units), at most `spacing`
/// apart, each with the length it stands for.
pub(super) fn sample(a: &Point3<f64>, b: &Point3<f64>, spacing: f64, out: &mut Vec<Sample>) {
    let (a, b) = (a.xy(), b.xy());
    let length = (b - a).norm();
    let n = ((length / spacing).ceil() as usize).clamp(1, 100_000);
    let weight = length / n as f64;
    for i in 0..n {
        let f = (i as f64 + 0.5) / n as f64;
        out.push(Sample {
            at: a + (b - a) * f,
            weight,
        });
    }
    if out.len() >= 2 * MAX_LAYER_SAMPLES {
        thin(out);
    }
}

/// The most samples a fitted layer keeps before they are thinned: far more than a real layer's
/// extrusions give at [`SAMPLE_SPACING_MM`] (a 200 mm square's outer perimeter is 1,600), so
/// only a file of millions of moves on one layer is thinned, and its memory stays bounded.
pub(super) const MAX_LAYER_SAMPLES: usize = 250_000;

/// Keeps every other sample of `samples`, each standing for the length of the one dropped after
/// it too: the same path, half the points.
fn thin(samples: &mut Vec<Sample>) {
    let mut kept = 0;
    for index in (0..samples.len()).step_by(2) {
        let extra = samples.get(index + 1).map_or(0.0, |next| next.weight);
        samples[kept] = Sample {
            at: samples[index].at,
            weight: samples[index].weight + extra,
        };
        kept += 1;
    }
    samples.truncate(kept);
}

/// The sample spacing, project units, at `mm` project units per mm.
pub(super) fn spacing(mm: f64) -> f64 {
    SAMPLE_SPACING_MM * mm
}

/// A point of an extrusion's centre line on the bed and the length it stands for.
#[derive(Debug, Clone, Copy)]
pub(super) struct Sample {
    at: Point2<f64>,
    weight: f64,
}

/// One fitted layer: the model's outline at the layer's material centre, and the samples of the
/// object's extrusions on it.
pub(super) struct FitLayer {
    /// The outline.
    pub outline: Outline2,
    /// The samples.
    pub samples: Vec<Sample>,
}

/// A part's outline at one height on the bed: its edges, found near a point through a grid of
/// cells.
pub(super) struct Outline2 {
    edges: Vec<[Point2<f64>; 2]>,
    cell: f64,
    cells: HashMap<(i64, i64), Vec<u32>>,
}

impl Outline2 {
    /// The outline of `mesh` (positions on the bed and triangles) cut at height `z`, its edges
    /// filed in cells of side `cell`.
    pub fn cut(positions: &[Point3<f64>], triangles: &[[u32; 3]], z: f64, cell: f64) -> Self {
        let mut edges = Vec::new();
        for triangle in triangles {
            let corners = triangle.map(|i| positions[i as usize]);
            let mut crossings = Vec::with_capacity(2);
            for k in 0..3 {
                let (p, q) = (corners[k], corners[(k + 1) % 3]);
                if (p.z >= z) != (q.z >= z) {
                    let f = (z - p.z) / (q.z - p.z);
                    crossings.push(Point2::new(p.x + (q.x - p.x) * f, p.y + (q.y - p.y) * f));
                }
            }
            if let [a, b] = crossings[..] {
                edges.push([a, b]);
            }
        }
        let mut cells: HashMap<(i64, i64), Vec<u32>> = HashMap::new();
        for (index, [a, b]) in edges.iter().enumerate() {
            let (low, high) = (a.inf(b), a.sup(b));
            let (i0, j0) = cell_of(&low, cell);
            let (i1, j1) = cell_of(&high, cell);
            for i in i0..=i1 {
                for j in j0..=j1 {
                    let centre = Point2::new((i as f64 + 0.5) * cell, (j as f64 + 0.5) * cell);
                    if closest_on(&centre, a, b).0 <= cell {
                        cells.entry((i, j)).or_default().push(index as u32);
                    }
                }
            }
        }
        Outline2 { edges, cell, cells }
    }

    /// Its length.
    pub fn length(&self) -> f64 {
        self.edges.iter().map(|[a, b]| (b - a).norm()).sum()
    }

    /// The distance from `p` to the nearest edge and the unit direction from that edge to `p`,
    /// when an edge is within the cell size of `p`.
    fn nearest(&self, p: &Point2<f64>) -> Option<(f64, Vector2<f64>)> {
        let (i, j) = cell_of(p, self.cell);
        let mut best: Option<(f64, Vector2<f64>)> = None;
        for di in -1..=1 {
            for dj in -1..=1 {
                for &index in self.cells.get(&(i + di, j + dj)).into_iter().flatten() {
                    let [a, b] = &self.edges[index as usize];
                    let (distance, away) = closest_on(p, a, b);
                    if best.is_none_or(|(d, _)| distance < d) {
                        best = Some((distance, away));
                    }
                }
            }
        }
        best.filter(|(d, _)| *d <= self.cell)
    }
}

/// The cell holding `p`.
fn cell_of(p: &Point2<f64>, cell: f64) -> (i64, i64) {
    ((p.x / cell).floor() as i64, (p.y / cell).floor() as i64)
}

/// The distance from `p` to the segment `a`–`b`, and the unit direction from its closest point
/// to `p` (zero when `p` is on it).
fn closest_on(p: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> (f64, Vector2<f64>) {
    let ab = b - a;
    let f = if ab.norm_squared() > 0.0 {
        ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let away = p - (a + ab * f);
    let distance = away.norm();
    let unit = if distance > 0.0 {
        away / distance
    } else {
        Vector2::zeros()
    };
    (distance, unit)
}

/// The translation fitting `layers`, starting from `start` (project units), for a print of
/// extrusion width `width`.
pub(super) fn fit(layers: &[FitLayer], start: Vector2<f64>, width: f64) -> PlacementFit {
    let mut shift = start;
    let mut inset = width / 2.0;
    let band = width / 2.0;
    for _ in 0..MAX_STEPS {
        let mut normal = Matrix3::zeros();
        let mut rhs = Vector3::zeros();
        for layer in layers {
            for s in &layer.samples {
                let Some((d, n)) = layer.outline.nearest(&(s.at - shift)) else {
                    continue;
                };
                let r = d - inset;
                if r.abs() >= band {
                    continue;
                }
                let j = Vector3::new(-n.x, -n.y, -1.0);
                normal += j * j.transpose() * s.weight;
                rhs -= j * (r * s.weight);
            }
        }
        let Some(step) = normal.try_inverse().map(|inverse| inverse * rhs) else {
            break;
        };
        shift += step.xy();
        inset += step.z;
        if step.norm() < 1e-9 * width {
            break;
        }
    }
    measure(layers, shift, inset, band)
}

/// The fit at `shift` and `inset`: its residual, layers, samples and coverage.
fn measure(layers: &[FitLayer], shift: Vector2<f64>, inset: f64, band: f64) -> PlacementFit {
    let (mut squares, mut fitted, mut outline) = (0.0, 0.0, 0.0);
    let mut normals = nalgebra::Matrix2::zeros();
    let (mut used_layers, mut samples) = (0, 0);
    for layer in layers {
        let before = samples;
        for s in &layer.samples {
            let Some((d, n)) = layer.outline.nearest(&(s.at - shift)) else {
                continue;
            };
            let r = d - inset;
            if r.abs() < band {
                normals += n * n.transpose() * s.weight;
                squares += r * r * s.weight;
                fitted += s.weight;
                samples += 1;
            }
        }
        if samples > before {
            used_layers += 1;
            outline += layer.outline.length();
        }
    }
    let finite = |x: f64| if x.is_finite() { x } else { 0.0 };
    PlacementFit {
        shift: [shift.x, shift.y],
        residual: finite((squares / fitted).sqrt()),
        inset,
        layers: used_layers,
        samples,
        coverage: finite(fitted / outline),
        spread: finite((normals / fitted).symmetric_eigenvalues().min()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples of a square loop from `low` to `high`, moved by `shift`.
    fn ring(low: f64, high: f64, shift: Vector2<f64>, out: &mut Vec<Sample>) {
        let corners = [(low, low), (high, low), (high, high), (low, high)];
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            let a = Point3::new(a.0 + shift.x, a.1 + shift.y, 0.0);
            let b = Point3::new(b.0 + shift.x, b.1 + shift.y, 0.0);
            sample(&a, &b, 0.5, out);
        }
    }

    fn layers(shift: Vector2<f64>, walls: bool) -> Vec<FitLayer> {
        // A 20 × 20 × 10 box with its corner at the origin.
        let crate::geometry::TriMesh {
            positions,
            triangles,
        } = crate::geometry::box_at([0.0; 3], [20.0, 20.0, 10.0], 0);
        (0..5)
            .map(|k| {
                let mut samples = Vec::new();
                if walls {
                    // Outer and inner perimeters, then infill lines across.
                    ring(0.225, 19.775, shift, &mut samples);
                    ring(0.675, 19.325, shift, &mut samples);
                    for i in 0..9 {
                        let y = 2.0 + 2.0 * f64::from(i) + shift.y;
                        let a = Point3::new(0.9 + shift.x, y, 0.0);
                        let b = Point3::new(19.1 + shift.x, y, 0.0);
                        sample(&a, &b, 0.5, &mut samples);
                    }
                } else {
                    // One straight wall: it fixes x, not y.
                    let a = Point3::new(0.225 + shift.x, 0.225 + shift.y, 0.0);
                    let b = Point3::new(0.225 + shift.x, 19.775 + shift.y, 0.0);
                    sample(&a, &b, 0.5, &mut samples);
                }
                FitLayer {
                    outline: Outline2::cut(&positions, &triangles, 1.0 + 2.0 * k as f64, 0.9),
                    samples,
                }
            })
            .collect()
    }

    #[test]
    fn a_moved_square_is_found_from_a_lopsided_start() {
        let shift = Vector2::new(0.3, -0.2);
        let found = fit(&layers(shift, true), Vector2::new(0.4, -0.1), 0.45);
        assert!((found.shift[0] - 0.3).abs() < 1e-9, "{found:?}");
        assert!((found.shift[1] + 0.2).abs() < 1e-9, "{found:?}");
        assert!((found.inset - 0.225).abs() < 1e-6, "{found:?}");
        assert_eq!(found.layers, 5);
        assert_eq!(found.doubt(0.45), None);
    }

    #[test]
    fn a_single_straight_wall_is_not_trusted() {
        let found = fit(&layers(Vector2::zeros(), false), Vector2::zeros(), 0.45);
        let doubt = found.doubt(0.45).expect("not trusted");
        assert!(
            doubt.contains("every direction") || doubt.contains("outline"),
            "{doubt}"
        );
    }

    #[test]
    fn too_few_layers_are_not_trusted() {
        let few = layers(Vector2::zeros(), true)
            .into_iter()
            .take(2)
            .collect::<Vec<_>>();
        let found = fit(&few, Vector2::zeros(), 0.45);
        assert_eq!(found.layers, 2);
        assert!(found.doubt(0.45).unwrap().contains("2 layers"));
    }

    #[test]
    fn millions_of_samples_on_a_layer_are_thinned_keeping_their_length() {
        let mut samples = Vec::new();
        let (a, b) = (Point3::new(0.0, 0.0, 0.2), Point3::new(1.0, 0.0, 0.2));
        for _ in 0..1_000_000 {
            sample(&a, &b, 0.5, &mut samples);
        }
        assert!(samples.len() < 2 * MAX_LAYER_SAMPLES, "{}", samples.len());
        let length: f64 = samples.iter().map(|s| s.weight).sum();
        assert!((length - 1e6).abs() < 1e-6, "{length}");
    }

    #[test]
    fn layers_are_spread_between_the_first_and_the_last() {
        assert_eq!(fit_layers(0, 100), [1, 15, 29, 43, 57, 71, 85, 99]);
        assert_eq!(fit_layers(3, 5), [4]);
        assert_eq!(fit_layers(0, 0), [0]);
    }
}
