//! Progress of long stages on a terminal: one line on standard error, rewritten as each stage
//! starts and erased when the build is done. Nothing is printed when standard error is not a
//! terminal, so logs and pipes see only the results.

use std::io::{IsTerminal, Write};

use crate::compile::{Stage, Workspace};

/// Erases the line and moves back to its start.
const ERASE_LINE: &str = "\r\x1b[2K";

/// A progress sink for a [`Workspace`] when standard error is a terminal.
pub(super) fn on_terminal() -> Option<Box<dyn Fn(Stage) + Send + Sync>> {
    std::io::stderr().is_terminal().then(|| {
        Box::new(|stage: Stage| {
            let mut stderr = std::io::stderr().lock();
            let _ = write!(stderr, "{ERASE_LINE}{stage}…");
            let _ = stderr.flush();
        }) as Box<dyn Fn(Stage) + Send + Sync>
    })
}

/// Erases the progress line, if `workspace` shows one.
pub(super) fn clear(workspace: &Workspace) {
    if workspace.progress.is_some() && std::io::stderr().is_terminal() {
        eprint!("{ERASE_LINE}");
    }
}
