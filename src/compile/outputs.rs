//! Writing a compilation's outputs: the glTF file, the JSON report, the print files (an STL per
//! component, the PrusaSlicer 3MF, the insertion sheet and its pictures) and, for an optimized
//! design, the solution file. They are replaced as one set ([`crate::emit::replace_set`]): after
//! a kill at any point, the next build (or `check`) finds either every old file or every new one.
//! [`write_outputs`] is the one place a build writes its outputs.

use std::io;
use std::path::{Path, PathBuf};

use super::output_paths::{input_files, OutputScope};
use super::{
    bed_parts, bed_plate_pauses, interrupted_solution_text, output_path, print_settings,
    solution_text, Compilation, DesignSource, Report,
};
use crate::emit::output_set::same_file;
use crate::emit::print_files::{
    file_name, write_prusa_3mf, write_sheet, write_stl, BedPart, BedPlatePause, PrintSettings,
};
use crate::emit::{finish_interrupted, replace_set, write_glb};
use crate::geometry::{MeshLimits, ReadPolicy};
use crate::spec::model::Project;

/// The files a build wrote, and those of the previous build's set that it removed.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct WrittenOutputs {
    /// Every output written, in the order replaced.
    pub written: Vec<PathBuf>,
    /// Outputs the previous build (of the same project into the same folder) wrote that this one
    /// no longer writes (an output removed from the `output` block, renamed, a component gone),
    /// removed so that no stale file looks current. Only files ballast's manifest names that
    /// still hold what it wrote, never an input.
    pub removed: Vec<PathBuf>,
}

/// Encodes every output of `compilation` (the project read from `path`), then replaces them as
/// one set where the project says, or in `out_dir`, removing the previous set's files this one no
/// longer has; returns what was written and removed. Nothing is replaced when an output cannot be
/// encoded, would overwrite a file the build read, or cannot be written (a read-only folder): the
/// old outputs stay as they were.
pub fn write_outputs(
    compilation: &Compilation,
    path: &Path,
    out_dir: Option<&Path>,
) -> Result<WrittenOutputs, String> {
    let targets = encode_outputs(compilation, path, out_dir, None)?;
    replace_outputs(compilation, path, out_dir, targets)
}

/// [`write_outputs`], taking the print files from `cache` when they were last encoded from the
/// same parts, pauses, settings and names (watch mode judging an unchanged design), and keeping
/// this build's there. The files written are the same bytes either way.
pub fn write_outputs_with(
    compilation: &Compilation,
    path: &Path,
    out_dir: Option<&Path>,
    cache: &mut PrintFileCache,
) -> Result<WrittenOutputs, String> {
    let targets = encode_outputs(compilation, path, out_dir, Some(cache))?;
    replace_outputs(compilation, path, out_dir, targets)
}

/// Replaces the outputs with `targets` as one set (see [`write_outputs`]).
fn replace_outputs(
    compilation: &Compilation,
    path: &Path,
    out_dir: Option<&Path>,
    targets: Vec<Encoded>,
) -> Result<WrittenOutputs, String> {
    // Every buffer counts as an input here, wherever it is: refusing to overwrite one more file
    // is safe.
    let anywhere = ReadPolicy {
        within: None,
        limits: MeshLimits::default(),
    };
    let inputs = input_files(&compilation.project, path, &anywhere);
    for (target, _) in &targets {
        if let Some(input) = inputs.iter().find(|input| same_file(target, input)) {
            return Err(format!(
                "{} would overwrite {}, which the build reads",
                target.display(),
                input.display()
            ));
        }
    }
    let scope = OutputScope::of(&compilation.project, path, out_dir);
    let removed = replace_set(&journal_path(path, out_dir), &targets, &scope)
        .map_err(|error| format!("cannot write the outputs: {error}"))?;
    Ok(WrittenOutputs {
        written: targets.into_iter().map(|(target, _)| target).collect(),
        removed,
    })
}

/// Finishes replacing the outputs of a build of `project` (read from `path`, written into
/// `out_dir`) that was killed while replacing them, so they are all the new ones; does nothing
/// otherwise. Only files of `project`'s [`OutputScope`] are touched.
pub fn finish_interrupted_outputs(
    project: &Project,
    path: &Path,
    out_dir: Option<&Path>,
) -> io::Result<()> {
    let scope = OutputScope::of(project, path, out_dir);
    finish_interrupted(&journal_path(path, out_dir), &scope)
}

/// The journal of the output set of the project at `path`: a hidden file in `out_dir`, else
/// beside the project, named after the project file. It exists only while a build replaces its
/// outputs, or after a kill then. Beside it, [`manifest_path`](crate::emit::manifest_path) names
/// the files of the last set written.
pub fn journal_path(path: &Path, out_dir: Option<&Path>) -> PathBuf {
    let folder = out_dir.map_or_else(|| crate::emit::atomic::folder_of(path), Path::to_path_buf);
    let mut name = std::ffi::OsString::from(".");
    name.push(path.file_name().unwrap_or_else(|| "project".as_ref()));
    name.push(".ballast-outputs");
    folder.join(name)
}

