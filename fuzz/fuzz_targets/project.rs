//! Project text through the whole front end (parse, check, resolve) and the diagnostics drawn.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let parsed = ballast::spec::parse_project(text, Path::new("fuzz/project.kdl"));
    assert_eq!(
        parsed.project.is_some(),
        !parsed.problems.iter().any(|p| p.is_error())
    );
    let _ = ballast::diagnostic::render_plain(&parsed.problems, "project.kdl", text);
});
