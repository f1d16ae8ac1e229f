//! The command line, as clap parses it.

use std::path::PathBuf;

use clap::{Parser, Subcommand};

/// ballast: design 3D-printed objects that balance, with steel balls rolling in capsules.
#[derive(Debug, Parser)]
#[command(name = "ballast", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Check a project and show what the object does in every pose. Writes nothing.
    ///
    /// Exit status: 0 every goal met, 1 the project is valid but some goal is not met,
    /// 2 invalid project or failure.
    Check {
        /// The project file (.kdl).
        project: PathBuf,
        /// Print the JSON report on standard output instead of the table.
        #[arg(long)]
        json: bool,
    },
    /// Check a project, then write its glTF file and JSON report.
    ///
    /// Nothing is written when the project is invalid. Exit status as for `check`.
    Build {
        /// The project file (.kdl).
        project: PathBuf,
        /// Write the outputs into this folder instead of the ones the project file names.
        #[arg(long, value_name = "DIR")]
        out_dir: Option<PathBuf>,
    },
}