/// Every output of `compilation`, encoded, in the order they are replaced: the glTF file, the
/// report, the print files, then the solution file.
fn encode_outputs(
    compilation: &Compilation,
    path: &Path,
    out_dir: Option<&Path>,
    cache: Option<&mut PrintFileCache>,
) -> Result<Vec<Encoded>, String> {
    let glb = write_glb(&compilation.scene())
        .map_err(|error| format!("cannot encode the glTF file: {error}"))?;
    let report = Report::new(compilation, path).to_json();
    let output = &compilation.project.output;
    let mut targets = vec![
        (output_path(&output.gltf, out_dir), glb),
        (output_path(&output.report, out_dir), report.into_bytes()),
    ];
    targets.extend(print_files(compilation, path, out_dir, cache)?);
    // A design judged again is the last build's, whose solution file is this build's output
    // too: left out, the output set would remove it.
    if matches!(
        compilation.source,
        DesignSource::Optimized | DesignSource::Earlier
    ) {
        let name = path
            .file_name()
            .map(|name| name.to_string_lossy().into_owned())
            .unwrap_or_default();
        let (project, meshes, design) = (
            &compilation.project,
            &compilation.meshes,
            &compilation.design,
        );
        let interrupted = compilation
            .optimization
            .as_ref()
            .and_then(|optimization| optimization.interrupted);
        let text = match interrupted {
            None => solution_text(project, &name, meshes, design),
            Some(why) => interrupted_solution_text(project, &name, meshes, design, why),
        };
        targets.push((output_path(&output.solution, out_dir), text.into_bytes()));
    }
    Ok(targets)
}

/// The print files last encoded in one process, with what they were encoded from, so a build
/// with the same parts, pauses, settings and names (in watch mode, a goal-only edit judging the
/// last design) takes their bytes instead of encoding the 3MF, the STL files and the sheet again:
/// on a 240k-triangle part that is most of the time from a save to its outputs.
#[derive(Debug, Default)]
pub struct PrintFileCache {
    /// The last inputs and the files encoded from them.
    last: Option<(PrintFileInputs, Vec<Encoded>)>,
    /// Sets of print files encoded (not taken from the cache) since it was made.
    encoded: usize,
}

impl PrintFileCache {
    /// Sets of print files encoded, not taken from the cache, since it was made.
    pub fn encoded(&self) -> usize {
        self.encoded
    }
}

/// An output's path and its bytes.
type Encoded = (PathBuf, Vec<u8>);

/// Everything the print files are a function of.
#[derive(Debug, PartialEq)]
struct PrintFileInputs {
    parts: Vec<BedPart>,
    /// The whole bed's pauses.
    pauses: Vec<BedPlatePause>,
    settings: PrintSettings,
    /// The project file's name, the sheet's title.
    title: String,
    /// Where the STL files, the 3MF and the sheet go.
    paths: [PathBuf; 3],
}

/// The print files of `compilation`, encoded: each component's STL in the `stl` folder, the
/// PrusaSlicer project, the insertion sheet and its pictures beside it; from `cache` when it holds
/// them for the same inputs, and kept there (without a cache, nothing is copied to keep).
fn print_files(
    compilation: &Compilation,
    path: &Path,
    out_dir: Option<&Path>,
    cache: Option<&mut PrintFileCache>,
) -> Result<Vec<Encoded>, String> {
    let output = &compilation.project.output;
    let inputs = PrintFileInputs {
        parts: bed_parts(
            &compilation.project,
            &compilation.meshes,
            &compilation.design,
            &compilation.print_plan,
        ),
        pauses: bed_plate_pauses(&compilation.project, &compilation.print_plan),
        settings: print_settings(&compilation.project, &compilation.design),
        title: path
            .file_name()
            .map(|name| name.to_string_lossy().into_owned())
            .unwrap_or_default(),
        paths: [
            output_path(&output.stl, out_dir),
            output_path(&output.prusa, out_dir),
            output_path(&output.sheet, out_dir),
        ],
    };
    let Some(cache) = cache else {
        return encode_print_files(&inputs);
    };
    if let Some((last, files)) = &cache.last {
        if *last == inputs {
            return Ok(files.clone());
        }
    }
    let files = encode_print_files(&inputs)?;
    cache.encoded += 1;
    cache.last = Some((inputs, files.clone()));
    Ok(files)
}

/// The print files of `inputs`, encoded.
fn encode_print_files(inputs: &PrintFileInputs) -> Result<Vec<Encoded>, String> {
    let PrintFileInputs {
        parts,
        pauses,
        settings,
        title,
        paths: [folder, prusa_path, sheet_path],
    } = inputs;
    let mut targets: Vec<Encoded> = parts
        .iter()
        .map(|part| {
            (
                folder.join(format!("{}.stl", file_name(&part.name))),
                write_stl(part),
            )
        })
        .collect();
    let prusa = write_prusa_3mf(parts, pauses, settings)
        .map_err(|error| format!("cannot encode the PrusaSlicer project: {error}"))?;
    targets.push((prusa_path.clone(), prusa));
    let stem = sheet_path.file_stem().map_or_else(
        || "insertion".into(),
        |stem| stem.to_string_lossy().into_owned(),
    );
    let sheet = write_sheet(title, parts, settings, &stem);
    let pictures = sheet_path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    targets.push((sheet_path.clone(), sheet.markdown.into_bytes()));
    for (name, svg) in sheet.pictures {
        targets.push((pictures.join(name), svg.into_bytes()));
    }
    Ok(targets)
}
