//! `ballast new MESH`: a starter project beside a mesh file, so that a downloaded STL is one
//! command away from its first build.
//!
//! The project reads the mesh in the unit its size suggests (OBJ and STL state none; glTF and
//! 3MF files do, and are read in theirs), lists the facets the solid model rests on stably as
//! poses (the most stable active, the others commented out) with a `stand` goal, and asks the
//! optimizer for capsules.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::poses::direction;
use super::table::unit_name;
use super::{file_name, print_problems, MessageFormat, EXIT_INVALID, EXIT_MET};
use crate::balance::{resting_facets, RestingFacet};
use crate::compile::{compile_with, CompileOptions, Failure, Workspace};
use crate::emit::write_atomic;
use crate::geometry::{load_mesh_with, MeshSelector, ReadPolicy};
use crate::spec::model::Units;

/// Stable facets written as poses, the first active; the rest are left to `ballast poses`.
const FACETS_WRITTEN: usize = 8;

/// Writes the starter project for `mesh` to `project` (default: beside the mesh, its name with
/// `.kdl`), refusing to replace a file unless `force`. Exit status 0, or 2 when the mesh cannot
/// be read or used, or the project cannot be written.
pub fn run(mesh: &Path, project: Option<&Path>, force: bool, options: &CompileOptions) -> i32 {
    let project = project.map_or_else(|| mesh.with_extension("kdl"), Path::to_path_buf);
    if project.exists() && !force {
        eprintln!(
            "error: {} exists; pass --force to replace it, or name another file with -o",
            project.display()
        );
        return EXIT_INVALID;
    }
    let Some(reference) = mesh_reference(mesh, &project) else {
        eprintln!(
            "error: {} is not inside the folder of {}: write the project beside the mesh",
            mesh.display(),
            project.display()
        );
        return EXIT_INVALID;
    };
    let name = mesh
        .file_stem()
        .map_or_else(|| "part".to_string(), |s| s.to_string_lossy().into_owned());
    let name = name.replace(['"', '\\'], "_");
    let guess = match unit_guess(mesh, options) {
        Ok(guess) => guess,
        Err(message) => {
            eprintln!("error: cannot read {}: {message}", mesh.display());
            return EXIT_INVALID;
        }
    };
    let component = component_line(&name, &reference, guess.as_ref());
    // The facets come from the project itself, compiled with one provisional pose.
    let provisional = format!("{HEADER}{component}\npose \"rest\" {{\n    stand\n}}\n");
    let mut workspace = Workspace::new();
    let compilation = match compile_with(&provisional, &project, options, &mut workspace) {
        Ok(compilation) => compilation,
        Err(Failure::Invalid(problems)) => {
            let shown = format!("{} (the starter project for it)", project.display());
            print_problems(MessageFormat::Human, &problems, &shown, &provisional);
            eprintln!(
                "error: {} cannot be used as it is; nothing was written",
                mesh.display()
            );
            return EXIT_INVALID;
        }
        Err(Failure::Cancelled) => return EXIT_INVALID,
    };
    // What the mesh check says of a usable mesh (repairs, crossings) is said now: the starter
    // project's goals are not the user's yet, so the other warnings wait for the first build.
    for warning in compilation
        .warnings
        .iter()
        .filter(|w| w.code.split("::").nth(1) == Some("mesh"))
    {
        eprintln!("warning: {} ({})", warning.message, warning.code);
    }
    let bodies = compilation.bare_bodies();
    let facets = compilation
        .project
        .poses
        .first()
        .and_then(|pose| resting_facets(&compilation.project, &bodies, pose, None))
        .unwrap_or_default();
    let stable: Vec<&RestingFacet> = facets.iter().filter(|f| f.solid_margin > 0.0).collect();
    let size = compilation.meshes[0]
        .bounding_box()
        .map(|(low, high)| high - low);
    let text = project_text(
        &file_name(mesh),
        &component,
        guess.as_ref(),
        size.map(|s| [s.x, s.y, s.z]),
        &stable,
    );
    if let Err(error) = write_atomic(&project, text.as_bytes()) {
        eprintln!("error: cannot write {}: {error}", project.display());
        return EXIT_INVALID;
    }
    println!(
        "wrote {}: component `{name}` from {}, resting on the most stable of {} stable facets",
        project.display(),
        file_name(mesh),
        stable.len()
    );
    println!("next: ballast build {}", project.display());
    EXIT_MET
}

/// The first lines of every starter project.
const HEADER: &str = "units mm\nup z\nmaterial \"PLA\" density=1.24\n";

/// The unit guessed for a mesh file that states none, with the size it was guessed from.
struct UnitGuess {
    units: Units,
    /// The mesh's largest extent in its file's numbers.
    extent: f64,
}

