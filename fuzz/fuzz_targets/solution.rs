//! Solution-file text read against the T shape example project, and the diagnostics drawn.
#![no_main]

use std::path::Path;
use std::sync::OnceLock;

use ballast::spec::model::Project;
use libfuzzer_sys::fuzz_target;

/// The project the solution files are read against.
fn project() -> &'static Project {
    static PROJECT: OnceLock<Project> = OnceLock::new();
    PROJECT.get_or_init(|| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/t_shape.kdl");
        let text = std::fs::read_to_string(&path).unwrap();
        ballast::spec::parse_project(&text, &path).project.unwrap()
    })
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let parsed = ballast::spec::parse_solution(text, Path::new("fuzz.solution.kdl"), project());
    let _ = ballast::diagnostic::render_plain(&parsed.problems, "fuzz.solution.kdl", text);
});
