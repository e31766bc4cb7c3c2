//! Helpers for canopy's integration tests: build the executables, run the
//! coupler, read what a run left behind.

mod scene;

pub use scene::{ParticipantSpec, Scenario};
use std::path::{Path, PathBuf};
use std::process::Output;
use std::sync::{Once, OnceLock};

pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace root")
        .to_path_buf()
}

fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace().join("target"))
}

/// `cargo build --release ARGS` in the workspace, or cargo's stderr.
fn try_cargo_build(args: &[&str]) -> Result<(), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = std::process::Command::new(cargo)
        .current_dir(workspace())
        .args(["build", "--release"])
        .args(args)
        .output()
        .map_err(|e| format!("cannot run cargo build: {e}"))?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "cargo build {args:?} failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// `cargo build --release ARGS` in the workspace; panics with cargo's
/// stderr if it fails.
fn cargo_build(args: &[&str]) {
    try_cargo_build(args).unwrap_or_else(|e| panic!("{e}"));
}

/// The MPI fluid-proc's path, or why it could not be built (see
/// `mpi_fluid_proc`); set by `ensure_built` where `mpirun` runs.
static MPI_FLUID_PROC: OnceLock<Result<PathBuf, String>> = OnceLock::new();

/// Build every executable of the workspace once (release), so tests launch
/// what the README's command launches; first, where `mpirun` runs, fluid-proc with
/// its `mpi` feature. That one is built in the workspace's own target
/// directory, where only fluid-proc and the MPI crates compile again (a
/// target directory of its own compiled every dependency a second time),
/// and cargo puts it where the default fluid-proc was: it is copied to
/// `target/release/mpi/`, and the default build put back, before any test
/// of this process can start a run.
pub fn ensure_built() {
    static BUILD: Once = Once::new();
    BUILD.call_once(|| {
        if has_mpirun() {
            let _ = MPI_FLUID_PROC.set(build_mpi_fluid_proc());
        }
        cargo_build(&["--bins"]);
    });
}

/// fluid-proc with its `mpi` feature, copied to `target/release/mpi/`.
fn build_mpi_fluid_proc() -> Result<PathBuf, String> {
    try_cargo_build(&["-p", "fluid-proc", "--features", "mpi"])?;
    let release = target_dir().join("release");
    let copy = release.join("mpi").join("fluid-proc");
    std::fs::create_dir_all(copy.parent().unwrap())
        .and_then(|()| std::fs::copy(release.join("fluid-proc"), &copy))
        .map_err(|e| format!("cannot copy the MPI fluid-proc to {}: {e}", copy.display()))?;
    Ok(copy)
}

/// Example `name` of workspace package `package`, built (release).
pub fn example_exe(package: &str, name: &str) -> PathBuf {
    ensure_built();
    cargo_build(&["-p", package, "--example", name]);
    target_dir().join("release").join("examples").join(name)
}

/// Whether `mpirun` runs on this machine (OpenMPI installed).
pub fn has_mpirun() -> bool {
    std::process::Command::new("mpirun")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// fluid-proc built with its `mpi` feature (by `ensure_built`), or None
/// when this machine has no `mpirun`. CI sets `CANOPY_REQUIRE_MPI` (its
/// script installs OpenMPI), and then a machine without MPI fails instead
/// of skipping; where the MPI build failed, the tests that need it fail
/// with cargo's message and the others run.
pub fn mpi_fluid_proc() -> Option<PathBuf> {
    if !has_mpirun() {
        assert!(
            std::env::var_os("CANOPY_REQUIRE_MPI").is_none(),
            "CANOPY_REQUIRE_MPI is set but mpirun cannot be run"
        );
        eprintln!("no mpirun on this machine: the MPI runs are skipped");
        return None;
    }
    ensure_built();
    match MPI_FLUID_PROC.get() {
        Some(Ok(path)) => Some(path.clone()),
        Some(Err(e)) => panic!("{e}"),
        None => panic!("mpirun runs now but did not when the executables were built"),
    }
}

pub fn coupler_exe() -> PathBuf {
    ensure_built();
    target_dir().join("release").join("coupler")
}

/// A fresh, empty scratch directory for one test, removed when the test
/// passes and kept, its path printed, when it fails.
pub fn scratch(name: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("canopy-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    Scratch(dir)
}

/// A test's scratch directory (`scratch`): it goes when dropped, unless
/// the test is failing (its thread panicking), when it stays for a look.
#[derive(Debug)]
pub struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        match std::thread::panicking() {
            true => eprintln!("the failed test's files are kept in {}", self.0.display()),
            false => {
                let _ = std::fs::remove_dir_all(&self.0);
            }
        }
    }
}

/// The shipped scenario `name` run once in this test process for every
/// test that reads it: its output directory. The run is kept for the
/// process's life (a static is never dropped), so a validation tier that
/// shares it leaves this one run in the temporary folder.
pub fn shipped_run(name: &str) -> &'static Path {
    static RUNS: std::sync::Mutex<std::collections::BTreeMap<String, &'static Path>> =
        std::sync::Mutex::new(std::collections::BTreeMap::new());
    let mut runs = RUNS.lock().unwrap_or_else(|e| e.into_inner());
    runs.entry(name.to_string()).or_insert_with(|| {
        let dir: &'static Scratch = Box::leak(Box::new(scratch(name)));
        let out: &'static Path = Box::leak(dir.join("run").into_boxed_path());
        run_ok(&scenario_path(name), out);
        out
    })
}