/// The unit to read `mesh` in: `None` for a format that states its own (glTF, 3MF), else the
/// one its size suggests: millimetres from an extent of 5 on, centimetres from 0.5, metres
/// below.
fn unit_guess(mesh: &Path, options: &CompileOptions) -> Result<Option<UnitGuess>, String> {
    let extension = mesh
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if matches!(extension.as_str(), "gltf" | "glb" | "3mf") {
        return Ok(None);
    }
    let folder = mesh
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let policy = ReadPolicy {
        within: (!options.read_outside).then(|| folder.to_path_buf()),
        limits: options.mesh_limits,
    };
    let loaded = load_mesh_with(mesh, &MeshSelector::Whole, &policy).map_err(|e| e.to_string())?;
    let (low, high) = loaded
        .mesh
        .bounding_box()
        .ok_or_else(|| "the mesh has no vertices".to_string())?;
    let extent = (high - low).max();
    let units = if extent >= 5.0 {
        Units::Millimetre
    } else if extent >= 0.5 {
        Units::Centimetre
    } else {
        Units::Metre
    };
    Ok(Some(UnitGuess { units, extent }))
}

/// How the project names `mesh`: its path from the project's folder, when the mesh is inside
/// that folder.
fn mesh_reference(mesh: &Path, project: &Path) -> Option<String> {
    let folder = |path: &Path| -> Option<PathBuf> {
        let parent = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        parent.canonicalize().ok()
    };
    let (mesh_folder, project_folder) = (folder(mesh)?, folder(project)?);
    let within = mesh_folder.strip_prefix(&project_folder).ok()?;
    let path = within.join(mesh.file_name()?);
    let text = path.to_str()?.replace('\\', "/");
    (!text.contains('"')).then_some(text)
}

/// The `component` node.
fn component_line(name: &str, mesh: &str, guess: Option<&UnitGuess>) -> String {
    let units = match guess.map(|g| g.units) {
        Some(Units::Millimetre) | None => String::new(),
        Some(units) => format!(" mesh-units={}", units.keyword()),
    };
    format!("component \"{name}\" mesh=\"{mesh}\"{units}\n")
}

/// The starter project's text.
fn project_text(
    mesh: &str,
    component: &str,
    guess: Option<&UnitGuess>,
    size: Option<[f64; 3]>,
    stable: &[&RestingFacet],
) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "// A starter project for {mesh}: build it with `ballast build`, which places capsules\n\
         // with steel balls inside so that it meets the goals of every pose. docs/format.md\n\
         // describes every node."
    );
    out += "\n";
    out += HEADER;
    let size_text = size.map(|[x, y, z]| format!("{x:.1} × {y:.1} × {z:.1} mm"));
    match (guess, size_text) {
        (Some(guess), Some(size)) => {
            let _ = writeln!(
                out,
                "// {mesh} states no unit. Its largest extent is {} in its numbers: read in {},\n\
                 // it is {size}. If that is not its size, change `mesh-units=` (mm, cm, m\n\
                 // or in) or add `scale=`.",
                trimmed(guess.extent),
                unit_name(guess.units),
            );
        }
        (None, Some(size)) => {
            let _ = writeln!(
                out,
                "// {mesh} states its unit: {size}. Add `scale=` to print it at another size."
            );
        }
        _ => {}
    }
    out += component;
    out += "\n";
    if stable.is_empty() {
        out += "// The solid model rests stably on no facet of its convex hull: give the pose a\n\
                // `down` direction (`ballast poses` lists the facets) and a goal.\n";
        out += "pose \"standing\" {\n    stand\n}\n";
    } else {
        let _ = writeln!(
            out,
            "// The facets of its convex hull the solid model rests on stably, most stable first\n\
             // (`ballast poses` lists them all). The first is the pose to meet; uncomment others\n\
             // to ask for more, and give each pose its goals: stand, imbalance, suspend, immerse."
        );
        for (k, facet) in stable.iter().take(FACETS_WRITTEN).enumerate() {
            let prefix = if k == 0 { "" } else { "// " };
            let _ = writeln!(
                out,
                "{prefix}pose \"facet {}\" {{\n{prefix}    down {} // tilt margin {:.1}°, area {:.0} mm²\n{prefix}    stand\n{prefix}}}",
                k + 1,
                direction(&facet.down),
                facet.solid_margin,
                facet.area
            );
        }
    }
    out += "\noptimize\n";
    out
}

/// `value` with at most three decimals, trailing zeros left out.
fn trimmed(value: f64) -> String {
    let text = format!("{value:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}
