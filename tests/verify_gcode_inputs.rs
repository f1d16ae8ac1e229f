//! `ballast verify --gcode` with options no printer takes: each refused with its range, at
//! once, with exit status 2.

mod cli_support;

use std::fs;
use std::path::Path;

use cli_support::{ballast, examples, stderr};

fn t_shape() -> String {
    examples()
        .join("t_shape.kdl")
        .to_str()
        .expect("a UTF-8 path")
        .to_string()
}

fn write(folder: &Path, name: &str, text: &str) -> String {
    let path = folder.join(name);
    fs::write(&path, text).unwrap();
    path.to_str().expect("a UTF-8 path").to_string()
}

#[test]
fn a_filament_diameter_outside_its_range_is_refused() {
    let folder = tempfile::tempdir().unwrap();
    let gcode = write(folder.path(), "a.gcode", "M83\nG1 Z0.3\nG1 X10 E1\n");
    for diameter in ["1e308", "0.4", "5.1", "NaN", "inf", "-1.75", "0"] {
        let option = format!("--filament-diameter={diameter}");
        let output = ballast(&["verify", &t_shape(), "--gcode", &gcode, &option]);
        assert_eq!(output.status.code(), Some(2), "{diameter}");
        assert!(
            stderr(&output).contains("give one from 0.5 to 5 mm"),
            "{}",
            stderr(&output)
        );
    }
    for diameter in ["0.5", "2.85", "5"] {
        let output = ballast(&[
            "verify",
            &t_shape(),
            "--gcode",
            &gcode,
            "--filament-diameter",
            diameter,
        ]);
        assert_eq!(
            output.status.code(),
            Some(1),
            "{diameter}: {}",
            stderr(&output)
        );
    }
}
