//! `coupler bench parachute`: the C-9 at the original code's resolution
//! (issue 43, item 1), `scenarios/c9-frontier-grid.toml`: FronTier++'s
//! 12 × 12 × 24 m box of 60 × 60 × 120 cells, 11 173 canopy vertices,
//! lines of 140 segments. Two variants, each run for a stated number of
//! windows in the same invocation:
//!
//! - explicit coupling with FronTier++'s heavier fabric (0.2 kg/m², its
//!   C-9 input's mass per area), the like of the original code's step;
//! - the scene as shipped: implicit IQN-ILS coupling with 50 g/m² fabric;
//! - the same with `scheme = "parallel-implicit"`: the fluid and the
//!   structure compute each try at once.
//!
//! With `--device gpu` it runs the scene as shipped on the CPU and with
//! both solvers on the GPU (`[fluid] device = "gpu"`, `[structure] device =
//! "gpu"`, issue 47), one after the other, and prints their ratio and
//! issue 47's target of 0.1 s a window beside the GPU's.
//!
//! Per window it prints the coupled run's wall time (from the start signal
//! to the end, the setup not counted) and where it went: each solver's own
//! work, the quasi-Newton acceleration, the window checkpoints' saving and
//! restoring, and each solver's waiting; and the tries. Given FronTier++'s
//! `airfoil` (`shared/peers/frontier/build.sh`), it runs the original
//! code's own C-9 for as many steps right after and prints each variant's
//! speed-up over its step; without it, FronTier++'s figures measured for
//! issue 43 stand beside them for reference.

use super::run_manifest;
use std::path::Path;

/// FronTier++ at commit 852a7b0 on its own C-9 input (`in-C9`), one
/// process, on this machine kind (2 cores) on a quiet machine, 2026-11-28
/// (issue 43; `shared/peers/README.md`): seconds per fluid step in two
/// runs, and the split of the second.
const FRONTIER_STEP_S: [f64; 2] = [6.7, 6.92];
const FRONTIER_FLUID_S: f64 = 4.31;
const FRONTIER_STRUCTURE_S: f64 = 1.21;

/// The mass per area of FronTier++'s C-9 fabric, about 0.2 kg/m² on the
/// canopy (issue 43's explicit variant) [kg/m²].
const FRONTIER_AREAL_DENSITY: f64 = 0.2;

/// One variant's run, per window.
struct Row {
    wall_s: f64,
    tries: f64,
    most_tries: f64,
    fluid_s: f64,
    structure_s: f64,
    accelerate_s: f64,
    checkpoint_s: f64,
    fluid_wait_s: f64,
    structure_wait_s: f64,
}

impl Row {
    /// From a run's manifest.
    fn of(m: &serde_json::Value) -> Row {
        let f = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN);
        let windows = f(&m["schedule"]["windows"]);
        let per = |v: &serde_json::Value| f(v) / windows;
        let process = |role: &str| {
            let list = m["processes"].as_array().cloned().unwrap_or_default();
            let p = list.into_iter().find(|p| p["role"] == role);
            p.unwrap_or(serde_json::Value::Null)
        };
        let (fluid, structure) = (process("fluid"), process("structure"));
        let implicit = &m["implicit"];
        let (tries, most_tries) = match implicit.is_null() {
            true => (1.0, 1.0),
            false => (
                f(&implicit["mean_iterations"]),
                f(&implicit["largest_iterations"]),
            ),
        };
        Row {
            wall_s: per(&m["coupling"]["run_s"]),
            tries,
            most_tries,
            fluid_s: per(&fluid["compute_s"]),
            structure_s: per(&structure["compute_s"]),
            accelerate_s: per(&m["coupling"]["accelerate_s"]),
            checkpoint_s: per(&m["coupling"]["checkpoint_s"]),
            fluid_wait_s: per(&fluid["wait_s"]),
            structure_wait_s: per(&structure["wait_s"]),
        }
    }
}

