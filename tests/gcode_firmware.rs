//! The G-code reader on what firmware reads and slicers write beyond spaced `G1` lines: words
//! without spaces, arcs, numbers past any printer, many labels; and the one-pass scan against
//! the reading that keeps every segment.

use std::f64::consts::PI;

use ballast::gcode::{
    read_deposit, read_program, scan_program, GcodeErrorKind, ReadOptions, Segment,
    ARC_CHORDS_PER_TURN,
};
use nalgebra::Point3;

fn segments(text: &str) -> Vec<Segment> {
    let program = read_program(text, &ReadOptions::default()).expect("the program reads");
    program
        .objects
        .into_iter()
        .flat_map(|object| object.segments)
        .collect()
}

/// The same program spaced, unspaced, in lower case, with comments and line numbers: one
/// deposit, bit for bit.
#[test]
fn words_without_spaces_read_as_with_them() {
    let spaced = "\
M83
G1 Z0.2
G1 X0 Y0
G1 X10 Y10 E1
G1 X20 Y5 E0.5 F1800
G92 E0
G1 X0 Y0 Z0.4 E2
";
    let forms = [
        "M83\nG1Z0.2\nG1X0Y0\nG1X10Y10E1\nG1X20Y5E0.5F1800\nG92E0\nG1X0Y0Z0.4E2\n",
        "m83\ng1 z0.2\ng1x0y0\ng1 x10 y10 e1\ng1x20y5e0.5f1800\ng92 e0\ng1x0y0z.4e2\n",
        "M83;relative\nG1 Z0.2;up\nG01 X0 Y0\nG1 X10 Y10 E1;comment\nG1 X20Y5 E 0.5 F1800\nG92 E0\nG1X0 Y0Z0.4E2 ; done\n",
        "N1 M83*33\nN2 G1 Z0.2*40\nN3 G1 X0 Y0*33\nN4 G1 X10 Y10 E1*2\nN5 G1 X20 Y5 E0.5 F1800*0\nN6 G92 E0*1\nN7 G1 X0 Y0 Z0.4 E2*9\n",
    ];
    let expected = segments(spaced);
    assert_eq!(expected.len(), 3);
    let deposit = read_deposit(spaced, 1.75).unwrap();
    assert_eq!(deposit.filament, 3.5);
    for form in forms {
        assert_eq!(segments(form), expected, "{form}");
        assert_eq!(read_deposit(form, 1.75).unwrap(), deposit, "{form}");
    }
}

/// G-code numbers have no exponent: `E1e308` is `E1` then `e308`, one axis twice, which no
/// firmware reads alike (Marlin keeps the first, Klipper the last): an error at the word.
#[test]
fn an_axis_given_twice_is_an_error() {
    let error = read_deposit("M83\nG1 Z0.2\nG1 X10 E1e308\n", 1.75).unwrap_err();
    assert_eq!((error.line, error.kind), (3, GcodeErrorKind::Repeated));
    assert_eq!(error.word, "e308");
    let error = read_deposit("G1 X1 X2\n", 1.75).unwrap_err();
    assert_eq!(
        (error.word.as_str(), error.kind),
        ("X2", GcodeErrorKind::Repeated)
    );
    // Letters ballast does not read may repeat.
    assert!(read_deposit("G1 X1 F1 F2 E1\n", 1.75).is_ok());
}

