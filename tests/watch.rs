//! `ballast watch` end to end: the real binary watches a scratch folder while the tests edit it.
//!
//! Every wait polls the binary's output for the event it waits for, until a generous deadline
//! ([`timeout`]: 15 minutes, or `BALLAST_TEST_TIMEOUT` seconds), so a loaded machine only makes
//! the tests slower; a test that gives up says what it waited for and what was printed. The few
//! negative checks (no rebuild happened) wait a fixed time well beyond the debounce window and
//! look for a build starting, not only one finishing.

mod edit_support;

use std::ffi::OsStr;
use std::fs;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

/// How long a test waits for an event (a build finishing, a line printed) before it gives up:
/// `BALLAST_TEST_TIMEOUT` seconds when set, else 15 minutes. Optimizing builds take seconds in a
/// debug build, and many times that on a machine busy with other builds; the deadline only
/// bounds a test that would otherwise hang.
fn timeout() -> Duration {
    const DEFAULT_SECONDS: u64 = 900;
    let seconds = std::env::var("BALLAST_TEST_TIMEOUT")
        .ok()
        .map(|text| {
            text.trim().parse::<u64>().unwrap_or_else(|_| {
                panic!("BALLAST_TEST_TIMEOUT={text:?} is not a whole number of seconds")
            })
        })
        .unwrap_or(DEFAULT_SECONDS);
    Duration::from_secs(seconds)
}

/// Longer than the debounce window and the time a fast build takes, for checks that nothing
/// happened.
const QUIET: Duration = Duration::from_millis(2500);

/// Printed once per finished build, good or not. A rebuild after an edit that leaves the meshes
/// alone writes early results first (the last design judged, then perhaps a search from it),
/// each saying what follows (`; now ...`); those lines do not end the build.
const GOOD: &str = "  wrote ";
const EARLY: &str = "; now ";
const BAD: &str = "the last good outputs are left as they were";

/// A `ballast watch` process and everything it has printed so far (standard output and error
/// interleaved by line). Killed when dropped.
struct Watch {
    child: Child,
    output: Arc<Mutex<String>>,
}

impl Watch {
    /// Watches `project` without the disk cache, so no test writes into the user's cache folder.
    fn start(project: &Path, args: &[&str]) -> Watch {
        Watch::start_cached(project, args, "off")
    }

    /// Watches `project` with the disk cache in `cache`.
    fn start_cached(project: &Path, args: &[&str], cache: impl AsRef<OsStr>) -> Watch {
        let mut child = Command::new(env!("CARGO_BIN_EXE_ballast"))
            .env("BALLAST_CACHE_DIR", cache)
            .arg("watch")
            .arg(project)
            .args(args)
            .env("NO_COLOR", "1")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the ballast binary starts");
        let output = Arc::new(Mutex::new(String::new()));
        let stdout = child.stdout.take().unwrap();
        let stderr = child.stderr.take().unwrap();
        collect(stdout, output.clone());
        collect(stderr, output.clone());
        Watch { child, output }
    }

    fn output(&self) -> String {
        self.output.lock().unwrap().clone()
    }

    /// Waits until `builds` builds have finished; returns the output from the start of the last
    /// one.
    fn wait_builds(&self, builds: usize) -> String {
        self.wait_until(
            |output| finished_builds(output) >= builds,
            &format!("build {builds} to finish"),
        );
        last_build(&self.output())
    }

    /// Waits until every build begun has finished and none has begun for [`QUIET`]; returns the
    /// number of builds.
    fn settle(&self) -> usize {
        loop {
            let begun = started_builds(&self.output());
            self.wait_builds(begun);
            thread::sleep(QUIET);
            let output = self.output();
            if started_builds(&output) == begun && finished_builds(&output) == begun {
                return begun;
            }
        }
    }