/// The variants run, in order.
#[derive(Clone, Copy, PartialEq)]
enum Variant {
    /// Explicit coupling with FronTier++'s fabric.
    Explicit,
    /// The scene as shipped.
    Implicit,
    /// The scene with the parallel implicit scheme.
    Parallel,
    /// The scene as shipped, the fluid and the structure on the GPU.
    Gpu,
}

impl Variant {
    const ALL: [Variant; 3] = [Variant::Explicit, Variant::Implicit, Variant::Parallel];

    fn title(self) -> &'static str {
        match self {
            Variant::Explicit => "explicit, fabric 0.2 kg/m²",
            Variant::Implicit => "implicit IQN-ILS, fabric 50 g/m²",
            Variant::Parallel => "parallel-implicit, fabric 50 g/m²",
            Variant::Gpu => "implicit IQN-ILS, 50 g/m², on the GPU",
        }
    }

    fn file_tag(self) -> &'static str {
        match self {
            Variant::Explicit => "explicit",
            Variant::Implicit => "implicit",
            Variant::Parallel => "parallel",
            Variant::Gpu => "gpu",
        }
    }
}

/// The scene's text changed into `variant`, `windows` windows long.
fn variant(text: &str, windows: u32, variant: Variant) -> Result<String, String> {
    let mut s: toml::Table = text.parse().map_err(|e| format!("cannot parse it: {e}"))?;
    let table = |s: &toml::Table, key: &str| -> Result<toml::Table, String> {
        let t = s.get(key).and_then(|v| v.as_table()).cloned();
        t.ok_or(format!("it has no [{key}]"))
    };
    let (mut run, mut coupling) = (table(&s, "run")?, table(&s, "coupling")?);
    let window = coupling.get("window").and_then(|v| v.as_float());
    let window = window.ok_or("its [coupling] has no window")?;
    let start = run.get("start_time").and_then(|v| v.as_float());
    let end = start.unwrap_or(0.0) + windows as f64 * window;
    run.insert("end_time".into(), toml::Value::Float(end));
    if variant == Variant::Gpu {
        for part in ["fluid", "structure"] {
            let t = s.get_mut(part).and_then(|v| v.as_table_mut());
            let t = t.ok_or(format!("it has no [{part}]"))?;
            t.insert("device".into(), toml::Value::String("gpu".into()));
        }
    }
    if variant == Variant::Parallel {
        let scheme = toml::Value::String("parallel-implicit".into());
        coupling.insert("scheme".into(), scheme);
    }
    if variant == Variant::Explicit {
        coupling.insert("scheme".into(), toml::Value::String("explicit".into()));
        coupling.remove("implicit");
        let fabric = s
            .get_mut("structure")
            .and_then(|v| v.get_mut("parachute"))
            .and_then(|v| v.get_mut("fabric"))
            .and_then(|v| v.as_table_mut())
            .ok_or("it has no [structure.parachute.fabric]")?;
        let density = toml::Value::Float(FRONTIER_AREAL_DENSITY);
        fabric.insert("areal_density".into(), density);
    }
    s.insert("run".into(), toml::Value::Table(run));
    s.insert("coupling".into(), toml::Value::Table(coupling));
    toml::to_string(&s).map_err(|e| e.to_string())
}

/// Run one variant of `scene` for `windows` windows; its row.
fn measure(exe: &Path, scene: &Path, windows: u32, which: Variant) -> Result<Row, String> {
    let text = std::fs::read_to_string(scene).map_err(|e| format!("cannot read it: {e}"))?;
    let name = which.file_tag();
    // Beside the scene, so that its relative paths still hold.
    let path = scene.with_extension(format!("bench-{name}.toml"));
    std::fs::write(&path, variant(&text, windows, which)?)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    let m = run_manifest(exe, &path);
    let _ = std::fs::remove_file(&path);
    Ok(Row::of(&m.map_err(|e| format!("{name}: {e}"))?))
}

