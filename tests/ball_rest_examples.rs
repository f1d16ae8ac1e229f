//! Where each example's balls come to rest on the printed floor, read from PrusaSlicer's G-code,
//! and how far the top of each ball then lies below the top of the layer the print pauses after.
//!
//! The insertion window (`docs/fabrication.md`, "The window") takes the ball resting against the
//! void's smooth spherical end. The printed floor is a stack of layers: each ball is dropped into
//! its void at its pause and rolls to the lowest place the beads printed so far leave it. This
//! test finds that place from the file alone: every extrusion printed before the pause is a bead
//! of the width its filament gives at its layer's thickness (PrusaSlicer's flow: a rectangle with
//! round sides, `A = (w − h) h + π h² / 4`), that is the points within `h / 2` of a level strip
//! `w − h` wide along its path, half a layer below the nozzle. A ball of radius `b` clears a bead
//! while its centre stays `b + h / 2` from that strip. From every centre on a fine grid within
//! `r − b` (seen from above) of the void's lower end, at the height of that end (inside the void,
//! clear of every wall), the ball is let down until it first touches a bead; it rests at the
//! lowest of those. The void comes from the design through the print plan (every part prints
//! where the plan puts it: `tests/fabrication_examples.rs`); nothing else of ballast's model is
//! used.
//!
//! Skipped when `prusa-slicer` is not installed (`.ci/run` installs it).

mod print_support;

use ballast::compile::compile;
use ballast::gcode::{filament_area, read_program, ReadOptions};
use nalgebra::{Point2, Point3};
use print_support::{examples, sliced_compilation, slicer_available};

/// The filament the examples are sliced for, mm.
const FILAMENT_DIAMETER: f64 = 1.75;

/// Spacing of the grid of ball centres tried, mm.
const GRID_STEP: f64 = 0.005;

/// The least distance the top of a ball should have below the top of the paused layer, mm: a
/// ball level with it is printed over.
const MARGIN: f64 = 0.2;

/// The balls (`example: capsule`) whose top comes to rest less than [`MARGIN`] below the top of
/// the paused layer, as printed: none, since the insertion window allows a layer for the
/// stepped floor and the ball's pause clearance (0.2 mm by default). The test fails when the list
/// is not exactly those balls.
const BALLS_WITHIN_THE_MARGIN: &[&str] = &[];

/// A bead of plastic: the points within `half_height` of the level strip of half-width
/// `half_width` along `from`–`to` (seen from above) at height `z`, mm.
struct Bead {
    from: Point2<f64>,
    to: Point2<f64>,
    z: f64,
    half_width: f64,
    half_height: f64,
}