    /// Checks that, after `builds` finished builds, no other build starts (or finishes) within
    /// [`QUIET`].
    fn assert_quiet(&self, builds: usize) {
        thread::sleep(QUIET);
        let output = self.output();
        assert_eq!(
            (started_builds(&output), finished_builds(&output)),
            (builds, builds),
            "an unexpected rebuild (builds started, finished); output:\n{output}"
        );
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Appends every line read from `stream` to `output`, on a thread of its own.
fn collect(stream: impl Read + Send + 'static, output: Arc<Mutex<String>>) {
    thread::spawn(move || {
        for line in BufReader::new(stream).lines() {
            let Ok(line) = line else { break };
            let mut output = output.lock().unwrap();
            output.push_str(&line);
            output.push('\n');
        }
    });
}

/// Builds finished in `output`, good and bad.
fn finished_builds(output: &str) -> usize {
    let good = output
        .lines()
        .filter(|line| line.starts_with(GOOD) && !line.contains(EARLY))
        .count();
    good + output.matches(BAD).count()
}

/// Builds begun in `output`: each starts with a heading line.
fn started_builds(output: &str) -> usize {
    output
        .lines()
        .filter(|line| line.starts_with("building ") || line.starts_with("changed: "))
        .count()
}

/// The output from the last build's heading line on.
fn last_build(output: &str) -> String {
    let start = [output.rfind("\nbuilding "), output.rfind("\nchanged: ")]
        .into_iter()
        .flatten()
        .max()
        .unwrap_or(0);
    output[start..].to_string()
}

/// A scratch folder holding `project` as `model.kdl` and a copy of the T shape in `meshes/`.
fn scratch(project: &str) -> (tempfile::TempDir, PathBuf) {
    let folder = tempfile::tempdir().unwrap();
    let meshes = folder.path().join("meshes");
    fs::create_dir(&meshes).unwrap();
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/meshes");
    fs::copy(examples.join("t_shape.obj"), meshes.join("t_shape.obj")).unwrap();
    let path = folder.path().join("model.kdl");
    fs::write(&path, project).unwrap();
    (folder, path)
}

/// Hand-placed capsules: a build takes milliseconds.
const HAND_PLACED: &str = r#"
component "T" mesh="meshes/t_shape.obj"
capsule "keel" component="T" radius=4 {
    from -15 0 29
    to 15 0 32
}
pose "upright" { stand margin=1 }
"#;

/// The files a good build of `model.kdl` writes, and their bytes.
fn outputs(folder: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    ["build/model.glb", "build/model.report.json"]
        .iter()
        .map(|name| {
            let path = folder.join(name);
            let bytes = fs::read(&path).unwrap_or_default();
            (path, bytes)
        })
        .collect()
}

/// Saves `text` as an editor does: into a temp file beside `path`, then renamed over it. Tests
/// save this way so that a build never reads a half-written file (on a busy machine the debounce
/// window can close between truncating a file and writing it).
fn save_by_rename(path: &Path, text: &str) {
    save_bytes_by_rename(path, text.as_bytes());
}

/// [`save_by_rename`] for any content.
fn save_bytes_by_rename(path: &Path, bytes: &[u8]) {
    let name = path.file_name().unwrap().to_string_lossy();
    let temp = path.with_file_name(format!(".{name}.swp"));
    fs::write(&temp, bytes).unwrap();
    fs::rename(&temp, path).unwrap();
}

#[test]
fn a_broken_save_keeps_the_outputs_and_fixing_it_rebuilds() {
    let (folder, project) = scratch(HAND_PLACED);
    let watch = Watch::start(&project, &[]);
    let first = watch.wait_builds(1);
    assert!(
        first.contains("model.kdl: 1 of 1 goal met, 1 capsule"),
        "{first}"
    );
    let good = outputs(folder.path());
    assert!(good.iter().all(|(_, bytes)| !bytes.is_empty()));
    assert_eq!(&good[0].1[..4], b"glTF");

    save_by_rename(&project, &HAND_PLACED.replace("margin=1 }", "margin= }"));
    let broken = watch.wait_builds(2);
    assert!(broken.contains(BAD), "{broken}");
    // Diagnostics go to standard error, read on a thread of its own: wait for them too.
    watch.wait_for("ballast::syntax");
    watch.wait_for("model.kdl is invalid: 1 error");
    assert_eq!(
        outputs(folder.path()),
        good,
        "outputs changed after a broken save"
    );

    // The fix asks for more than the design gives: the summary names the goal now broken.
    save_by_rename(&project, &HAND_PLACED.replace("margin=1", "margin=40"));
    let fixed = watch.wait_builds(3);
    assert!(fixed.contains(GOOD), "{fixed}");
    assert!(
        fixed.contains("now broken: `stand` in pose \"upright\""),
        "{fixed}"
    );
    assert!(fixed.contains("grids and skeletons: not needed"), "{fixed}");
    assert_ne!(outputs(folder.path()), good);
}

#[test]
fn saving_the_same_bytes_again_does_not_rebuild() {
    let (folder, project) = scratch(HAND_PLACED);
    let watch = Watch::start(&project, &[]);
    watch.wait_builds(1);
    save_by_rename(&project, HAND_PLACED);
    let mesh = folder.path().join("meshes/t_shape.obj");
    save_by_rename(&mesh, &fs::read_to_string(&mesh).unwrap());
    watch.assert_quiet(1);
    // A real edit after them still rebuilds.
    save_by_rename(&project, &HAND_PLACED.replace("margin=1", "margin=2"));
    let edited = watch.wait_builds(2);
    assert!(edited.contains("changed: "), "{edited}");
    assert!(edited.contains(GOOD), "{edited}");
}

#[test]
fn a_rename_save_rebuilds_once_and_the_watched_set_follows_the_project() {
    let (folder, project) = scratch(HAND_PLACED);
    let watch = Watch::start(&project, &[]);
    watch.wait_builds(1);

    let two_poses = format!("{HAND_PLACED}pose \"down\" {{ rotate 180 0 0; stand }}\n");
    save_by_rename(&project, &two_poses);
    let renamed = watch.wait_builds(2);
    assert!(
        renamed.contains("new goal: `stand` in pose \"down\""),
        "{renamed}"
    );
    watch.assert_quiet(2);

    // Delete and re-create: picked up, and the watch survives it.
    fs::remove_file(&project).unwrap();
    fs::write(&project, HAND_PLACED).unwrap();
    watch.wait_for("goal gone: `stand` in pose \"down\"");
    // The deletion may have been a build of its own, seeing no file; let the burst settle.
    let builds = watch.settle();

    // Point the component at a mesh in another folder: that folder is watched, the old mesh not.
    let parts = folder.path().join("parts");
    fs::create_dir(&parts).unwrap();
    fs::copy(
        folder.path().join("meshes/t_shape.obj"),
        parts.join("copy.obj"),
    )
    .unwrap();
    save_by_rename(
        &project,
        &HAND_PLACED.replace("meshes/t_shape.obj", "parts/copy.obj"),
    );
    let moved = watch.wait_builds(builds + 1);
    assert!(moved.contains(GOOD), "{moved}");
    watch.wait_for_line_containing("watching ", "copy.obj");
    let builds = watch.settle();

    touch_mesh(&folder.path().join("meshes/t_shape.obj"), 0.5);
    watch.assert_quiet(builds);
    touch_mesh(&parts.join("copy.obj"), 0.5);
    let edited = watch.wait_builds(builds + 1);
    assert!(edited.contains("copy.obj"), "{edited}");
}

#[test]
fn a_mesh_edit_rebuilds_the_grids_and_a_goal_edit_reuses_them_and_starts_warm() {
    let (folder, project) = scratch(
        "optimize capsules=1\ncomponent \"T\" mesh=\"meshes/t_shape.obj\"\npose \"upright\" { stand margin=1 }\n",
    );
    let watch = Watch::start(&project, &[]);
    let first = watch.wait_builds(1);
    assert!(
        first.contains("grids and skeletons: 1 grid and 1 skeleton built (1 mesh in the cache)"),
        "{first}"
    );
    assert!(!first.contains("the last design"), "{first}");
    assert!(folder.path().join("model.solution.kdl").exists());

    save_by_rename(&project, "optimize capsules=1\ncomponent \"T\" mesh=\"meshes/t_shape.obj\"\npose \"upright\" { stand margin=2 }\n");
    let goal = watch.wait_builds(2);
    // The last design judged at once (a stand margin of 2 it may or may not meet), a search from
    // it where it misses, then the full search; none samples anything.
    assert!(
        goal.contains("model.kdl (the last design, judged): "),
        "{goal}"
    );
    assert!(
        goal.contains("grids and skeletons: not needed (the last design is judged as it is)"),
        "{goal}"
    );
    // One summary per step, every one but the judged one a search with the cached grid.
    let summaries = goal.matches("  meshes: reused").count();
    assert!(summaries >= 2, "{goal}");
    assert_eq!(
        goal.matches("grids and skeletons: reused (1 mesh in the cache)")
            .count(),
        summaries - 1,
        "{goal}"
    );
    let settled = outputs_with_solution(folder.path());

    // Once quiet, the outputs are exactly what `build` writes.
    drop(watch);
    let built = Command::new(env!("CARGO_BIN_EXE_ballast"))
        .env("BALLAST_CACHE_DIR", "off")
        .arg("build")
        .arg(&project)
        .output()
        .unwrap();
    assert!(built.status.success(), "{built:?}");
    assert_eq!(outputs_with_solution(folder.path()), settled);

    let watch = Watch::start(&project, &[]);
    watch.wait_builds(1);
    touch_mesh(&folder.path().join("meshes/t_shape.obj"), 1.0);
    let mesh = watch.wait_builds(2);
    assert!(mesh.contains("t_shape.obj"), "{mesh}");
    // A new mesh: nothing to start warm from, and the old mesh's grid is dropped.
    assert!(!mesh.contains("the last design"), "{mesh}");
    assert!(
        mesh.contains("  meshes: 1 of 1 loaded and checked"),
        "{mesh}"
    );
    assert!(
        mesh.contains("grids and skeletons: 1 grid and 1 skeleton built (1 mesh in the cache)"),
        "{mesh}"
    );
}

/// [`outputs`] and the solution file.
fn outputs_with_solution(folder: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files = outputs(folder);
    let solution = folder.join("model.solution.kdl");
    files.push((solution.clone(), fs::read(&solution).unwrap_or_default()));
    files
}

#[test]
fn a_save_during_a_build_cancels_it_and_the_newest_version_is_built() {
    let optimized = |optimize: &str, margin: u32| {
        format!(
            "{optimize}\ncomponent \"T\" mesh=\"meshes/t_shape.obj\"\npose \"upright\" {{ stand margin={margin} }}\n"
        )
    };
    // A grid of 1.6 million nodes: minutes of sampling unless the build gives up.
    let slow = "optimize capsules=1 grid-cell=0.4";
    let (_folder, project) = scratch(&optimized(slow, 1));
    let watch = Watch::start(&project, &[]);
    watch.wait_for("building model.kdl");
    save_by_rename(&project, &optimized("optimize capsules=1", 2));
    save_by_rename(&project, &optimized("optimize capsules=1", 40));
    watch.wait_builds(1);
    let output = watch.output();
    let cancelled = output.find("cancelled: ");
    assert!(
        cancelled.is_some_and(|at| !output[..at].contains(GOOD)),
        "{output}"
    );
    // Whichever saves the first rebuild saw, the last version is the one built in the end.
    watch.wait_for("model.kdl: 0 of 1 goal met");
    let builds = watch.settle();
    assert!(
        watch.output().ends_with(&last_build(&watch.output())),
        "{}",
        watch.output()
    );
    assert!(
        last_build(&watch.output()).contains("model.kdl: 0 of 1 goal met"),
        "{builds} builds: {}",
        watch.output()
    );
}

#[cfg(unix)]
#[test]
fn ctrl_c_stops_with_status_zero() {
    let (_folder, project) = scratch(HAND_PLACED);
    let mut watch = Watch::start(&project, &[]);
    watch.wait_builds(1);
    let status = Command::new("kill")
        .args(["-INT", &watch.child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let (start, limit) = (Instant::now(), timeout());
    let code = loop {
        if let Some(status) = watch.child.try_wait().unwrap() {
            break status.code();
        }
        assert!(
            start.elapsed() < limit,
            "waited {limit:?} for watch to stop after SIGINT; output so far:\n{}",
            watch.output()
        );
        thread::sleep(Duration::from_millis(50));
    };
    assert_eq!(code, Some(0), "{}", watch.output());
    // The reader threads may still be draining the pipes.
    watch.wait_for("stopped watching model.kdl");
}

impl Watch {
    /// Waits until the output contains `text`.
    fn wait_for(&self, text: &str) {
        self.wait_until(|output| output.contains(text), text);
    }

    /// Waits for a line starting with `start` that contains `text`.
    fn wait_for_line_containing(&self, start: &str, text: &str) {
        self.wait_until(
            |output| {
                output
                    .lines()
                    .any(|line| line.starts_with(start) && line.contains(text))
            },
            text,
        );
    }

    /// Waits until the output so far is `done`; past [`timeout`], fails saying `what` it waited
    /// for and what was printed.
    fn wait_until(&self, done: impl Fn(&str) -> bool, what: &str) {
        let (begun, limit) = (Instant::now(), timeout());
        while !done(&self.output()) {
            assert!(
                begun.elapsed() < limit,
                "waited {limit:?} for {what:?} (set BALLAST_TEST_TIMEOUT to wait longer); output so far:\n{}",
                self.output()
            );
            thread::sleep(Duration::from_millis(50));
        }
    }
}

/// Moves every vertex of the OBJ file at `path` by `dx` along x: the same shape, a new content.
fn touch_mesh(path: &Path, dx: f64) {
    let text = fs::read_to_string(path).unwrap();
    save_by_rename(path, &edit_support::shifted_obj(&text, dx));
}

/// A project on the box of [`write_box`], with one hand-placed capsule.
const BOX: &str = r#"
component "box" mesh="meshes/box.gltf" mesh-units=mm mesh-up=z
capsule "keel" component="box" radius=4 {
    from -8 0 10
    to 8 0 10
}
pose "upright" { stand margin=1 }
"#;

/// Writes `box.gltf` into `folder`, its geometry in the external buffer `box.bin` (see
/// [`box_bin`]), with a top face of half-width `top`.
fn write_box(folder: &Path, top: f32) {
    let gltf = r#"{
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "buffers": [{"uri": "box.bin", "byteLength": 168}],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 96},
    {"buffer": 0, "byteOffset": 96, "byteLength": 72}
  ],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
     "min": [-20, -20, 0], "max": [20, 20, 40]},
    {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}
  ]
}"#;
    fs::write(folder.join("box.gltf"), gltf).unwrap();
    fs::write(folder.join("box.bin"), box_bin(top)).unwrap();
}