/// Prints the table; returns the exit code. With `frontier` (its `airfoil`
/// executable and C-9 input) FronTier++ runs as many steps right after, and
/// each variant's speed-up over its step is printed.
pub fn parachute(scene: &Path, windows: u32, frontier: Option<(&Path, &Path)>, gpu: bool) -> i32 {
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: cannot find the coupler executable: {e}");
            return 1;
        }
    };
    let mut rows = Vec::new();
    let variants: &[Variant] = match gpu {
        true => &[Variant::Implicit, Variant::Gpu],
        false => &Variant::ALL,
    };
    for &which in variants {
        match measure(&exe, scene, windows, which) {
            Ok(r) => rows.push((which.title(), r)),
            Err(e) => {
                eprintln!("error: {}: {e}", scene.display());
                return 1;
            }
        }
    }
    let peer =
        match frontier.map(|(airfoil, input)| super::frontier::measure(airfoil, input, windows)) {
            Some(Err(e)) => {
                eprintln!("error: FronTier++: {e}");
                return 1;
            }
            Some(Ok(step)) => Some(step),
            None => None,
        };
    print_table(scene, windows, &rows, peer.as_ref());
    if let [(_, cpu), (_, gpu)] = &rows[..] {
        println!(
            "on the GPU: {:.3} s a window against {:.3} on the CPU ({:.1}×); issue 47's target: ≤ {GPU_TARGET_S} s",
            gpu.wall_s,
            cpu.wall_s,
            cpu.wall_s / gpu.wall_s
        );
    }
    0
}

/// Issue 47's target for the implicit C-9 at 60 × 60 × 120 cells with both
/// solvers on the GPU [s a window].
const GPU_TARGET_S: f64 = 0.1;

fn print_table(
    scene: &Path,
    windows: u32,
    rows: &[(&str, Row)],
    peer: Option<&super::frontier::Step>,
) {
    println!(
        "{}: {windows} windows of each variant, one after the other; seconds per window \
         (coupled run from start to end, setup not counted)",
        scene.display()
    );
    println!(
        "{:<34} {:>8} {:>11} {:>8} {:>9} {:>8} {:>11} {:>10} {:>11} {:>12}",
        "variant",
        "wall s",
        "tries",
        "fluid s",
        "struct s",
        "accel s",
        "checkpts s",
        "fluid wait",
        "struct wait",
        "× FronTier++"
    );
    for (name, r) in rows {
        let speedup = peer.map_or(String::from("–"), |p| {
            format!("{:.2}", p.total_s / r.wall_s)
        });
        println!(
            "{name:<34} {:>8.3} {:>5.1} ({:>3.0}) {:>8.3} {:>9.3} {:>8.3} {:>11.3} {:>10.3} {:>11.3} {speedup:>12}",
            r.wall_s,
            r.tries,
            r.most_tries,
            r.fluid_s,
            r.structure_s,
            r.accelerate_s,
            r.checkpoint_s,
            r.fluid_wait_s,
            r.structure_wait_s
        );
    }
    match peer {
        Some(p) => println!(
            "{:<34} {:>8.3} {:>11} {:>8.3} {:>9.3}   (its own clocks, mean of {} steps after the first 2, one process, run right after)",
            "FronTier++ in-C9, explicit, a step", p.total_s, "1", p.fluid_s, p.structure_s, p.steps
        ),
        None => println!(
            "{:<34} {:>8} {:>11} {:>8.2} {:>9.2}   (issue 43's figures on this machine kind, 2026-11-28, not re-run: \
             --frontier AIRFOIL runs it beside)",
            "FronTier++ in-C9, explicit, a step",
            format!("{}-{}", FRONTIER_STEP_S[0], FRONTIER_STEP_S[1]),
            "1",
            FRONTIER_FLUID_S,
            FRONTIER_STRUCTURE_S
        ),
    }
}
