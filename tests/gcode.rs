//! The G-code reader on hand-written programs whose deposit is known.

use ballast::gcode::{read_deposit, read_program, LayerDialect, ReadOptions};
use nalgebra::Point3;

const AREA: f64 = std::f64::consts::PI * 1.75 * 1.75 / 4.0;

#[test]
fn absolute_extrusion_with_a_retraction_and_a_reset() {
    let program = "\
G90 ; absolute positions
M82 ; absolute extrusion
G92 E0
G1 Z0.2 F3000
G1 X0 Y0
G1 X10 Y0 E1.0 ; 1 mm of filament along y = 0, centre (5, 0)
G1 E0.2 F2400 ; retract: no motion, no deposit
G1 X10 Y10 ; travel
G1 E1.0 ; unretract
G1 X0 Y10 E3.0 ; 2 mm along y = 10, centre (5, 10)
G92 E0
G1 X0 Y0 Z0.4 E0.5 ; 0.5 mm from (0, 10, 0.2) to (0, 0, 0.4), centre (0, 5, 0.3)
";
    let deposit = read_deposit(program, 1.75).unwrap();
    assert!((deposit.filament - 3.5).abs() < 1e-12, "{deposit:?}");
    assert!((deposit.volume - 3.5 * AREA).abs() < 1e-12);
    let expected = [
        (1.0 * 5.0 + 2.0 * 5.0) / 3.5,
        (2.0 * 10.0 + 0.5 * 5.0) / 3.5,
        (3.0 * 0.2 + 0.5 * 0.3) / 3.5,
    ];
    for (axis, want) in expected.iter().enumerate() {
        assert!((deposit.centroid[axis] - want).abs() < 1e-12, "{deposit:?}");
    }
    assert!((deposit.mass(1.24) - 3.5 * AREA * 1.24 / 1000.0).abs() < 1e-15);
}

#[test]
fn relative_extrusion_and_relative_positions() {
    let program = "\
M83
G1 X0 Y0 Z0.3
G1 X4 E0.4
G1 E-0.8
G1 Y4 E0.8 ; moves while it undoes the retraction: deposits 0.8 along x = 4
G91
G1 X-4 E0.4 ; relative: to (0, 4), 0.4 mm
";
    let deposit = read_deposit(program, 1.75).unwrap();
    assert!((deposit.filament - 1.6).abs() < 1e-12, "{deposit:?}");
    let x = (0.4 * 2.0 + 0.8 * 4.0 + 0.4 * 2.0) / 1.6;
    let y = (0.4 * 0.0 + 0.8 * 2.0 + 0.4 * 4.0) / 1.6;
    assert!((deposit.centroid.x - x).abs() < 1e-12, "{deposit:?}");
    assert!((deposit.centroid.y - y).abs() < 1e-12, "{deposit:?}");
    assert!((deposit.centroid.z - 0.3).abs() < 1e-12, "{deposit:?}");
}

#[test]
fn a_bad_number_names_its_line_and_nothing_deposited_is_the_origin() {
    let error = read_deposit("G1 X0\nG1 X1 Efoo\n", 1.75).unwrap_err();
    assert_eq!(error.line, 2);
    assert_eq!(error.word, "Efoo");
    assert!(error.to_string().contains("line 2"));
    let error = read_deposit("G1 Xinf\n", 1.75).unwrap_err();
    assert_eq!(error.line, 1);
    let empty = read_deposit("; nothing\nM104 S200\n", 1.75).unwrap();
    assert_eq!(empty.filament, 0.0);
    assert_eq!(empty.centroid, nalgebra::Point3::origin());
}