/// Numbers past any printer are refused at their line, so no sum of them overflows: two
/// extrusions of 10³⁰⁸ mm (written out in digits), a relative move past 1 km, a number past
/// the largest float, an absolute `E` past 10⁹ mm.
#[test]
fn numbers_past_any_printer_are_errors_at_their_line() {
    let huge = format!("1{}", "0".repeat(308));
    let text = format!("M83\nG1 Z0.2\nG1 X0 Y0\nG1 X10 E{huge}\nG1 X0 E{huge}\n");
    let error = read_deposit(&text, 1.75).unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (4, GcodeErrorKind::TooMuchFilament)
    );
    assert!(error.word.starts_with("E1000") && error.word.ends_with('…'));
    assert!(error.to_string().starts_with("G-code line 4: "), "{error}");

    // Within the limit each, past it together.
    let text = "M83\nG1 Z0.2\nG1 X10 E600000000\nG1 X0 E600000000\n";
    let error = read_deposit(text, 1.75).unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (4, GcodeErrorKind::TooMuchFilament)
    );

    let text = "G91\nG1 Z0.2\nG1 X600000 E1\nG1 X600000 E1\n";
    let error = read_deposit(text, 1.75).unwrap_err();
    assert_eq!((error.line, error.kind), (4, GcodeErrorKind::OutOfRange));
    assert_eq!(error.word, "X600000");

    let text = format!("G1 Y1{}\n", "9".repeat(400));
    let error = read_deposit(&text, 1.75).unwrap_err();
    assert_eq!((error.line, error.kind), (1, GcodeErrorKind::OutOfRange));

    let error = read_deposit("G92 E2000000000\n", 1.75).unwrap_err();
    assert_eq!(error.kind, GcodeErrorKind::TooMuchFilament);
    // What any printer does reads.
    let deposit = read_deposit("G1 Z0.2\nG1 X-999999 Y999999 E99999\n", 1.75).unwrap();
    assert!(deposit.filament == 99999.0 && deposit.centroid.x.is_finite());
}

/// A full circle drawn by `G2` with its centre at `I`, `J`: the filament it feeds, along
/// chords of the circle whose total length is 2πr (less what chords cut), centred on the
/// circle's centre; a half circle by `G3` with `R` has its centroid 2r/π from the centre.
#[test]
fn arcs_deposit_along_the_circle() {
    let r = 10.0;
    let text = "M83\nG1 Z0.2\nG1 X110 Y100\nG2 I-10 J0 E5\nG1 X120 Y100 E1\n";
    let all = segments(text);
    assert_eq!(all.len(), ARC_CHORDS_PER_TURN + 1);
    let (arc, after) = all.split_at(ARC_CHORDS_PER_TURN);
    let length: f64 = arc.iter().map(|s| (s.end - s.start).norm()).sum();
    let chords = ARC_CHORDS_PER_TURN as f64;
    let expected = 2.0 * chords * r * (PI / chords).sin();
    assert!((length - expected).abs() < 1e-9, "{length} {expected}");
    assert!((length - 2.0 * PI * r).abs() < 2e-3 * 2.0 * PI * r);
    for s in arc {
        assert!(
            ((s.end.coords.xy() - nalgebra::Vector2::new(100.0, 100.0)).norm() - r).abs() < 1e-9
        );
        assert!((s.filament - 5.0 / chords).abs() < 1e-15);
        assert_eq!((s.line, s.layer, s.start.z), (4, 0, 0.2));
    }
    // Clockwise: from (110, 100) down to (100, 90) first.
    assert!(arc[ARC_CHORDS_PER_TURN / 4 - 1].end.y < 90.0 + 1e-9);
    assert!(arc[ARC_CHORDS_PER_TURN / 4 - 1].end.x < 100.0 + 1e-9);
    // The circle ends where it began, and the next move starts there.
    assert_eq!(arc.last().unwrap().end, Point3::new(110.0, 100.0, 0.2));
    assert_eq!(after[0].start, Point3::new(110.0, 100.0, 0.2));

    let circle = read_deposit("M83\nG1 Z0.2\nG1 X110 Y100\nG2 I-10 J0 E5\n", 1.75).unwrap();
    assert!((circle.filament - 5.0).abs() < 1e-12);
    let centre = Point3::new(100.0, 100.0, 0.2);
    assert!(
        (circle.centroid - centre).norm() < 1e-9,
        "{:?}",
        circle.centroid
    );

    // The upper half, counter-clockwise by R from (110, 100) to (90, 100).
    let half = read_deposit("M83\nG1 Z0.2\nG1 X110 Y100\nG3 X90 Y100 R10 E3\n", 1.75).unwrap();
    assert!(
        (half.centroid.x - 100.0).abs() < 1e-9,
        "{:?}",
        half.centroid
    );
    let arm = half.centroid.y - 100.0;
    assert!((arm - 2.0 * r / PI).abs() < 1e-3 * r, "{arm}");
    // Clockwise, the lower half.
    let lower = read_deposit("M83\nG1 Z0.2\nG1 X110 Y100\nG2 X90 Y100 R10 E3\n", 1.75).unwrap();
    assert!(
        (lower.centroid.y - 100.0 + arm).abs() < 1e-9,
        "{:?}",
        lower.centroid
    );
    // A quarter by R, the short way round; by a negative R, the long way (three quarters).
    let quarter = "M83\nG1 Z0.2\nG1 X110 Y100\nG3 X100 Y110 R10 E1\n";
    assert_eq!(segments(quarter).len(), ARC_CHORDS_PER_TURN / 4);
    let long = segments(&quarter.replace("R10", "R-10"));
    assert_eq!(long.len(), ARC_CHORDS_PER_TURN * 3 / 4);
    let centre = nalgebra::Vector2::new(110.0, 110.0);
    assert!(long
        .iter()
        .all(|s| ((s.end.coords.xy() - centre).norm() - r).abs() < 1e-9));
    // A quarter by I/J, relative positions, and a rising helix: the chords climb evenly.
    let helix = segments("M83\nG91\nG1 Z0.2\nG3 X-10 Y10 Z1 I-10 E1\n");
    assert_eq!(helix.len(), ARC_CHORDS_PER_TURN / 4);
    let top = helix.last().unwrap().end;
    assert_eq!(top, Point3::new(-10.0, 10.0, 1.2));
    assert!((helix[0].end.z - (0.2 + 1.0 / 16.0)).abs() < 1e-12);
}

