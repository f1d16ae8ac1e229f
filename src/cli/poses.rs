//! `ballast poses`: the facets the model rests on stably, and the `pose` lines that use them.

use std::fmt::Write as _;
use std::path::Path;

use super::{compile_file, file_name, MessageFormat, EXIT_INVALID, EXIT_MET};
use crate::balance::{resting_facets, RestingFacet};
use crate::compile::{CompileOptions, Workspace};

/// Lists the stable facets of the project at `path`, the components placed as the pose named
/// `pose` (default: the first) places them.
pub fn run(path: &Path, pose: Option<&str>, options: &CompileOptions) -> i32 {
    let Ok(compilation) = compile_file(path, options, &mut Workspace::new(), MessageFormat::Human)
    else {
        return EXIT_INVALID;
    };
    let project = &compilation.project;
    let chosen = match pose {
        Some(name) => project.poses.iter().find(|p| p.name.value == name),
        None => project.poses.first(),
    };
    let Some(chosen) = chosen else {
        eprintln!(
            "error: {} has no pose named `{}`",
            file_name(path),
            pose.unwrap_or_default()
        );
        return EXIT_INVALID;
    };
    let bodies = compilation.bare_bodies();
    let cut = compilation.bodies();
    let design =
        (!compilation.design.capsules.is_empty()).then_some((&compilation.design, cut.as_slice()));
    let Some(facets) = resting_facets(project, &bodies, chosen, design) else {
        eprintln!(
            "error: the model of {} has no volume, so no convex hull",
            file_name(path)
        );
        return EXIT_INVALID;
    };
    print!(
        "{}",
        listing(
            &file_name(path),
            &chosen.name.value,
            project.units.keyword(),
            &facets,
            design.is_some()
        )
    );
    EXIT_MET
}

/// The table of stable facets and the lines to paste.
fn listing(
    file: &str,
    pose: &str,
    units: &str,
    facets: &[RestingFacet],
    with_design: bool,
) -> String {
    let stable: Vec<&RestingFacet> = facets
        .iter()
        .filter(|f| f.solid_margin > 0.0 || f.design_margin.is_some_and(|m| m > 0.0))
        .collect();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{file}: the model rests stably on {} of its {} hull facets (components as pose `{pose}` places them), most stable first",
        stable.len(),
        facets.len()
    );
    let design_column = if with_design { "  design margin" } else { "" };
    let _ = writeln!(
        out,
        "  facet  solid margin{design_column}  area ({units}²)  corners  outward normal"
    );
    for (k, facet) in stable.iter().enumerate() {
        let design = match (with_design, facet.design_margin) {
            (false, _) => String::new(),
            (true, Some(margin)) => format!("  {:>12.2}°", margin),
            (true, None) => format!("  {:>13}", "rolls off"),
        };
        let _ = writeln!(
            out,
            "  {:>5}  {:>11.2}°{design}  {:>12.4}  {:>7}  {}",
            k + 1,
            facet.solid_margin,
            facet.area,
            facet.corners,
            direction(&facet.normal)
        );
    }
    if !stable.is_empty() {
        let _ = writeln!(
            out,
            "\nTo rest on one, paste its pose into the project (`down` aims from the solid centre of mass into the facet):"
        );
        for (k, facet) in stable.iter().enumerate() {
            let _ = writeln!(
                out,
                "pose \"facet {}\" {{ down {}; stand }}",
                k + 1,
                direction(&facet.down)
            );
        }
    }
    out
}

/// A direction as three numbers of six decimals, trailing zeros left out.
pub(super) fn direction(v: &[f64; 3]) -> String {
    v.iter()
        .map(|x| {
            let text = format!("{x:.6}");
            let text = text.trim_end_matches('0').trim_end_matches('.');
            match text {
                "-0" => "0".to_string(),
                other => other.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}