/// Two labelled objects, a purge line outside any label, a z-hop, and a pause after the second
/// layer with its message: what the reader finds in each.
#[test]
fn objects_layers_and_pauses() {
    let program = "\
M83
G1 Z0.2
G1 X0 Y-5 E1 ; purge line, outside any object
; printing object left id:0 copy 0
G1 X0 Y0 F600
G1 X10 Y0 E1
; stop printing object left id:0 copy 0
G1 Z0.6 ; z-hop travel
; printing object right id:1 copy 0
G1 X20 Y0 Z0.2
G1 X30 Y0 E1
; stop printing object right id:1 copy 0
;LAYER_CHANGE
G1 Z0.5
; printing object left id:0 copy 0
G1 X10 Y5 E0.5
; stop printing object left id:0 copy 0
G1 Z0.8
M117 Insert one 8 mm steel ball into capsule `keel`
m601 ; lower case, a comment
G1 E-1 ; retract: the pause's message is kept
; printing object left id:0 copy 0
G1 X0 Y5 Z0.8 E0.5
; stop printing object left id:0 copy 0
M601
";
    let read = read_program(program, &ReadOptions::default()).unwrap();
    let labels: Vec<_> = read.objects.iter().map(|o| o.label.as_deref()).collect();
    assert_eq!(
        labels,
        [Some("left id:0 copy 0"), Some("right id:1 copy 0"), None]
    );
    assert_eq!(read.objects[0].name(), Some("left"));
    assert_eq!(read.objects[2].name(), None);
    let counts: Vec<_> = read.objects.iter().map(|o| o.segments.len()).collect();
    assert_eq!(counts, [3, 1, 1]);
    assert_eq!(read.layers, [0.2, 0.5, 0.8]);
    assert!((read.layer_thickness(1) - 0.3).abs() < 1e-12);
    assert_eq!(read.layer_thickness(0), 0.2);
    assert_eq!(read.layer_thickness(3), 0.0);
    let left = &read.objects[0].segments;
    assert_eq!(left[0].start, Point3::new(0.0, 0.0, 0.2));
    assert_eq!(left[1].layer, 1);
    assert_eq!(left[1].line, 16);
    assert_eq!(read.pauses.len(), 2);
    let first = &read.pauses[0];
    assert_eq!(first.line, 20);
    assert_eq!(first.layers_done, 2);
    assert_eq!(first.height, Some(0.5));
    assert_eq!(
        first.message.as_deref(),
        Some("Insert one 8 mm steel ball into capsule `keel`")
    );
    assert_eq!(first.resume_height, Some(0.8));
    assert_eq!(read.pauses[1].layers_done, 3);
    assert_eq!(read.pauses[1].resume_height, None);
    assert_eq!(read.pauses[1].message, None);
    // The total deposit is every object's, the purge line included.
    assert!((read_deposit(program, 1.75).unwrap().filament - 4.0).abs() < 1e-12);
}

/// Without labels everything is one object; another pause command; OrcaSlicer's labels.
#[test]
fn one_object_without_labels_another_pause_command_and_orca_labels() {
    let program = "G1 Z0.3\nG1 X1 E1\nM400   u1\nG1 X2 E2\n";
    let options = ReadOptions {
        pause_gcode: "M400 U1".to_string(),
    };
    let read = read_program(program, &options).unwrap();
    assert_eq!(read.objects.len(), 1);
    assert_eq!(read.objects[0].label, None);
    assert_eq!(read.pauses.len(), 1);
    assert_eq!(read.pauses[0].layers_done, 1);
    assert!(read_program(program, &ReadOptions::default())
        .unwrap()
        .pauses
        .is_empty());
    let orca = "\
; start printing object, unique label id: 15
G1 Z0.2
G1 X1 E1
; stop printing object, unique label id: 15
";
    let read = read_program(orca, &ReadOptions::default()).unwrap();
    assert_eq!(read.objects.len(), 1);
    assert_eq!(read.objects[0].label.as_deref(), Some("15"));
    assert_eq!(read.objects[0].name(), Some("15"));
}

/// Firmware labels (`M486`) when the file has no label comments: named by `A`, the name kept
/// when the object starts again without it; `M486 S-1` ends an object.
#[test]
fn firmware_labels_without_label_comments() {
    let program = "\
M83
M486 T2
G1 Z0.2
M486 S0 A\"left\"
G1 X1 E1
M486 S-1
G1 X5 E1 ; outside any object
M486 S1
G1 X9 E1
M486 S0
G1 X2 E1
M486 S-1
";
    let read = read_program(program, &ReadOptions::default()).unwrap();
    let labels: Vec<_> = read.objects.iter().map(|o| o.label.as_deref()).collect();
    assert_eq!(labels, [Some("left"), Some("1"), None]);
    let counts: Vec<_> = read.objects.iter().map(|o| o.segments.len()).collect();
    assert_eq!(counts, [2, 1, 1]);
    // With label comments, M486 is not read a second time.
    let both = format!("; printing object left id:0 copy 0\n{program}");
    let read = read_program(&both, &ReadOptions::default()).unwrap();
    assert_eq!(read.objects.len(), 1);
    assert_eq!(read.objects[0].segments.len(), 4);
}

/// A file of many labelled objects, each printed twice (as a slicer prints objects layer by
/// layer): every label one object, in first-seen order, with both of its moves.
#[test]
fn many_labels_each_one_object_in_first_seen_order() {
    let objects = 20_000;
    let mut program = String::from("M83\nG1 Z0.2\n");
    for pass in 0..2 {
        for i in 0..objects {
            program.push_str(&format!(
                "; printing object part{i} id:{i} copy 0\nG1 X{i} Y{pass}\nG1 X{i}.5 Y{pass} E0.1\n; stop printing object part{i} id:{i} copy 0\n"
            ));
        }
    }
    let read = read_program(&program, &ReadOptions::default()).unwrap();
    assert_eq!(read.objects.len(), objects);
    for (i, object) in read.objects.iter().enumerate() {
        assert_eq!(object.name(), Some(format!("part{i}").as_str()));
        assert_eq!(object.segments.len(), 2);
    }
}