/// The same circle as one `G2` and as the chords the reader splits it into, written as `G1`
/// moves: one deposit.
#[test]
fn an_arc_deposits_what_its_chords_do() {
    let arc = "M83\nG1 Z0.3\nG1 X5 Y0\nG3 X-5 Y0 I-5 J0 E2\nG3 X5 Y0 I5 J0 E2\n";
    let mut lines = String::from("M83\nG1 Z0.3\nG1 X5 Y0\n");
    for s in segments(arc) {
        lines.push_str(&format!("G1 X{} Y{} E{}\n", s.end.x, s.end.y, s.filament));
    }
    let (a, b) = (
        read_deposit(arc, 1.75).unwrap(),
        read_deposit(&lines, 1.75).unwrap(),
    );
    assert!((a.filament - b.filament).abs() < 1e-12);
    assert!((a.centroid - b.centroid).norm() < 1e-12, "{a:?} {b:?}");
}

#[test]
fn arcs_that_are_not_arcs_are_errors() {
    let cases = [
        ("G1 X1 Y1\nG2 X5 Y5 E1\n", "neither"),
        ("G1 X1 Y1\nG2 X5 Y5 I0 J0 E1\n", "centre is its start"),
        ("G1 X1 Y1\nG3 R5 E1\n", "`R` must end elsewhere"),
        ("G18\nG1 X1 Y1\nG2 X5 Y5 I1 E1\n", "XY plane"),
        ("G1 X1 Y1\nG2 I1 P2.5 E1\n", "full turns"),
        ("G1 X1 Y1\nG2 I1 P101 E1\n", "full turns"),
    ];
    for (text, why) in cases {
        let error = read_deposit(text, 1.75).unwrap_err();
        assert!(matches!(error.kind, GcodeErrorKind::NotAnArc(_)), "{text}");
        assert!(error.to_string().contains(why), "{error}");
    }
    // Whole extra turns (Marlin's `P`) at the start change nothing: a spiral lift (Bambu
    // Studio's `G2 Z… I… J… P1`, a travel) ends above its start.
    let lift = "M83\nG1 Z0.2 X10 Y10\nG2 Z0.6 I0.86 J0.86 P1 F20000\nG1 X12 E1\n";
    assert_eq!(segments(lift)[0].start, Point3::new(10.0, 10.0, 0.6));
    assert_eq!(
        segments("G1 X1 Y1\nG2 I1 P3 E1\n"),
        segments("G1 X1 Y1\nG2 I1 E1\n")
    );
    // Back in the XY plane, arcs read again; an arc without `E` moves the nozzle only.
    let text = "G18\nG17\nM83\nG1 Z0.2 X1\nG2 I1 J0\nG1 X3 E1\n";
    assert_eq!(segments(text)[0].start, Point3::new(1.0, 0.0, 0.2));
}

