//! `coupler bench implicit`: what an implicit window costs against an
//! explicit one (issue 22, item 7), on a scene both schemes run (by
//! default `scenarios/sheet-updraft.toml`: a porous sheet, stable either
//! way), each run `repeats` times in turn in the same invocation, the
//! fastest of each kept (the machine is shared and noisy).
//!
//! An implicit window of k tries should cost no more than k + 0.2 explicit
//! windows: the tries themselves, plus checkpoints, relaxation and the
//! verdict. The table gives that ratio against its target, and the share
//! of the implicit run's wall time the solvers spent saving and restoring
//! checkpoints and the library spent relaxing the accelerated fields.

use super::run_manifest;
use std::path::Path;

/// The scene's text with `scheme` set in its `[coupling]` table.
fn with_scheme(text: &str, scheme: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        if line.trim_start().starts_with("scheme") {
            continue;
        }
        out.push_str(line);
        out.push('\n');
        if line.trim() == "[coupling]" {
            out.push_str(&format!("scheme = \"{scheme}\"\n"));
        }
    }
    out
}

/// The fastest of `repeats` runs of each scheme: (run s, windows, tries
/// per window, checkpoint s, accelerate s).
fn fastest(exe: &Path, scene: &Path, repeats: usize) -> Result<[[f64; 5]; 2], String> {
    let text = std::fs::read_to_string(scene).map_err(|e| format!("cannot read it: {e}"))?;
    let mut best = [[f64::INFINITY; 5]; 2];
    for _ in 0..repeats {
        for (i, scheme) in ["explicit", "implicit"].iter().enumerate() {
            // Beside the scene, so that its relative paths still hold.
            let path = scene.with_extension(format!("bench-{scheme}.toml"));
            std::fs::write(&path, with_scheme(&text, scheme))
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
            let m = run_manifest(exe, &path);
            let _ = std::fs::remove_file(&path);
            let m = m?;
            let f = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN);
            let c = &m["coupling"];
            let windows = f(&m["schedule"]["windows"]);
            let tries = match i {
                0 => 1.0,
                _ => f(&m["implicit"]["mean_iterations"]),
            };
            let row = [
                f(&c["run_s"]),
                windows,
                tries,
                f(&c["checkpoint_s"]),
                f(&c["accelerate_s"]),
            ];
            if row[0] < best[i][0] {
                best[i] = row;
            }
        }
    }
    Ok(best)
}

/// Prints the table; returns the exit code.
pub fn implicit(scene: &Path, repeats: usize) -> i32 {
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: cannot find the coupler executable: {e}");
            return 1;
        }
    };
    println!(
        "{}: explicit and implicit, the fastest of {repeats} runs each",
        scene.display()
    );
    let [explicit, implicit] = match fastest(&exe, scene, repeats) {
        Ok(rows) => rows,
        Err(e) => {
            eprintln!("error: {}: {e}", scene.display());
            return 1;
        }
    };
    let per_window = |r: &[f64; 5]| r[0] / r[1];
    let ratio = per_window(&implicit) / per_window(&explicit);
    let target = implicit[2] + 0.2;
    println!(
        "{:<10} {:>8} {:>8} {:>12} {:>14} {:>12} {:>8} {:>14}",
        "scheme",
        "run s",
        "windows",
        "tries/window",
        "ms per window",
        "vs explicit",
        "target",
        "checkpoint+relax"
    );
    for (name, r) in [("explicit", explicit), ("implicit", implicit)] {
        let share = (r[3] + r[4]) / r[0];
        let (vs, goal) = match name {
            "explicit" => (1.0, String::from("")),
            _ => (
                ratio,
                format!(
                    "{target:.2} {}",
                    if ratio <= target { "ok" } else { "over" }
                ),
            ),
        };
        println!(
            "{name:<10} {:>8.3} {:>8.0} {:>12.2} {:>14.3} {:>12.2} {:>8} {:>13.2}%",
            r[0],
            r[1],
            r[2],
            1e3 * per_window(&r),
            vs,
            goal,
            100.0 * share
        );
    }
    0
}
