//! Every example from its design to a sliced print: the PrusaSlicer project `ballast build`
//! writes is sliced by the installed `prusa-slicer` from the command line the docs give, and the
//! G-code is checked against the design through its print plan (`ballast verify --gcode`): every
//! planned pause in the file after its layer with its message, no pause that is not planned, no
//! extrusion inside a void, the mass the slicer deposits within 10% of the mass model's, and every
//! goal met with it (but for the examples listed below, each of which must still be off). Skipped
//! when `prusa-slicer` is not installed (`.ci/run` installs it).

mod print_support;

use ballast::compile::compile;
use ballast::sliced::{verify_gcode, SlicedOptions};
use print_support::{examples, sliced_compilation, slicer_available};

/// Examples whose goals the sliced mass does not meet yet: none. The T, the hammer, the fish and
/// Spot design for the mass PrusaSlicer deposits through their calibration files
/// (`examples/*.calibration.json`, docs/fabrication.md, "Calibrating the mass model"); the others
/// meet every goal with the model's. The test fails when an example misses a goal with the sliced
/// mass, or when one listed here meets them all.
const SHORT_WITH_THE_SLICED_MASS: &[&str] = &[];

/// Examples whose sliced mass is more than 10% from the mass model's: none. The test fails when
/// one is, or when one listed here comes within 10%.
const MASS_OFF_BY_MORE_THAN_10_PERCENT: &[&str] = &[];

#[test]
fn every_example_sliced_from_its_3mf_is_as_planned() {
    if !slicer_available() {
        eprintln!("skipped: prusa-slicer is not on the PATH (apt-get install prusa-slicer)");
        return;
    }
    let folder = tempfile::tempdir().unwrap();
    let projects = examples();
    assert!(projects.len() >= 6);
    let mut failures = Vec::new();
    for path in &projects {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let source = std::fs::read_to_string(path).unwrap();
        let compilation = compile(&source, path)
            .unwrap_or_else(|problems| panic!("{name} does not compile: {problems:?}"));
        let gcode = sliced_compilation(&compilation, folder.path(), &name);
        let check = verify_gcode(
            &compilation,
            &compilation.print_plan,
            &gcode,
            &SlicedOptions::default(),
        )
        .unwrap_or_else(|error| panic!("{name}: {error}"));
        for part in &check.components {
            println!(
                "{name} `{}`: shift ({:+.4}, {:+.4}), fit residual {:.4} on {} layers",
                part.component, part.shift[0], part.shift[1], part.fit.residual, part.fit.layers
            );
        }
        // The file is as planned: every part where the plan put it, every planned pause after
        // its layer with its message and none other, no extrusion inside a void.
        failures.extend(
            check
                .components
                .iter()
                .filter_map(|c| c.mismatch.clone())
                .chain(check.pauses.iter().filter_map(|p| p.problem.clone()))
                .chain(check.voids.iter().filter_map(|v| v.problem()))
                .map(|failure| format!("{name}: {failure}")),
        );
        assert!(
            check.pauses.iter().all(|pause| pause.problem.is_none()),
            "{name}: {:#?}",
            check.pauses
        );
        // Every goal with the sliced mass, which is the mass model's within 10% but for the
        // examples known to be further off.
        let mut short = Vec::new();
        let mass_off = MASS_OFF_BY_MORE_THAN_10_PERCENT.contains(&name.as_str());
        for pose in &check.poses {
            let off = (pose.sliced_mass - pose.computed_mass).abs() > 0.1 * pose.computed_mass;
            if off != mass_off {
                failures.push(format!(
                    "{name}, pose \"{}\": sliced mass {:.2} g, computed {:.2} g{}",
                    pose.pose,
                    pose.sliced_mass,
                    pose.computed_mass,
                    if mass_off {
                        "; now within 10%: take it off the list"
                    } else {
                        ""
                    }
                ));
            }
            for goal in &pose.goals {
                println!(
                    "{name}, pose \"{}\": {} {} computed {:.2}, sliced {:.2} (mass {:.2} g computed, {:.2} g sliced)",
                    pose.pose, goal.kind, goal.quantity, goal.computed, goal.sliced,
                    pose.computed_mass, pose.sliced_mass
                );
                if !goal.met {
                    short.push(format!("pose \"{}\" {}", pose.pose, goal.kind));
                }
            }
        }
        let known = SHORT_WITH_THE_SLICED_MASS.contains(&name.as_str());
        if known && short.is_empty() {
            failures.push(format!(
                "{name}: now meets every goal with the sliced mass; take it off the list"
            ));
        } else if !known && !short.is_empty() {
            failures.push(format!("{name}: not met with the sliced mass: {short:?}"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