/// The scan hands over the segments `read_program` keeps, in print order, each with its
/// object's id.
#[test]
fn a_scan_sees_every_segment_in_print_order() {
    let text = "\
M83
G1 Z0.2
G1 X0 Y-5 E1
; printing object left id:0 copy 0
G1 X10 E1
; stop printing object left id:0 copy 0
; printing object right id:1 copy 0
G2 X20 Y0 I5 E1
; stop printing object right id:1 copy 0
; printing object left id:0 copy 0
G1 X0 E1
";
    let program = read_program(text, &ReadOptions::default()).unwrap();
    let mut seen: Vec<(usize, Segment)> = Vec::new();
    let outline = scan_program(text, &ReadOptions::default(), |id, s| seen.push((id, *s))).unwrap();
    assert_eq!(outline.layers, program.layers);
    assert_eq!(outline.objects.len(), program.objects.len());
    for (object, read) in outline.objects.iter().zip(&program.objects) {
        assert_eq!(object.label, read.label);
        assert_eq!(object.segments, read.segments.len());
        let mine: Vec<Segment> = seen
            .iter()
            .filter(|(id, _)| *id == object.id)
            .map(|(_, s)| *s)
            .collect();
        assert_eq!(mine, read.segments);
    }
    // Print order: the purge line (unlabelled, listed last) first.
    assert_eq!(outline.objects.last().unwrap().label, None);
    assert_eq!(seen[0].0, outline.objects.last().unwrap().id);
    let lines: Vec<usize> = seen.iter().map(|(_, s)| s.line).collect();
    assert!(lines.windows(2).all(|w| w[0] <= w[1]), "{lines:?}");
}

/// 100 000 firmware labels, each started three times: each found again by its number (a
/// lookup by hash; a linear one took a minute).
#[test]
fn many_firmware_labels_are_looked_up_by_hash() {
    let objects = 100_000;
    let mut text = String::from("M83\nG1 Z0.2\n");
    for pass in 0..3 {
        for i in 0..objects {
            let name = if pass == 0 {
                format!(" A\"part{i}\"")
            } else {
                String::new()
            };
            let y = i + 1;
            text.push_str(&format!(
                "M486 S{i}{name}\nG1 X{pass} Y{y} E0.1\nM486 S-1\n"
            ));
        }
    }
    let outline = scan_program(&text, &ReadOptions::default(), |_, _| {}).unwrap();
    assert_eq!(outline.objects.len(), objects);
    assert_eq!(outline.objects[77_777].label.as_deref(), Some("part77777"));
    assert!(outline.objects.iter().all(|o| o.segments == 3));
}

/// Labels and messages longer than any printer shows, and more pauses than any print has,
/// are errors at their line.
#[test]
fn texts_and_pauses_are_bounded() {
    let long = "x".repeat(ballast::gcode::MAX_TEXT_BYTES + 1);
    let error = read_deposit(&format!("G1 X1\n; printing object {long}\n"), 1.75).unwrap_err();
    assert_eq!((error.line, error.kind), (2, GcodeErrorKind::TooLong));
    assert_eq!(error.word.chars().count(), 41);
    let error = read_deposit(&format!("M117 {long}\n"), 1.75).unwrap_err();
    assert_eq!(error.kind, GcodeErrorKind::TooLong);
    let pauses = "M601\n".repeat(ballast::gcode::MAX_PAUSES + 1);
    let error = read_deposit(&pauses, 1.75).unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (
            ballast::gcode::MAX_PAUSES + 1,
            GcodeErrorKind::TooManyPauses
        )
    );
}

/// A line of 15 MB (words no reader uses, then a move) is read, word by word on slices of the
/// line (it once took 3 GB: every word an upper-cased string). The time is the benchmarks'.
#[test]
fn a_long_line_is_read() {
    let mut text = String::from("M83\nG1 Z0.2\nG1");
    for _ in 0..5_000_000 {
        text.push_str(" F1");
    }
    text.push_str("F2X5E1\n");
    let deposit = read_deposit(&text, 1.75).unwrap();
    assert_eq!(deposit.filament, 1.0);
}