/// The buffer of the box of [`write_box`]: a square frustum 40 mm high on a 40 mm square base,
/// whose top face has half-width `top` (20: a cube; less: tapered, same bounds), as 8 FLOAT
/// positions then 36 u16 indices, counter-clockwise seen from outside.
fn box_bin(top: f32) -> Vec<u8> {
    let mut bytes = Vec::new();
    // Vertex i has x from bit 0, y from bit 1, z from bit 2.
    for i in 0..8 {
        let (half, z) = if i & 4 == 0 { (20.0, 0.0) } else { (top, 40.0) };
        let side = |bit: usize| if i & bit == 0 { -half } else { half };
        for c in [side(1), side(2), z] {
            bytes.extend_from_slice(&f32::to_le_bytes(c));
        }
    }
    let triangles: [u16; 36] = [
        0, 2, 3, 0, 3, 1, // z = 0
        4, 5, 7, 4, 7, 6, // z = 40
        0, 1, 5, 0, 5, 4, // y = -20
        2, 6, 7, 2, 7, 3, // y = 20
        0, 4, 6, 0, 6, 2, // x = -20
        1, 3, 7, 1, 7, 5, // x = 20
    ];
    for index in triangles {
        bytes.extend_from_slice(&index.to_le_bytes());
    }
    bytes
}