pub fn scenario_path(name: &str) -> PathBuf {
    workspace().join("scenarios").join(format!("{name}.toml"))
}

/// Load a shipped scenario, change it, and write it into `dir`.
pub fn variant(name: &str, dir: &Path, change: impl FnOnce(&mut Scenario)) -> PathBuf {
    let mut s = Scenario::load(&scenario_path(name)).expect("shipped scenario parses");
    change(&mut s);
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, s.to_toml()).expect("write scenario");
    path
}

/// `scenarios/cloth-strings.toml` on the coarser mesh the CI runs (10
/// rings, 20 segments a string, 10 structure sub-steps a window).
pub fn coarse_cloth_strings(s: &mut Scenario) {
    s.structure_mut().substeps = 10;
    let st = s.structure.as_mut().expect("cloth-strings has a structure");
    st.disk.as_mut().expect("cloth-strings has a disk").rings = 10;
    st.cords[0].segments = 20;
}

pub fn coupler(args: &[&str]) -> Output {
    std::process::Command::new(coupler_exe())
        .args(args)
        .output()
        .expect("run coupler")
}

/// Whether `coupler check` passes `scenario`, which puts a section on the
/// GPU. False, with a note, where it is refused for want of an adapter and
/// `CANOPY_REQUIRE_GPU` is unset: the test then skips on a machine without
/// one. Any other refusal fails the test, with the coupler's message.
pub fn gpu_check_passes(scenario: &Path) -> bool {
    let o = coupler(&["check", scenario.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    if !o.status.success()
        && err.contains("no GPU adapter")
        && std::env::var_os(gpu_device::REQUIRE_GPU).is_none()
    {
        eprintln!("skipped: {err}");
        return false;
    }
    assert!(o.status.success(), "check of {}: {err}", scenario.display());
    true
}

/// The command `coupler run scenario --out out`, not yet started.
pub fn run_command(scenario: &Path, out: &Path) -> std::process::Command {
    let mut command = std::process::Command::new(coupler_exe());
    command.args([
        "run",
        scenario.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    command
}

/// `coupler run scenario --out out`.
pub fn run(scenario: &Path, out: &Path) -> Output {
    run_command(scenario, out).output().expect("run coupler")
}

/// Run a scenario into `out`; panics with the coupler's stderr if it fails.
pub fn run_ok(scenario: &Path, out: &Path) {
    let o = run(scenario, out);
    assert!(
        o.status.success(),
        "run of {} failed:\n{}",
        scenario.display(),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Run a scenario that must fail into `out`: exit code 1 and a
/// `run failed:` line, which is returned.
pub fn run_failed(scenario: &Path, out: &Path) -> String {
    let o = run(scenario, out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "a failed run exits 1:\n{err}");
    err.lines()
        .find(|l| l.starts_with("run failed:"))
        .unwrap_or_else(|| panic!("no failure line in:\n{err}"))
        .to_string()
}

/// `monitors.csv` as columns.
pub struct Monitors {
    pub header: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Monitors {
    pub fn read(run: &Path) -> Monitors {
        let text = std::fs::read_to_string(run.join("monitors.csv")).expect("monitors.csv");
        let mut lines = text.lines();
        let header = lines
            .next()
            .expect("header")
            .split(',')
            .map(String::from)
            .collect();
        let rows = lines
            .map(|l| l.split(',').map(|v| v.parse().expect("number")).collect())
            .collect();
        Monitors { header, rows }
    }

    pub fn column(&self, name: &str) -> Vec<f64> {
        let i = self
            .header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.header));
        self.rows.iter().map(|r| r[i]).collect()
    }

    /// The mean of monitor `name` over the rows from `from` to `to` [s].
    pub fn mean_over(&self, name: &str, from: f64, to: f64) -> f64 {
        let (t, v) = (self.column("time"), self.column(name));
        let picked: Vec<f64> = (0..t.len())
            .filter(|&i| t[i] >= from && t[i] <= to)
            .map(|i| v[i])
            .collect();
        picked.iter().sum::<f64>() / picked.len() as f64
    }

    /// Monitor `name` in the first row at or after `time` [s].
    pub fn at(&self, name: &str, time: f64) -> f64 {
        let t = self.column("time");
        let row = t
            .iter()
            .position(|&t| t >= time - 1e-9)
            .expect("a row at that time");
        self.column(name)[row]
    }
}

/// Everything of parachute `p` that falls [kg]: the `payload`, the fabric
/// on its flat nominal area (the vent's few grams included) and the lines.
pub fn falling_mass(p: &structure_section::Parachute, payload: f64) -> f64 {
    let g = p.geometry();
    payload
        + p.fabric.areal_density * g.nominal_area()
        + p.line_density * g.line_length * g.gores as f64
}

pub fn manifest(run: &Path) -> serde_json::Value {
    serde_json::from_str(
        &std::fs::read_to_string(run.join("manifest.json")).expect("manifest.json"),
    )
    .expect("manifest parses")
}

/// The number that follows `marker` in `text` (up to the next space), e.g.
/// the time in "diverged at t = 2.4e0 s"; panics if there is none.
pub fn number_after(text: &str, marker: &str) -> f64 {
    text.split(marker)
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|x| x.parse().ok())
        .unwrap_or_else(|| panic!("no number after {marker:?} in {text:?}"))
}

/// The last `.vti` the fluid wrote into a run directory.
pub fn last_vti(run: &Path) -> PathBuf {
    std::fs::read_dir(run.join("vtk"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vti"))
        .max()
        .expect("fluid outputs")
}