/// Where each layer starts, as PrusaSlicer (and SuperSlicer, OrcaSlicer) mark it: after
/// `;LAYER_CHANGE` and the `;Z:`/`;HEIGHT:` comments that follow it, whatever comes before the
/// layer's first extrusion (the Z move, a travel).
#[test]
fn prusaslicer_layer_changes_start_layers_after_their_height_comments() {
    let program = "\
M83
;LAYER_CHANGE
;Z:0.35
;HEIGHT:0.35
G1 Z.35 F7800
G1 X1 Y1
G1 X10 E1
G1 X10 Y10 E1
;LAYER_CHANGE
;Z:0.65
;HEIGHT:0.3
;BEFORE_LAYER_CHANGE
G1 Z.65 F7800
G1 X0 E1
";
    let read = read_program(program, &ReadOptions::default()).unwrap();
    assert_eq!(read.layers, [0.35, 0.65]);
    let starts: Vec<_> = read.layer_starts.iter().map(|s| s.insert_before).collect();
    assert_eq!(starts, [5, 12]);
    let marker = read.layer_starts[1].marker.unwrap();
    assert_eq!(marker.line, 9);
    assert_eq!(marker.dialect, LayerDialect::LayerChange);
    assert_eq!((marker.height, marker.thickness), (Some(0.65), Some(0.3)));
    assert_eq!(marker.number, None);
}

/// Bambu Studio's spelling: `; CHANGE_LAYER`, `; Z_HEIGHT:`, `; LAYER_HEIGHT:`.
#[test]
fn bambu_studio_change_layer_markers() {
    let program = "\
M83
; CHANGE_LAYER
; Z_HEIGHT: 0.2
; LAYER_HEIGHT: 0.2
G1 E-.8 F1800
; layer num/total_layer_count: 1/2
G1 Z.2
G1 X10 E1
; CHANGE_LAYER
; Z_HEIGHT: 0.4
; LAYER_HEIGHT: 0.2
G1 Z.4
G1 X0 E1
";
    let read = read_program(program, &ReadOptions::default()).unwrap();
    assert_eq!(read.layers, [0.2, 0.4]);
    let starts: Vec<_> = read.layer_starts.iter().map(|s| s.insert_before).collect();
    assert_eq!(starts, [5, 12]);
    let marker = read.layer_starts[0].marker.unwrap();
    assert_eq!(marker.dialect, LayerDialect::ChangeLayer);
    assert_eq!((marker.height, marker.thickness), (Some(0.2), Some(0.2)));
}

/// Cura: `;LAYER_COUNT:` is no layer, `;LAYER:n` (from 0) starts one, and the move up to the
/// next layer comes before its marker; `;MESH:NAME` labels objects, `;MESH:NONMESH` ends them,
/// and an object named after its STL file is named without its folders and `.stl`.
#[test]
fn cura_layer_numbers_and_mesh_labels() {
    let program = "\
;FLAVOR:Marlin
M82 ;absolute extrusion mode
G92 E0
;LAYER_COUNT:2
;LAYER:0
M107
G0 F3600 X44 Y44 Z0.35
;TYPE:SKIRT
G1 F1800 X45 Y44 E1
;TYPE:WALL-OUTER
;MESH:/tmp/build/box-stl/box.stl
G1 X55 Y44 E2
;MESH:lid.STL
G1 X55 Y54 E3
;MESH:NONMESH
G0 F600 X55 Y54 Z0.65
;TIME_ELAPSED:10.5
;LAYER:1
;TYPE:WALL-INNER
;MESH:/tmp/build/box-stl/box.stl
G1 X45 Y54 E4
";
    let read = read_program(program, &ReadOptions::default()).unwrap();
    assert_eq!(read.layers, [0.35, 0.65]);
    let starts: Vec<_> = read.layer_starts.iter().map(|s| s.insert_before).collect();
    assert_eq!(starts, [6, 19]);
    let numbers: Vec<_> = read
        .layer_starts
        .iter()
        .map(|s| s.marker.map(|m| (m.dialect, m.number)))
        .collect();
    assert_eq!(
        numbers,
        [
            Some((LayerDialect::LayerNumber, Some(0))),
            Some((LayerDialect::LayerNumber, Some(1)))
        ]
    );
    let names: Vec<_> = read.objects.iter().map(|o| o.name()).collect();
    assert_eq!(names, [Some("box"), Some("lid"), None]);
    let counts: Vec<_> = read.objects.iter().map(|o| o.segments.len()).collect();
    assert_eq!(counts, [2, 1, 1]);
}

/// A layer without a marker starts at its first extrusion; a marker followed by extrusions at
/// the current height (no new layer) is dropped, not given to the next layer.
#[test]
fn layers_without_markers_start_at_their_first_extrusion() {
    let program = "\
G1 Z0.3
G1 X1 E1
;LAYER_CHANGE
;Z:0.3
G1 X2 E2
G1 Z0.6
G1 X3 E3
";
    let read = read_program(program, &ReadOptions::default()).unwrap();
    assert_eq!(read.layers, [0.3, 0.6]);
    let starts: Vec<_> = read.layer_starts.iter().map(|s| s.insert_before).collect();
    assert_eq!(starts, [2, 7]);
    assert!(read.layer_starts.iter().all(|s| s.marker.is_none()));
}
