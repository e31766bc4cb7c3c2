//! `coupler bench contact`: what the structure's contact pass costs a run
//! of an open canopy (issue 46, item 2: at most 1.2× the run without it),
//! on a scene run with and without `[structure.collision]`, each run
//! `repeats` times in turn in the same invocation (the machine is shared
//! and noisy: the same run moves by 30 % from one to the next). By
//! default `scenarios/c9-drop.toml` over its first two seconds, before its
//! lines and folds first touch (at 2.2 s), with a 5 mm layer: the open
//! dome the issue measures.
//!
//! It prints each variant's fastest and median run, the ratio of the
//! medians against the target, and what structure-proc's log says the
//! pass cost against its own sub-steps and how many sub-steps it skipped
//! in quiet spells (`structure-proc/src/collision/quiet.rs`).

use super::run_reading;
use std::path::Path;

/// The run may cost at most this many times the run without the pass.
const TARGET: f64 = 1.2;

/// The scene's text ended at `end_time` [s], without its
/// `[structure.collision]` table and, when `layer` is given, with one of
/// that thickness [m] appended.
fn variant(text: &str, end_time: f64, layer: Option<f64>) -> String {
    let mut out = String::new();
    let mut in_collision = false;
    for line in text.lines() {
        let trimmed = line.trim();
        if trimmed.starts_with('[') {
            in_collision = trimmed == "[structure.collision]";
        }
        if in_collision {
            continue;
        }
        match trimmed.starts_with("end_time") {
            true => out.push_str(&format!("end_time = {end_time}\n")),
            false => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    if let Some(layer) = layer {
        out.push_str(&format!("\n[structure.collision]\nthickness = {layer}\n"));
    }
    out
}

/// The run's wall time [s] and, with the pass, the last line structure-proc
/// wrote of its cost.
fn run(exe: &Path, scene: &Path, text: &str, name: &str) -> Result<(f64, String), String> {
    // Beside the scene, so that its relative paths still hold.
    let path = scene.with_extension(format!("bench-{name}.toml"));
    std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    let ran = run_reading(exe, &path, Some("logs/structure.log"));
    let _ = std::fs::remove_file(&path);
    let (m, log) = ran?;
    let wall = m["coupling"]["run_s"].as_f64().unwrap_or(f64::NAN);
    let cost = log
        .lines()
        .rfind(|l| l.starts_with("the contact pass took"))
        .unwrap_or("")
        .to_string();
    Ok((wall, cost))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n % 2 {
        1 => v[n / 2],
        _ => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// Prints the table; returns the exit code.
pub fn contact(scene: &Path, end_time: f64, layer: f64, repeats: usize) -> i32 {
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: cannot find the coupler executable: {e}");
            return 1;
        }
    };
    let text = match std::fs::read_to_string(scene) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {}: cannot read it: {e}", scene.display());
            return 1;
        }
    };
    println!(
        "{} to {end_time} s, without and with the contact pass (layer {layer} m), {repeats} runs each in turn",
        scene.display()
    );
    let variants = [("none", None), ("contact", Some(layer))];
    let mut walls = [Vec::new(), Vec::new()];
    let mut cost = String::new();
    for _ in 0..repeats {
        for (i, (name, layer)) in variants.iter().enumerate() {
            match run(&exe, scene, &variant(&text, end_time, *layer), name) {
                Ok((wall, c)) => {
                    walls[i].push(wall);
                    if layer.is_some() {
                        cost = c;
                    }
                }
                Err(e) => {
                    eprintln!("error: {}: {e}", scene.display());
                    return 1;
                }
            }
        }
    }
    println!("{:<8} {:>10} {:>10}", "pass", "fastest s", "median s");
    for ((name, _), w) in variants.iter().zip(&walls) {
        let fastest = w.iter().copied().fold(f64::INFINITY, f64::min);
        println!("{name:<8} {fastest:>10.3} {:>10.3}", median(w.clone()));
    }
    let ratio = median(walls[1].clone()) / median(walls[0].clone());
    let verdict = if ratio <= TARGET { "ok" } else { "over" };
    println!(
        "with the pass: {ratio:.2} times the run without it (medians; target {TARGET}: {verdict})"
    );
    println!("structure-proc, last run: {cost}");
    0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_variant_ends_the_run_and_sets_its_own_layer() {
        let scene = "[run]\nname = \"x\"\nend_time = 3.0\n\n[structure]\nsubsteps = 10\n\n\
                     [structure.collision]\nthickness = 1e-3\nmodel = \"layered\"\n\n[fluid]\nmodel = \"porous\"\n";
        let without = variant(scene, 2.0, None);
        assert!(without.contains("end_time = 2\n"), "{without}");
        assert!(!without.contains("collision"), "{without}");
        assert!(without.contains("[fluid]\nmodel = \"porous\""), "{without}");
        let with = variant(scene, 2.0, Some(5e-3));
        assert!(
            with.ends_with("[structure.collision]\nthickness = 0.005\n"),
            "{with}"
        );
        assert!(!with.contains("layered"), "{with}");
    }
}