#[test]
fn an_edit_to_an_external_gltf_buffer_rebuilds() {
    let (folder, project) = scratch(BOX);
    let meshes = folder.path().join("meshes");
    write_box(&meshes, 20.0);
    let watch = Watch::start(&project, &[]);
    let first = watch.wait_builds(1);
    assert!(
        first.contains("model.kdl: 1 of 1 goal met, 1 capsule"),
        "{first}"
    );
    watch.wait_for_line_containing("watching ", "box.bin");

    // Only the buffer changes: the box tapers, its bounds stay, its centre of mass drops.
    save_bytes_by_rename(&meshes.join("box.bin"), &box_bin(10.0));
    let tapered = watch.wait_builds(2);
    assert!(
        tapered
            .lines()
            .any(|line| line.starts_with("changed: ") && line.contains("box.bin")),
        "{tapered}"
    );
    assert!(tapered.contains(GOOD), "{tapered}");
    assert!(tapered.contains("worst tilt margin: "), "{tapered}");
}

#[test]
fn a_project_in_a_missing_folder_cannot_be_watched() {
    let folder = tempfile::tempdir().unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_ballast"))
        .env("BALLAST_CACHE_DIR", "off")
        .arg("watch")
        .arg(folder.path().join("no/such/model.kdl"))
        .env("NO_COLOR", "1")
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("cannot watch"), "{stderr}");
}

