//! `ballast verify --gcode` on files no slicer writes: a pipe, a device, a file past the size
//! limit, plastic past any printer, filament diameters no printer feeds, and text that would
//! drive the terminal. Each ends in a diagnostic and exit status 2 (or a table with the text
//! made printable), at once.

mod cli_support;

use std::fs;
use std::path::{Path, PathBuf};

use cli_support::{ballast, examples, stderr, stdout};

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

#[cfg(unix)]
#[test]
fn a_pipe_or_a_device_is_refused_at_once() {
    let folder = tempfile::tempdir().unwrap();
    let fifo = folder.path().join("sliced.gcode");
    let name = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: `name` is a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
    for path in [fifo.to_str().unwrap(), "/dev/zero", "/dev/urandom"] {
        let output = ballast(&["verify", &t_shape(), "--gcode", path]);
        assert_eq!(output.status.code(), Some(2), "{path}: {}", stderr(&output));
        assert!(
            stderr(&output).contains("is not a regular file"),
            "{}",
            stderr(&output)
        );
    }
}

/// A file past the limit is refused by its size, before a byte is read (a sparse file: no
/// disk is used).
#[test]
fn a_file_past_the_size_limit_is_refused_by_its_size() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("huge.gcode");
    let file = fs::File::create(&path).unwrap();
    file.set_len(ballast::sliced::MAX_GCODE_BYTES + 1).unwrap();
    let output = ballast(&["verify", &t_shape(), "--gcode", path.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    let text = stderr(&output);
    assert!(text.contains("the most read is 1073741824 bytes"), "{text}");
    assert!(text.contains("docs/limits.md"), "{text}");
}

/// A project folder holding a copy of the T shape (its mesh and solution).
fn t_shape_copy() -> (tempfile::TempDir, PathBuf) {
    let folder = tempfile::tempdir().unwrap();
    fs::create_dir(folder.path().join("meshes")).unwrap();
    for name in ["t_shape.kdl", "t_shape.solution.kdl", "meshes/t_shape.obj"] {
        fs::copy(examples().join(name), folder.path().join(name)).unwrap();
    }
    let project = folder.path().join("t_shape.kdl");
    (folder, project)
}

/// Two extrusions of 10³⁰⁸ mm each (their sum is infinite) are an error at the line that
/// passes the limit, and `--calibrate` writes nothing; so is `E1e308`, which firmware reads as
/// two `E` words.
#[test]
fn plastic_past_any_printer_is_an_error_and_calibrates_nothing() {
    let (folder, project) = t_shape_copy();
    let calibration = folder.path().join("t_shape.calibration.json");
    let before = fs::read(&calibration).ok();
    let project = project.to_str().unwrap();
    let huge = format!("1{}", "0".repeat(308));
    let cases = [
        (
            format!("M83\nG1 Z0.2\nG1 X0 Y0\nG1 X10 E{huge}\nG1 X0 E{huge}\n"),
            "ballast::gcode::out_of_range",
            "G-code line 4:",
        ),
        (
            "M83\nG1 Z0.2\nG1 X0 Y0\nG1 X10 E1e308\nG1 X0 E1e308\n".to_string(),
            "ballast::gcode::repeated_word",
            "G-code line 4: `e308`",
        ),
    ];
    for (text, code, message) in cases {
        let gcode = write(folder.path(), "sliced.gcode", &text);
        let output = ballast(&["verify", project, "--gcode", &gcode, "--calibrate"]);
        assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
        let text = stderr(&output);
        assert!(text.contains(code) && text.contains(message), "{text}");
        assert!(!stdout(&output).contains("every goal is met"));
        assert_eq!(fs::read(&calibration).ok(), before, "nothing written");
    }
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

/// Object labels, `M117` messages and G-code lines with escape sequences (one sets the
/// terminal's title, one clears the screen) are printed with their control characters made
/// visible, in the table, in errors and in drawn diagnostics.
#[test]
fn text_from_the_file_cannot_drive_the_terminal() {
    let folder = tempfile::tempdir().unwrap();
    let title = "\u{1b}]0;pwned\u{7}";
    // The T's plan pauses after layer 57: a pause there showing another message.
    let mut text = format!("M83\n; printing object T{title}\u{9b}2J id:0 copy 0\n");
    for layer in 1..=57 {
        text.push_str(&format!(
            "G1 Z{}\nG1 X0 Y0\nG1 X100 E1\n",
            0.3 * layer as f64
        ));
    }
    // A message ends at a `;`, as for the firmware: this one clears the screen and rings.
    text.push_str("M117 ball\u{1b}[2J\u{7}\nM601\n");
    let gcode = write(folder.path(), "escape.gcode", &text);
    let table = ballast(&["verify", &t_shape(), "--gcode", &gcode]);
    assert_eq!(table.status.code(), Some(1), "{}", stderr(&table));
    let text = stdout(&table);
    assert!(
        text.contains("object `T\\u{1b}]0;pwned\\u{7}\\u{9b}2J id:0 copy 0`"),
        "{text}"
    );
    assert!(text.contains("it shows \"ball\\u{1b}[2J\\u{7}\""), "{text}");

    let two = format!(
        "; printing object a{title}\nG1 Z0.3\nG1 X1 E1\n; printing object b\u{1b}[2J\nG1 X2 E2\n"
    );
    let gcode = write(folder.path(), "two.gcode", &two);
    let unmatched = ballast(&["verify", &t_shape(), "--gcode", &gcode]);
    assert_eq!(unmatched.status.code(), Some(2));
    let text = stderr(&unmatched);
    assert!(
        text.contains("`a\\u{1b}]0;pwned\\u{7}`, `b\\u{1b}[2J`"),
        "{text}"
    );

    let bad = write(
        folder.path(),
        "bad.gcode",
        "G1 Z0.3\nG1 Xabc\u{1b}[2J\u{7} E1\n",
    );
    let unreadable = ballast(&["verify", &t_shape(), "--gcode", &bad]);
    assert_eq!(unreadable.status.code(), Some(2));
    let text = stderr(&unreadable);
    assert!(
        text.contains("`Xabc\\u{1b}[2J\\u{7}` is not a number"),
        "{text}"
    );
    assert!(text.contains("G1 Xabc\\u{1b}[2J\\u{7} E1"), "drawn: {text}");

    for output in [&table, &unmatched, &unreadable] {
        for printed in [&output.stdout, &output.stderr] {
            assert!(!printed.contains(&0x1b) && !printed.contains(&0x07));
            assert!(!String::from_utf8_lossy(printed).contains('\u{9b}'));
        }
    }
}

/// A label in another encoding than UTF-8 (Latin-1) is read with its bad bytes replaced: no
/// number or command holds one.
#[test]
fn text_that_is_not_utf8_is_read() {
    let folder = tempfile::tempdir().unwrap();
    let path = folder.path().join("latin1.gcode");
    let mut bytes = b"M83\n; printing object caf\xe9 id:0 copy 0\nG1 Z0.3\nG1 X10 E1\n".to_vec();
    bytes.extend_from_slice(b"; stop printing object caf\xe9 id:0 copy 0\n");
    fs::write(&path, bytes).unwrap();
    let output = ballast(&["verify", &t_shape(), "--gcode", path.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(stdout(&output).contains("object `caf\u{fffd} id:0 copy 0`"));
}
