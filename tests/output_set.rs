//! A build's outputs change as a set: after a kill at any point, and the next command's
//! [`finish_interrupted_outputs`], every output is the old one or every output is the new one;
//! a folder the build cannot write fails it before anything is replaced; what killed builds left
//! behind is removed by the next build, and nothing else is.

mod cli_support;

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use ballast::compile::{finish_interrupted_outputs, journal_path};
use ballast::emit::atomic::TempName;
use ballast::spec::parse_project;
use cli_support::{ballast, build, build_ok};

/// The T shape with a written capsule, evaluated in two poses; `density` tells one version of
/// the project from the other (it changes the report, the glTF file and the print settings).
fn text(density: f64) -> String {
    format!(
        "material \"PLA\" density={density}\n\
         component \"T\" mesh=\"meshes/t_shape.obj\"\n\
         pose \"upright\" {{ stand }}\n\
         pose \"upside down\" {{ rotate 180 0 0; stand }}\n"
    )
}

/// A fresh folder with the mesh; the project's path (not written yet).
fn folder() -> (tempfile::TempDir, PathBuf) {
    cli_support::scratch_folder("", &["t_shape.obj"])
}

/// Every file under `root` but the project, its mesh, ballast's temporary files and the journal:
/// the output set, by path.
fn outputs(root: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut set = BTreeMap::new();
    let mut folders = vec![root.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in fs::read_dir(&folder).unwrap().flatten() {
            let path = entry.path();
            let name = entry.file_name().to_string_lossy().into_owned();
            if path.is_dir() {
                if name != "meshes" {
                    folders.push(path);
                }
            } else if name != "model.kdl" && !is_debris(&name) {
                set.insert(
                    path.strip_prefix(root).unwrap().to_path_buf(),
                    fs::read(&path).unwrap(),
                );
            }
        }
    }
    set
}

/// A temporary file or journal of ballast's.
fn is_debris(name: &str) -> bool {
    (name.contains(".ballast-") && name.ends_with(".tmp")) || name.ends_with(".ballast-outputs")
}

/// Every temporary file of ballast's under `root`.
fn debris(root: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut folders = vec![root.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in fs::read_dir(&folder).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                folders.push(path);
            } else if is_debris(&entry.file_name().to_string_lossy()) {
                found.push(path);
            }
        }
    }
    found
}