#[test]
fn a_new_session_reads_the_grid_a_build_stored_in_the_disk_cache() {
    let (_folder, project) = scratch(
        "optimize capsules=1\ncomponent \"T\" mesh=\"meshes/t_shape.obj\"\npose \"upright\" { stand margin=1 }\n",
    );
    let cache = tempfile::tempdir().unwrap();
    let built = Command::new(env!("CARGO_BIN_EXE_ballast"))
        .env("BALLAST_CACHE_DIR", cache.path())
        .arg("build")
        .arg(&project)
        .output()
        .unwrap();
    assert!(built.status.success(), "{built:?}");

    let watch = Watch::start_cached(&project, &[], cache.path());
    let first = watch.wait_builds(1);
    assert!(
        first.contains("grids and skeletons: 1 read from the disk cache (1 mesh in the cache)"),
        "{first}"
    );
}

#[test]
fn a_project_folder_removed_and_made_again_is_watched_again() {
    let outer = tempfile::tempdir().unwrap();
    let (inner, _) = scratch(HAND_PLACED);
    let folder = outer.path().join("project");
    let copy = |to: &Path| {
        fs::create_dir_all(to.join("meshes")).unwrap();
        for name in ["model.kdl", "meshes/t_shape.obj"] {
            fs::copy(inner.path().join(name), to.join(name)).unwrap();
        }
    };
    copy(&folder);
    let project = folder.join("model.kdl");
    let watch = Watch::start(&project, &[]);
    watch.wait_builds(1);
    // As a checkout that swaps the folder out and back: removed (the build fails), then made
    // again with the project edited.
    fs::remove_dir_all(&folder).unwrap();
    let gone = watch.wait_builds(2);
    assert!(gone.contains(BAD), "{gone}");
    let staged = outer.path().join("staged");
    copy(&staged);
    fs::write(
        staged.join("model.kdl"),
        HAND_PLACED.replace("margin=1", "margin=2"),
    )
    .unwrap();
    fs::rename(&staged, &folder).unwrap();
    let back = watch.wait_builds(3);
    assert!(back.contains(GOOD), "{back}");
    // And its files are watched again: an edit rebuilds.
    save_by_rename(&project, &HAND_PLACED.replace("margin=1", "margin=3"));
    let edited = watch.wait_builds(4);
    assert!(edited.contains(GOOD), "{edited}");
}

