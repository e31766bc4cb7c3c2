//! Find the executable that plays each role.
//!
//! A bare name is looked up beside the running `coupler` executable, then on
//! PATH. When it is neither but the coupler runs from a cargo target directory
//! of this workspace and a workspace package has that name, it is built first,
//! so `cargo run -p coupler -- run …` works on a fresh clone.

use std::path::{Path, PathBuf};

#[derive(Debug, Clone)]
pub enum Program {
    Found(PathBuf),
    /// Not built yet: `cargo build [--release] -p package` in `workspace` makes `path`.
    Buildable {
        package: String,
        workspace: PathBuf,
        release: bool,
        path: PathBuf,
    },
}

fn is_executable(p: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    p.is_file()
        && p.metadata()
            .map(|m| m.permissions().mode() & 0o111 != 0)
            .unwrap_or(false)
}

/// Where `program` is, or None when it cannot be found or built.
pub fn resolve(program: &str, scenario_dir: &Path) -> Option<Program> {
    if program.contains('/') {
        let p = Path::new(program);
        let p = if p.is_absolute() {
            p.to_path_buf()
        } else {
            scenario_dir.join(p)
        };
        return is_executable(&p).then_some(Program::Found(p));
    }
    let exe_dir = std::env::current_exe().ok()?.parent()?.to_path_buf();
    let beside = exe_dir.join(program);
    if is_executable(&beside) {
        return Some(Program::Found(beside));
    }
    if let Some(path) = std::env::var_os("PATH") {
        for dir in std::env::split_paths(&path) {
            let p = dir.join(program);
            if is_executable(&p) {
                return Some(Program::Found(p));
            }
        }
    }
    // <workspace>/target/<profile>/coupler, with <workspace>/<program>/Cargo.toml naming the package.
    let profile = exe_dir.file_name()?.to_str()?.to_string();
    let workspace = exe_dir.parent()?.parent()?.to_path_buf();
    let manifest = std::fs::read_to_string(workspace.join(program).join("Cargo.toml")).ok()?;
    manifest
        .contains(&format!("name = \"{program}\""))
        .then(|| Program::Buildable {
            package: program.to_string(),
            workspace,
            release: profile == "release",
            path: beside,
        })
}

/// Build a workspace package; the user sees cargo's own output.
pub fn build(package: &str, workspace: &Path, release: bool) -> Result<(), String> {
    eprintln!("coupler: building `{package}` (first run of this checkout)…");
    let mut cmd =
        std::process::Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cmd.current_dir(workspace).args(["build", "-p", package]);
    if release {
        cmd.arg("--release");
    }
    match cmd.status() {
        Ok(s) if s.success() => Ok(()),
        Ok(s) => Err(format!("`cargo build -p {package}` failed ({s})")),
        Err(e) => Err(format!("cannot run cargo to build `{package}`: {e}")),
    }
}

/// Build `program` if it is a workspace package not built yet; then its path.
pub fn ensure_built(program: &mut Program) -> Result<PathBuf, String> {
    if let Program::Buildable {
        package,
        workspace,
        release,
        path,
    } = program.clone()
    {
        build(&package, &workspace, release)?;
        *program = Program::Found(path);
    }
    match program {
        Program::Found(p) => Ok(p.clone()),
        Program::Buildable { .. } => unreachable!("built above"),
    }
}
