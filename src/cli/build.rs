//! `ballast build`: check, optimize when the project asks, then write the glTF file, the JSON
//! report and the solution file atomically.
//!
//! Ctrl-C, SIGTERM and `--time-limit` interrupt the build's [`Cancel`] flag: the optimizer stops
//! and keeps the best design of the capsule counts it finished, which is written like any other
//! (marked as interrupted in the report) before the process exits with the interruption's status.
//! A second signal exits at once.

use std::path::Path;
use std::time::Duration;

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::Signals;

use super::{
    compile_file, file_name, goals_status, optimization_table, progress, say, table, MessageFormat,
    NotCompiled, EXIT_INVALID, EXIT_SIGINT, EXIT_SIGTERM, EXIT_TIME_LIMIT,
};
use crate::cancel::{Cancel, Interruption};
use crate::compile::{write_outputs, CompileOptions, Stage, Workspace};
use crate::diagnostic::Problem;
use crate::optimize::PrecomputeCache;

/// Builds the project at `path` as `options` say, with grids and skeletons from `cache`, the
/// optimizer's search stopped after `time_limit` when given, diagnostics printed as `format` says.
pub fn run(
    path: &Path,
    format: MessageFormat,
    options: &CompileOptions,
    cache: PrecomputeCache,
    time_limit: Option<Duration>,
) -> i32 {
    let mut workspace = Workspace {
        cache,
        progress: progress::on_terminal(),
        ..Workspace::new()
    };
    interrupt_on_signals(&workspace.cancel);
    if let Some(limit) = time_limit {
        let cancel = workspace.cancel.clone();
        std::thread::spawn(move || {
            std::thread::sleep(limit);
            cancel.interrupt(Interruption::TimeLimit);
        });
    }
    let compilation = match compile_file(path, options, &mut workspace, format) {
        Ok(compilation) => compilation,
        Err(NotCompiled::Invalid(_)) => return EXIT_INVALID,
        Err(NotCompiled::Cancelled) => {
            let why = workspace
                .cancel
                .interruption()
                .unwrap_or(Interruption::Interrupt);
            let problem = no_design(why, workspace.stage());
            let name = path.display().to_string();
            match format {
                MessageFormat::Human => eprint!(
                    "{}",
                    super::diagnostics::render_for_terminal(&[problem], &name, "")
                ),
                MessageFormat::Json => print!(
                    "{}",
                    super::diagnostics::render_json_lines(&[problem], &name, "")
                ),
            }
            return exit_status(why);
        }
    };
    let written = match write_outputs(&compilation, path, options.out_dir.as_deref()) {
        Ok(written) => written,
        Err(message) => {
            eprintln!("error: {message}");
            return EXIT_INVALID;
        }
    };
    let interrupted = compilation
        .optimization
        .as_ref()
        .and_then(|o| o.interrupted);
    if let Some(optimization) = &compilation.optimization {
        let from_disk = workspace.cache.built().loaded;
        say(
            format,
            &optimization_table::optimization(optimization, &compilation, from_disk),
        );
    }
    say(format, &table::summary(&compilation, &file_name(path)));
    for target in &written.written {
        say(format, &format!("wrote {}\n", target.display()));
    }
    for stale in &written.removed {
        say(
            format,
            &format!(
                "removed {} (an output of the last build that this one no longer writes)\n",
                stale.display()
            ),
        );
    }
    match (interrupted, &compilation.optimization) {
        (Some(why), Some(optimization)) => {
            let message = format!(
                "{}: the search stopped after {} capsule count{}; the outputs hold the best design found so far, marked as interrupted in the report",
                describe(why),
                optimization.candidates.len(),
                if optimization.candidates.len() == 1 { "" } else { "s" }
            );
            if format == MessageFormat::Human {
                println!("{message}");
            }
            eprintln!("{message}");
            exit_status(why)
        }
        _ => goals_status(&compilation),
    }
}

/// The code of a build stopped before the optimizer had any design.
pub const STOPPED_WITHOUT_DESIGN: &str = "ballast::build::stopped_without_design";

/// The diagnostic of a build stopped by `why` during `stage` (the last long stage it started)
/// before the optimizer had finished a capsule count: there is no design, nothing is written.
fn no_design(why: Interruption, stage: Option<Stage>) -> Problem {
    let during = match &stage {
        Some(Stage::Grid { .. } | Stage::Skeleton { .. }) | None => "the precomputation",
        Some(_) => "the first capsule count",
    };
    let stood = stage.map_or(String::new(), |stage| format!(" (it was {stage})"));
    let help = match why {
        Interruption::TimeLimit => "give a longer `--time-limit`: the first design needs the distance grids, the skeletons and the heuristic's first round",
        Interruption::Interrupt | Interruption::Terminate => "let the build run until the optimizer has finished a capsule count",
    };
    Problem::error(
        STOPPED_WITHOUT_DESIGN,
        format!(
            "{} during {during}{stood}, before any design could be found: there is no design to write, and nothing was written (the previous outputs are left as they were)",
            describe(why)
        ),
    )
    .with_help(help)
}

/// Ctrl-C and SIGTERM interrupt `cancel`; a second one exits at once with its status. A warning
/// when they cannot be caught (the signals then end the process as usual).
fn interrupt_on_signals(cancel: &Cancel) {
    let mut signals = match Signals::new([SIGINT, SIGTERM]) {
        Ok(signals) => signals,
        Err(error) => {
            eprintln!("warning: cannot catch Ctrl-C or SIGTERM ({error}): they end the build without writing");
            return;
        }
    };
    let cancel = cancel.clone();
    std::thread::spawn(move || {
        for signal in signals.forever() {
            let why = if signal == SIGTERM {
                Interruption::Terminate
            } else {
                Interruption::Interrupt
            };
            if cancel.is_cancelled() {
                std::process::exit(exit_status(why));
            }
            cancel.interrupt(why);
        }
    });
}

/// The exit status of a build stopped by `why`.
fn exit_status(why: Interruption) -> i32 {
    match why {
        Interruption::Interrupt => EXIT_SIGINT,
        Interruption::Terminate => EXIT_SIGTERM,
        Interruption::TimeLimit => EXIT_TIME_LIMIT,
    }
}

/// `why` for the terminal.
fn describe(why: Interruption) -> &'static str {
    match why {
        Interruption::Interrupt => "interrupted by Ctrl-C (SIGINT)",
        Interruption::Terminate => "interrupted by SIGTERM",
        Interruption::TimeLimit => "interrupted: the time limit ran out",
    }
}