impl Bead {
    /// The heights a ball of radius `radius` centred above `(x, y)` may not take: an open
    /// interval, `None` when the bead is out of reach seen from above.
    fn blocks(&self, at: &Point2<f64>, radius: f64) -> Option<(f64, f64)> {
        let along = self.to - self.from;
        let t = if along.norm_squared() > 0.0 {
            ((at - self.from).dot(&along) / along.norm_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let across = ((self.from + along * t - at).norm() - self.half_width).max(0.0);
        let reach = radius + self.half_height;
        (across < reach).then(|| {
            let rise = (reach * reach - across * across).sqrt();
            (self.z - rise, self.z + rise)
        })
    }
}

/// The lowest height the centre of a ball of `radius` reaches among the beads, let down from
/// `start` on every centre of the grid within `spread` of `below` seen from above; `None` when
/// no centre is free at `start` or none lands on a bead.
fn rest_height(beads: &[Bead], below: &Point3<f64>, spread: f64, radius: f64) -> Option<f64> {
    let steps = (spread / GRID_STEP).floor() as i64;
    let mut lowest: Option<f64> = None;
    for i in -steps..=steps {
        for j in -steps..=steps {
            let offset = nalgebra::Vector2::new(i as f64, j as f64) * GRID_STEP;
            if offset.norm() > spread {
                continue;
            }
            let at = Point2::new(below.x, below.y) + offset;
            let mut landing: Option<f64> = None;
            let mut free = true;
            for bead in beads {
                let Some((low, high)) = bead.blocks(&at, radius) else {
                    continue;
                };
                if low < below.z && below.z < high {
                    free = false;
                    break;
                }
                if high <= below.z {
                    landing = Some(landing.map_or(high, |h: f64| h.max(high)));
                }
            }
            if let (true, Some(height)) = (free, landing) {
                lowest = Some(lowest.map_or(height, |l| l.min(height)));
            }
        }
    }
    lowest
}

#[test]
fn every_ball_rests_below_the_paused_layer() {
    if !slicer_available() {
        eprintln!("skipped: prusa-slicer is not on the PATH (apt-get install prusa-slicer)");
        return;
    }
    let folder = tempfile::tempdir().unwrap();
    let mut within_margin = Vec::new();
    let mut balls = 0;
    println!("| ball | planned gap mm | lift mm | gap as printed mm |");
    println!("| --- | ---: | ---: | ---: |");
    for path in examples() {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let source = std::fs::read_to_string(&path).unwrap();
        let compilation = compile(&source, &path)
            .unwrap_or_else(|problems| panic!("{name} does not compile: {problems:?}"));
        let gcode = sliced_compilation(&compilation, folder.path(), &name);
        let program = read_program(&gcode, &ReadOptions::default()).unwrap();
        let mm = 1.0 / compilation.project.units.from_millimetres(1.0);
        let area = filament_area(FILAMENT_DIAMETER);
        for plan in &compilation.print_plan.components {
            for insertion in &plan.capsules {
                let capsule = &compilation.design.capsules[insertion.capsule];
                let Some(pause) = insertion.pause.map(|p| &plan.pauses[p]) else {
                    continue;
                };
                let (a, b) = (
                    plan.to_bed * capsule.from * mm,
                    plan.to_bed * capsule.to * mm,
                );
                let lower = if a.z <= b.z { a } else { b };
                let (radius, ball) = (capsule.radius * mm, capsule.ball_radius * mm);
                let paused_at = pause.height * mm;
                // Every bead printed before the pause, near the void's lower end.
                let beads: Vec<Bead> = program
                    .objects
                    .iter()
                    .flat_map(|object| &object.segments)
                    .filter(|s| program.layers[s.layer] <= paused_at + 1e-6)
                    .filter_map(|s| {
                        let h = program.layer_thickness(s.layer);
                        let length = (s.end - s.start).norm();
                        if h <= 0.0 || length <= 0.0 {
                            return None;
                        }
                        let width = s.filament * area / length / h
                            + h * (1.0 - std::f64::consts::FRAC_PI_4);
                        let bead = Bead {
                            from: Point2::new(s.start.x, s.start.y),
                            to: Point2::new(s.end.x, s.end.y),
                            z: program.layers[s.layer] - h / 2.0,
                            half_width: ((width - h) / 2.0).max(0.0),
                            half_height: h / 2.0,
                        };
                        let near = bead.blocks(&Point2::new(lower.x, lower.y), radius + width);
                        (near.is_some() && bead.z < lower.z + h).then_some(bead)
                    })
                    .collect();
                let rest = rest_height(&beads, &lower, radius - ball, ball)
                    .unwrap_or_else(|| panic!("{name} `{}`: no resting place", capsule.name));
                let smooth = lower.z - (radius - ball);
                let planned_gap = paused_at - (smooth + ball);
                let gap = paused_at - (rest + ball);
                let label = format!("{name}: {}", capsule.name);
                println!(
                    "| {label} | {planned_gap:.3} | {:.3} | {gap:.3} |",
                    rest - smooth
                );
                // The floor holds the ball no lower than the smooth end, and lifts it by less
                // than a layer.
                assert!(rest >= smooth - 1e-3, "{label}: rests below the smooth end");
                assert!(
                    rest - smooth < 0.5,
                    "{label}: lifted {:.3} mm",
                    rest - smooth
                );
                balls += 1;
                if gap < MARGIN {
                    within_margin.push(label);
                }
            }
        }
    }
    assert!(balls >= 9, "{balls} balls");
    assert_eq!(within_margin, BALLS_WITHIN_THE_MARGIN);
}
