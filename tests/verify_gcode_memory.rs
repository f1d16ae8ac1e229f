//! `ballast verify --gcode` keeps nothing per move: a file of 3 million tiny extrusions (27 MB)
//! is checked within the memory of the project and the file's own bytes. (Alone in its test
//! binary: the peak is that of every child process this binary has run.)

mod cli_support;

use cli_support::{ballast, examples, stderr};

/// Peak resident memory of the children waited for so far, bytes.
#[cfg(target_os = "linux")]
fn children_peak() -> u64 {
    // SAFETY: `getrusage` fills the zeroed struct it is given.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    assert_eq!(
        unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) },
        0
    );
    // Kilobytes on Linux.
    usage.ru_maxrss as u64 * 1024
}

#[cfg(target_os = "linux")]
#[test]
fn millions_of_moves_cost_no_memory_each() {
    let moves = 3_000_000;
    let mut text = String::with_capacity(moves * 9 + 16);
    text.push_str("M83\nG1 Z0.2\n");
    for _ in 0..moves / 2 {
        text.push_str("G1 X1 E1\nG1 X0 E1\n");
    }
    let folder = tempfile::tempdir().unwrap();
    let gcode = folder.path().join("moves.gcode");
    std::fs::write(&gcode, &text).unwrap();
    let bytes = text.len() as u64;
    drop(text);
    let t_shape = examples().join("t_shape.kdl");
    let output = ballast(&[
        "verify",
        t_shape.to_str().unwrap(),
        "--gcode",
        gcode.to_str().unwrap(),
        "--json",
    ]);
    // Not the planned part: the check runs to the end and says so.
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    let peak = children_peak();
    // The project and its check take about 90 MB; segments kept at 72 bytes each (as
    // `read_program` does) would add 216 MB more.
    let allowed = 160_000_000 + bytes;
    assert!(
        peak < allowed,
        "peak {} MB for {moves} moves ({} MB of G-code)",
        peak >> 20,
        bytes >> 20
    );
}