/// The output set of a complete build of the project version `density`.
fn complete(path: &Path, density: f64) -> (BTreeMap<PathBuf, Vec<u8>>, Duration) {
    fs::write(path, text(density)).unwrap();
    let clock = Instant::now();
    let output = build(path);
    let took = clock.elapsed();
    assert_ne!(
        output.status.code(),
        Some(2),
        "stderr: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    (outputs(path.parent().unwrap()), took)
}

/// What every command does first once it has read the project at `path`: finish replacing the
/// outputs of a build killed while it replaced them.
fn finish(path: &Path) {
    let source = fs::read_to_string(path).unwrap();
    let project = parse_project(&source, path).project.unwrap();
    finish_interrupted_outputs(&project, path, None).unwrap();
}

/// A small deterministic generator (xorshift), so a failing run can be repeated.
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn a_build_killed_at_random_points_leaves_all_old_or_all_new_outputs() {
    let (dir, path) = folder();
    let root = dir.path();
    let (first, _) = complete(&path, 1.24);
    let (second, took) = complete(&path, 1.30);
    assert_ne!(first, second);
    assert_eq!(
        first.keys().collect::<Vec<_>>(),
        second.keys().collect::<Vec<_>>()
    );
    // glb, report, STL, 3MF, sheet, SVG.
    assert!(first.len() >= 6, "{:?}", first.keys());
    let sets = [first, second];
    let densities = [1.24, 1.30];

    let mut current = 1;
    let mut random = Random(0x9e37_79b9_7f4a_7c15);
    let (mut old, mut new, mut journals) = (0, 0, 0);
    for round in 0..50 {
        let next = 1 - current;
        fs::write(&path, text(densities[next])).unwrap();
        // Half the kills anywhere in the build, half in its last fifth, where it writes.
        let at = if round % 2 == 0 {
            random.next() * 1.1
        } else {
            0.8 + random.next() * 0.25
        };
        let mut child = Command::new(env!("CARGO_BIN_EXE_ballast"))
            .arg("build")
            .arg(&path)
            .env("BALLAST_CACHE_DIR", "off")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(took.mul_f64(at));
        // SIGKILL on Unix.
        let _ = child.kill();
        child.wait().unwrap();

        let pending = journal_path(&path, None).exists();
        let raw = outputs(root);
        if pending {
            journals += 1;
        } else {
            assert!(
                raw == sets[current] || raw == sets[next],
                "round {round}: a mix of old and new outputs with no journal"
            );
        }
        // What the next command (any of them) does first.
        finish(&path);
        let after = outputs(root);
        if after == sets[next] {
            new += 1;
            current = next;
        } else {
            assert!(
                after == sets[current],
                "round {round}: a mix of old and new outputs"
            );
            assert!(!pending, "round {round}: a journal was not finished");
            old += 1;
        }
        assert!(!journal_path(&path, None).exists());
    }
    eprintln!("50 kills: {old} left the old outputs, {new} the new ones ({journals} finished from a journal)");

    // The next complete build removes every temporary file the killed ones left.
    complete(&path, densities[1 - current]);
    assert_eq!(debris(root), Vec::<PathBuf>::new());
}

#[test]
fn a_folder_the_build_cannot_write_fails_it_before_anything_is_replaced() {
    let (dir, path) = folder();
    let root = dir.path();
    let with_report = |density| {
        format!(
            "{}output {{ report \"reports/model.report.json\"; }}\n",
            text(density)
        )
    };
    fs::write(&path, with_report(1.24)).unwrap();
    let output = build(&path);
    assert_ne!(output.status.code(), Some(2));
    let before = outputs(root);
    let reports = root.join("reports");

    let original = fs::metadata(&reports).unwrap().permissions();
    let mut permissions = original.clone();
    permissions.set_readonly(true);
    fs::set_permissions(&reports, permissions).unwrap();
    // A user with the right to write anyway (root) is stopped by a file in the folder's place.
    let read_only = fs::write(reports.join("probe"), b"").is_err();
    let moved = root.join("reports-moved");
    if !read_only {
        fs::set_permissions(&reports, original.clone()).unwrap();
        fs::remove_file(reports.join("probe")).unwrap();
        fs::rename(&reports, &moved).unwrap();
        fs::write(&reports, b"a file where the folder was").unwrap();
    }
    fs::write(&path, with_report(1.30)).unwrap();
    let output = build(&path);
    let err = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(2), "{err}");
    assert!(err.contains("cannot write the outputs"), "{err}");
    if read_only {
        fs::set_permissions(&reports, original).unwrap();
    } else {
        fs::remove_file(&reports).unwrap();
        fs::rename(&moved, &reports).unwrap();
    }
    // Every old output as it was, and nothing of the new build left.
    assert_eq!(outputs(root), before);
    assert_eq!(debris(root), Vec::<PathBuf>::new());
}

