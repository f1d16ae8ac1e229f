//! The `ballast` binary: see `ballast --help` and docs/cli.md.

fn main() {
    std::process::exit(ballast::cli::run());
}
