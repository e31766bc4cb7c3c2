//! `coupler study …`: integrator studies live in their own executable,
//! `study`, which links the structure solver's library (the coupler cannot:
//! the solvers depend on it). This finds or builds it and hands over the
//! arguments.

use super::programs::{self, Program};
use super::{EXIT_BAD_INPUT, EXIT_RUN_FAILED};

/// Runs `study` with `args`; its exit code is the coupler's.
pub fn study(args: &[String]) -> i32 {
    let here = std::env::current_dir().unwrap_or_default();
    let path = match programs::resolve("study", &here) {
        Some(Program::Found(p)) => p,
        Some(Program::Buildable {
            package,
            workspace,
            release,
            path,
        }) => match programs::build(&package, &workspace, release) {
            Ok(()) => path,
            Err(e) => {
                eprintln!("error: {e}");
                return EXIT_RUN_FAILED;
            }
        },
        None => {
            eprintln!(
                "error: program `study` not found: it is neither beside the coupler executable nor on PATH \
                 (build it with `cargo build --release -p study`)"
            );
            return EXIT_BAD_INPUT;
        }
    };
    match std::process::Command::new(&path).args(args).status() {
        Ok(s) => s.code().unwrap_or(EXIT_RUN_FAILED),
        Err(e) => {
            eprintln!("error: cannot start {}: {e}", path.display());
            EXIT_RUN_FAILED
        }
    }
}