#[test]
fn only_ballasts_own_leftovers_are_removed() {
    let (dir, path) = folder();
    let root = dir.path();
    complete(&path, 1.24);
    let build_dir = root.join("build");
    // A process id no process has.
    let dead = u32::MAX - 1;
    let temp = |target: &str| TempName {
        target: target.into(),
        pid: dead,
        n: 3,
    };
    let stale = build_dir.join(temp("model.glb").file_name());
    let journal = journal_path(&path, None);
    let journal_name = journal.file_name().unwrap().to_str().unwrap();
    let stale_journal_temp = root.join(temp(journal_name).file_name());
    assert_eq!(
        stale.file_name().unwrap(),
        format!(".model.glb.ballast-{dead}-3.tmp").as_str()
    );
    let kept = [
        build_dir.join(".model.glb.tmp"),
        build_dir.join(format!(".notes.md.ballast-{dead}-3.tmp")),
        build_dir.join("model.glb.ballast-1-2.tmp"),
        build_dir.join("notes.md"),
    ];
    for file in kept.iter().chain([&stale, &stale_journal_temp]) {
        fs::write(file, b"left here").unwrap();
    }
    complete(&path, 1.30);
    assert!(!stale.exists() && !stale_journal_temp.exists());
    for file in &kept {
        assert_eq!(fs::read(file).unwrap(), b"left here", "{}", file.display());
    }
}

/// The project of [`text`] with `output` as its output block.
fn with_output(density: f64, output: &str) -> String {
    format!("{}output {{ {output} }}\n", text(density))
}

#[test]
fn an_output_the_build_no_longer_writes_is_removed_and_said() {
    let (dir, path) = folder();
    let root = dir.path();
    let build_dir = root.join("build");
    fs::write(&path, with_output(1.24, "gltf \"build/first.glb\"")).unwrap();
    build_ok(&path);
    let old = build_dir.join("first.glb");
    assert!(old.exists());
    // A killed build of the old set left a temporary file of it.
    let left = build_dir.join(
        TempName {
            target: "first.glb".into(),
            pid: u32::MAX - 1,
            n: 1,
        }
        .file_name(),
    );
    fs::write(&left, b"partial").unwrap();

    // Renamed: the old file would look like this build's model.
    fs::write(&path, with_output(1.30, "gltf \"build/second.glb\"")).unwrap();
    let printed = build_ok(&path);
    assert!(!old.exists(), "{printed}");
    assert!(build_dir.join("second.glb").exists());
    assert!(
        printed.contains(&format!(
            "removed {} (an output of the last build that this one no longer writes)",
            old.display()
        )),
        "{printed}"
    );
    if Path::new("/proc/self").exists() {
        assert!(
            !left.exists(),
            "a killed build's temporary file of the old output is left"
        );
    }
    assert_eq!(debris(root), Vec::<PathBuf>::new());

    // A file of the last set that someone changed since is theirs now: it stays.
    fs::write(build_dir.join("second.glb"), b"edited by hand").unwrap();
    fs::write(&path, with_output(1.24, "gltf \"build/third.glb\"")).unwrap();
    let printed = build_ok(&path);
    assert_eq!(
        fs::read(build_dir.join("second.glb")).unwrap(),
        b"edited by hand"
    );
    assert!(!printed.contains("removed "), "{printed}");

    // The same build again removes nothing, and a file ballast never wrote is never removed.
    fs::write(build_dir.join("notes.md"), b"mine").unwrap();
    assert!(!build_ok(&path).contains("removed "));
    assert_eq!(fs::read(build_dir.join("notes.md")).unwrap(), b"mine");
    assert!(build_dir.join("third.glb").exists());
}

