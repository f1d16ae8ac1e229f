//! The insertion sheet: a markdown page to print beside the printer, per part its orientation,
//! every pause (layer, heights, which balls go in) and a side view as an SVG picture, plus the
//! balls to buy.

use std::collections::BTreeMap;
use std::fmt::Write;

use super::{number, BedMesh, BedPart, PrintSettings, PAUSE_GCODE};

/// The sheet's markdown and its pictures.
#[derive(Clone, Debug, PartialEq)]
pub struct Sheet {
    /// The markdown page.
    pub markdown: String,
    /// Per part, the picture's file name (beside the page, as the page links it) and its SVG
    /// text.
    pub pictures: Vec<(String, String)>,
}

/// The insertion sheet of `parts` printed with `settings`; pictures are named
/// `{stem}-{part}.svg`.
pub fn write_sheet(title: &str, parts: &[BedPart], settings: &PrintSettings, stem: &str) -> Sheet {
    let mut md = String::new();
    let _ = writeln!(md, "# Insertion sheet: {title}\n");
    let _ = writeln!(
        md,
        "Print settings: layer height {} mm, first layer {} mm, {} perimeters, {} top and {} \
         bottom solid layers, {}% infill, support off. Each pause runs `{PAUSE_GCODE}`: drop the \
         balls in, then resume.\n",
        number(settings.layer_height, 4),
        number(settings.first_layer_height, 4),
        settings.perimeters,
        settings.top_solid_layers,
        settings.bottom_solid_layers,
        number(100.0 * settings.infill, 2),
    );

    md.push_str("## Balls to buy\n\n| steel ball | count |\n| --- | --- |\n");
    let mut balls: BTreeMap<String, (f64, usize)> = BTreeMap::new();
    for void in parts.iter().flat_map(|p| &p.voids) {
        let key = format!("{:012.4}", void.ball_diameter);
        balls.entry(key).or_insert((void.ball_diameter, 0)).1 += 1;
    }
    for (diameter, count) in balls.values() {
        let _ = writeln!(md, "| {} mm | {count} |", number(*diameter, 3));
    }
    let total: usize = balls.values().map(|b| b.1).sum();
    let _ = writeln!(
        md,
        "\nIn all: {total} {}.\n",
        plural(total, "ball", "balls")
    );

    let mut pictures = Vec::new();
    for part in parts {
        let _ = writeln!(md, "## Part `{}`\n", part.name);
        let _ = writeln!(md, "Orientation on the bed: {}.\n", part.orientation);
        let file = format!("{stem}-{}.svg", file_name(&part.name));
        let _ = writeln!(md, "![`{}` seen from the front]({file})\n", part.name);
        if part.voids.is_empty() {
            md.push_str("No pause: this part holds no ball.\n\n");
        } else if !part.pauses.is_empty() {
            md.push_str(
                "| pause | after layer | printed to (mm) | resumes with the layer to (mm) | balls |\n\
                 | --- | --- | --- | --- | --- |\n",
            );
            for (i, pause) in part.pauses.iter().enumerate() {
                let balls: Vec<String> = pause
                    .voids
                    .iter()
                    .map(|&v| {
                        let void = &part.voids[v];
                        format!(
                            "one {} mm ball into `{}`",
                            number(void.ball_diameter, 3),
                            void.name
                        )
                    })
                    .collect();
                let _ = writeln!(
                    md,
                    "| {} | {} | {} | {} | {} |",
                    i + 1,
                    pause.layers_done,
                    number(pause.height, 3),
                    number(pause.resume_height, 3),
                    balls.join("; ")
                );
            }
            md.push('\n');
        }
        let missing: Vec<&str> = part
            .voids
            .iter()
            .enumerate()
            .filter(|(v, _)| !part.pauses.iter().any(|p| p.voids.contains(v)))
            .map(|(_, void)| void.name.as_str())
            .collect();
        if !missing.is_empty() {
            let _ = writeln!(
                md,
                "**No pause is planned for the ball of {}.**\n",
                missing
                    .iter()
                    .map(|n| format!("`{n}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        pictures.push((file, side_view(part)));
    }
    Sheet {
        markdown: md,
        pictures,
    }
}

fn plural<'a>(n: usize, one: &'a str, many: &'a str) -> &'a str {
    if n == 1 {
        one
    } else {
        many
    }
}

/// `name` with every character but ASCII letters, digits, `-` and `_` replaced by `_`: a
/// component's name as part of a file name.
pub fn file_name(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Raster rows (and at most as many columns) of the silhouette.
const ROWS: f64 = 240.0;
/// Room around the drawing for the labels, mm.
const MARGIN: f64 = 4.0;

/// The part seen from the front (looking along +y, x to the right, z up) at 1 mm per SVG unit:
/// its silhouette, each capsule, each ball where it comes to rest, the bed and every pause
/// height as a line.
fn side_view(part: &BedPart) -> String {
    let (low, high) = bounds(&part.surface);
    let extent = (high[0] - low[0]).max(high[1] - low[1]).max(1e-3);
    let cell = extent / ROWS;
    let label_room = 38.0;
    let width = high[0] - low[0] + 2.0 * MARGIN + label_room;
    let height = high[1] - low[1] + 2.0 * MARGIN;
    let x = |v: f64| number(v - low[0] + MARGIN, 2);
    let y = |v: f64| number(high[1] - v + MARGIN, 2);

    let mut svg = String::new();
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}mm\" height=\"{h}mm\" \
         viewBox=\"0 0 {w} {h}\" font-family=\"sans-serif\" font-size=\"3\">",
        w = number(width, 2),
        h = number(height, 2)
    );
    let _ = writeln!(
        svg,
        "<title>{} seen from the front</title>",
        escape(&part.name)
    );
    svg.push_str("<path fill=\"#c8c8c8\" d=\"");
    for (start, end, bottom, top) in rectangles(&silhouette(&part.surface, low, cell)) {
        let _ = write!(
            svg,
            "M{} {}H{}V{}H{}z",
            x(low[0] + start as f64 * cell),
            y(low[1] + top as f64 * cell),
            x(low[0] + end as f64 * cell),
            y(low[1] + bottom as f64 * cell),
            x(low[0] + start as f64 * cell),
        );
    }
    svg.push_str("\"/>\n");
    let _ = writeln!(
        svg,
        "<line x1=\"{}\" y1=\"{b}\" x2=\"{}\" y2=\"{b}\" stroke=\"black\" stroke-width=\"0.4\"/>",
        x(low[0] - MARGIN / 2.0),
        x(high[0] + MARGIN / 2.0),
        b = y(0.0)
    );
    for void in &part.voids {
        let _ = writeln!(
            svg,
            "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#ffffff\" \
             stroke-width=\"{}\" stroke-linecap=\"round\"/>",
            x(void.from.x),
            y(void.from.z),
            x(void.to.x),
            y(void.to.z),
            number(2.0 * void.radius, 3)
        );
        let ball = void.ball_rest();
        let _ = writeln!(
            svg,
            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"#4a5a6a\"><title>{} mm ball in `{}`</title></circle>",
            x(ball.x),
            y(ball.z),
            number(void.ball_diameter / 2.0, 3),
            number(void.ball_diameter, 3),
            escape(&void.name)
        );
    }
    for (i, pause) in part.pauses.iter().enumerate() {
        let _ = writeln!(
            svg,
            "<line x1=\"{}\" y1=\"{h}\" x2=\"{}\" y2=\"{h}\" stroke=\"#c03020\" \
             stroke-width=\"0.3\" stroke-dasharray=\"1.5 1\"/>",
            x(low[0] - MARGIN / 2.0),
            x(high[0] + MARGIN / 2.0),
            h = y(pause.height)
        );
        let _ = writeln!(
            svg,
            "<text x=\"{}\" y=\"{}\" fill=\"#c03020\">pause {}: layer {}, {} mm</text>",
            x(high[0] + MARGIN),
            number(high[1] - pause.height + MARGIN + 1.0, 2),
            i + 1,
            pause.layers_done,
            number(pause.height, 2)
        );
    }
    svg.push_str("</svg>\n");
    svg
}

fn escape(text: &str) -> String {
    super::xml::escape(text)
}

/// Lowest and highest x and z of `mesh`.
fn bounds(mesh: &BedMesh) -> ([f64; 2], [f64; 2]) {
    let mut low = [f64::INFINITY; 2];
    let mut high = [f64::NEG_INFINITY; 2];
    for p in &mesh.positions {
        for (k, v) in [p.x, p.z].into_iter().enumerate() {
            low[k] = low[k].min(v);
            high[k] = high[k].max(v);
        }
    }
    if mesh.positions.is_empty() {
        return ([0.0; 2], [0.0; 2]);
    }
    (low, high)
}

/// The runs of `rows` merged with the same run in the rows above: `(first column, past the last,
/// first row, past the last)`, in order of their first row, then column.
fn rectangles(rows: &[Vec<(usize, usize)>]) -> Vec<(usize, usize, usize, usize)> {
    let mut done = Vec::new();
    let mut open: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    for (row, runs) in rows.iter().enumerate() {
        let closed: Vec<(usize, usize)> = open
            .keys()
            .filter(|run| !runs.contains(run))
            .copied()
            .collect();
        for run in closed {
            let first = open.remove(&run).unwrap_or(row);
            done.push((run.0, run.1, first, row));
        }
        for &run in runs {
            open.entry(run).or_insert(row);
        }
    }
    for (run, first) in open {
        done.push((run.0, run.1, first, rows.len()));
    }
    done.sort_by_key(|&(start, _, first, _)| (first, start));
    done
}

/// The mesh projected onto the x-z plane on a raster of square cells of side `cell` from `low`:
/// per row (bottom first), the runs of covered columns as `(first, past the last)`. A cell is
/// covered when a triangle's projection covers the middle of its row anywhere in it.
fn silhouette(mesh: &BedMesh, low: [f64; 2], cell: f64) -> Vec<Vec<(usize, usize)>> {
    let rows = ROWS as usize + 1;
    let mut covered = vec![vec![false; rows]; rows];
    for t in &mesh.triangles {
        let corners = t.map(|i| {
            let p = mesh.positions[i as usize];
            ((p.x - low[0]) / cell, (p.z - low[1]) / cell)
        });
        let z_low = corners.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
        let z_high = corners
            .iter()
            .map(|c| c.1)
            .fold(f64::NEG_INFINITY, f64::max);
        let first = (z_low - 0.5).ceil().max(0.0) as usize;
        let last = ((z_high - 0.5).floor().max(-1.0) + 1.0) as usize;
        let last = last.min(rows).max(first);
        for (row, cells) in covered.iter_mut().enumerate().take(last).skip(first) {
            let z = row as f64 + 0.5;
            let mut span = (f64::INFINITY, f64::NEG_INFINITY);
            for k in 0..3 {
                let (a, b) = (corners[k], corners[(k + 1) % 3]);
                if (a.1 - z) * (b.1 - z) <= 0.0 && a.1 != b.1 {
                    let x = a.0 + (z - a.1) / (b.1 - a.1) * (b.0 - a.0);
                    span = (span.0.min(x), span.1.max(x));
                }
            }
            if span.0 > span.1 {
                continue;
            }
            let start = span.0.floor().max(0.0) as usize;
            let end = (span.1.ceil().max(0.0) as usize).min(rows);
            for c in &mut cells[start..end.max(start)] {
                *c = true;
            }
        }
    }
    covered
        .iter()
        .map(|row| {
            let mut runs = Vec::new();
            let mut start = None;
            for (i, &c) in row.iter().chain([false].iter()).enumerate() {
                match (c, start) {
                    (true, None) => start = Some(i),
                    (false, Some(s)) => {
                        runs.push((s, i));
                        start = None;
                    }
                    _ => {}
                }
            }
            runs
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::test_parts::{box_with_two_capsules, settings};
    use super::*;

    #[test]
    fn the_sheet_lists_every_pause_and_the_balls_to_buy() {
        let part = box_with_two_capsules();
        let sheet = write_sheet(
            "block.kdl",
            std::slice::from_ref(&part),
            &settings(),
            "insertion",
        );
        let md = &sheet.markdown;
        assert!(md.contains("| 5 mm | 1 |\n| 7 mm | 1 |\n"), "{md}");
        assert!(md.contains("In all: 2 balls."));
        assert!(
            md.contains("| 1 | 24 | 7.25 | 7.55 | one 5 mm ball into `tip` |"),
            "{md}"
        );
        assert!(
            md.contains("| 2 | 34 | 10.25 | 10.55 | one 7 mm ball into `keel` |"),
            "{md}"
        );
        assert!(md.contains("![`block` seen from the front](insertion-block.svg)"));
        assert!(!md.contains("No pause"));
        assert_eq!(sheet.pictures.len(), 1);
        assert_eq!(sheet.pictures[0].0, "insertion-block.svg");
        assert_eq!(
            sheet,
            write_sheet("block.kdl", &[part], &settings(), "insertion"),
            "deterministic"
        );
    }

    #[test]
    fn a_capsule_without_a_pause_is_called_out() {
        let mut part = box_with_two_capsules();
        part.pauses.remove(1);
        let sheet = write_sheet("b", &[part], &settings(), "s");
        assert!(sheet
            .markdown
            .contains("**No pause is planned for the ball of `keel`.**"));
    }

    #[test]
    fn the_silhouette_of_a_box_fills_its_rectangle_and_the_pictures_mark_pauses_and_balls() {
        let part = box_with_two_capsules();
        // 40 × 20 mm seen from the front: 240 columns by 120 rows at 1/6 mm.
        let (low, _) = bounds(&part.surface);
        let rows = silhouette(&part.surface, low, 40.0 / ROWS);
        let filled: Vec<&Vec<(usize, usize)>> = rows.iter().filter(|r| !r.is_empty()).collect();
        assert_eq!(filled.len(), 120);
        assert!(filled.iter().all(|r| r.as_slice() == [(0, 240)]));
        assert_eq!(rectangles(&rows), [(0, 240, 0, 120)]);
        let steps = [vec![(0, 4)], vec![(0, 4), (6, 8)], vec![(6, 8)], vec![]];
        assert_eq!(rectangles(&steps), [(0, 4, 0, 2), (6, 8, 1, 3)]);

        let svg = side_view(&part);
        assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"86mm\""));
        assert_eq!(svg.matches("<circle").count(), 2);
        assert_eq!(svg.matches("stroke-dasharray").count(), 2);
        assert!(svg.contains("pause 1: layer 24, 7.25 mm"));
        // The keel's ball rests at the bottom of its capsule: centre 3.5 mm above its floor at
        // z = 3, so at z = 6.5, drawn 20 - 6.5 + 4 below the top.
        assert!(
            svg.contains("<circle cx=\"14\" cy=\"17.5\" r=\"3.5\""),
            "{svg}"
        );
    }
}