#[cfg(unix)]
#[test]
fn a_mesh_replaced_by_a_pipe_or_a_device_fails_its_build_and_the_watch_goes_on() {
    let (folder, project) = scratch(HAND_PLACED);
    let mesh = folder.path().join("meshes/t_shape.obj");
    let bytes = fs::read(&mesh).unwrap();
    let watch = Watch::start(&project, &[]);
    watch.wait_builds(1);
    // A pipe no one writes to, then a link to an endless device, each followed by the real
    // mesh: neither is read, and the watch is not stuck on either.
    let pipe = || {
        let name = std::ffi::CString::new(mesh.to_str().unwrap()).unwrap();
        // SAFETY: `name` is a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
    };
    let device = || std::os::unix::fs::symlink("/dev/zero", &mesh).unwrap();
    let mut builds = 1;
    for replace in [&pipe as &dyn Fn(), &device] {
        fs::remove_file(&mesh).unwrap();
        replace();
        builds += 1;
        let refused = watch.wait_builds(builds);
        assert!(refused.contains(BAD), "{refused}");
        fs::remove_file(&mesh).unwrap();
        save_bytes_by_rename(&mesh, &bytes);
        builds += 1;
        let back = watch.wait_builds(builds);
        assert!(back.contains(GOOD), "{back}");
    }
}