#[test]
fn a_solution_file_stays_when_the_project_stops_optimizing() {
    let (dir, path) = folder();
    let solution = dir.path().join("model.solution.kdl");
    let optimizing = format!("{}optimize capsules=1\n", text(1.24));
    fs::write(&path, &optimizing).unwrap();
    let built = build(&path);
    assert_ne!(
        built.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let design = fs::read(&solution).unwrap();
    // Without `optimize`, the build writes no solution file; the committed one stays for when
    // `optimize` comes back.
    fs::write(&path, text(1.24)).unwrap();
    let plain = build(&path);
    assert_ne!(plain.status.code(), Some(2));
    assert_eq!(fs::read(&solution).unwrap(), design);
}

/// The BLAKE3 hash of `path`'s bytes, hexadecimal, as the journal and manifest record it.
fn hash(path: &Path) -> String {
    blake3::hash(&fs::read(path).unwrap()).to_hex().to_string()
}

#[test]
fn a_forged_journal_or_manifest_removes_and_replaces_nothing_outside_the_outputs() {
    let (dir, path) = folder();
    let root = dir.path();
    fs::write(&path, text(1.24)).unwrap();
    build_ok(&path);
    // Files the project does not write: one in another folder, one in the project's folder
    // with an output's suffix, and the project and its mesh themselves (also by another
    // spelling, through /proc).
    let elsewhere = tempfile::tempdir().unwrap();
    let victim = elsewhere.path().join("notes.txt");
    fs::write(&victim, "someone's notes").unwrap();
    let notes = root.join("notes.md");
    fs::write(&notes, "notes").unwrap();
    let mesh = root.join("meshes/t_shape.obj");
    let calibration = root.join("model.calibration.json");
    fs::write(&calibration, "{}").unwrap();
    let by_proc = Path::new("/proc/self/root").join(path.strip_prefix("/").unwrap());
    let named = [&victim, &notes, &path, &mesh, &calibration];
    let mut entries: Vec<String> = named
        .iter()
        .map(|file| {
            format!(
                r#"{{"path":"{}","blake3":"{}"}}"#,
                file.display(),
                hash(file)
            )
        })
        .collect();
    entries.push(format!(
        r#"{{"path":"{}","blake3":"{}"}}"#,
        by_proc.display(),
        hash(&path)
    ));
    entries.push(format!(
        r#"{{"path":"{}","blake3":"{}"}}"#,
        Path::new("..")
            .join(elsewhere.path().file_name().unwrap())
            .join("notes.txt")
            .display(),
        hash(&victim)
    ));
    let journal = journal_path(&path, None);
    let manifest = ballast::emit::manifest_path(&journal);
    // A forged journal also tries to rename a planted file over the project.
    let planted = root.join(
        TempName {
            target: "model.kdl".into(),
            pid: u32::MAX - 1,
            n: 1,
        }
        .file_name(),
    );
    fs::write(&planted, "pose").unwrap();
    let forged_journal = format!(
        r#"{{"ballast_output_set":1,"files":[{{"target":"{}","temp":"{}"}}],"remove":[{}]}}"#,
        path.display(),
        planted.file_name().unwrap().to_string_lossy(),
        entries.join(",")
    );
    let forged_manifest = format!(
        r#"{{"ballast_output_manifest":1,"files":[{}]}}"#,
        entries.join(",")
    );
    let originals: Vec<Vec<u8>> = named.iter().map(|file| fs::read(file).unwrap()).collect();
    fs::write(&journal, &forged_journal).unwrap();
    let checked = ballast(&["check", path.to_str().unwrap()]);
    assert_eq!(
        checked.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&checked.stderr)
    );
    fs::write(&manifest, &forged_manifest).unwrap();
    build_ok(&path);
    for (file, original) in named.iter().zip(&originals) {
        assert_eq!(
            &fs::read(file).unwrap(),
            original,
            "{} was touched",
            file.display()
        );
    }
    assert!(!journal.exists());
}

#[cfg(unix)]
#[test]
fn a_journal_or_manifest_that_is_not_a_regular_file_is_not_read() {
    let (dir, path) = folder();
    fs::write(&path, text(1.24)).unwrap();
    let journal = journal_path(&path, None);
    let manifest = ballast::emit::manifest_path(&journal);
    // A link to an endless device, then a pipe no one writes to: neither is read.
    std::os::unix::fs::symlink("/dev/zero", &journal).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &manifest).unwrap();
    build_ok(&path);
    for record in [&journal, &manifest] {
        let name = std::ffi::CString::new(record.to_str().unwrap()).unwrap();
        let _ = fs::remove_file(record);
        // SAFETY: `name` is a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
    }
    let checked = ballast(&["check", path.to_str().unwrap()]);
    assert_eq!(
        checked.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&checked.stderr)
    );
    build_ok(&path);
    assert!(dir.path().join("build/model.glb").exists());
}
