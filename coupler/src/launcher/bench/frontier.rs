//! FronTier++'s own C-9 beside `coupler bench parachute`, when the bench
//! is given its `airfoil` executable (built by `shared/peers/frontier/
//! build.sh`): the same number of steps on one process, timed by its own
//! clocks (`CLOCK t (name)` lines of its run output), as
//! `shared/peers/frontier/clocks.py` reads them.

use std::path::Path;

/// Steps at the start left out of the mean (set-up work lands in them).
const SKIPPED: usize = 2;

/// FronTier++'s mean step: the whole step, the flow solver's `solve`, the
/// structure's `propagate` [s].
pub struct Step {
    pub total_s: f64,
    pub fluid_s: f64,
    pub structure_s: f64,
    pub steps: usize,
}

/// Run `airfoil` on `input` (its C-9 input, `Max step` replaced) for
/// `steps` steps after [`SKIPPED`] more, in a scratch directory removed
/// after; the mean of the timed steps.
pub fn measure(airfoil: &Path, input: &Path, steps: u32) -> Result<Step, String> {
    let text = std::fs::read_to_string(input)
        .map_err(|e| format!("cannot read {}: {e}", input.display()))?;
    let most = format!("Max step: {}", steps as usize + SKIPPED);
    let text: Vec<String> = text
        .lines()
        .map(|l| match l.starts_with("Max step:") {
            true => most.clone(),
            false => l.to_string(),
        })
        .collect();
    let dir = std::env::temp_dir().join(format!(
        "canopy-frontier-{}",
        participant::supervisor::new_run_id()
    ));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("in-C9"), text.join("\n") + "\n").map_err(|e| e.to_string())?;
    let status = std::process::Command::new(airfoil)
        .args(["-d", "3", "-p", "1", "1", "1", "-i", "in-C9", "-o", "out"])
        .current_dir(&dir)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMP_NUM_THREADS", "1")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status();
    let output = std::fs::read_to_string(dir.join("out").join("run-output"));
    let _ = std::fs::remove_dir_all(&dir);
    match status {
        Ok(s) if s.success() => {}
        Ok(s) => return Err(format!("{} ended with {s}", airfoil.display())),
        Err(e) => return Err(format!("cannot run {}: {e}", airfoil.display())),
    }
    let output = output.map_err(|e| format!("no run-output: {e}"))?;
    mean_step(&output).ok_or_else(|| format!("fewer than {} steps timed", SKIPPED + 1))
}

/// The mean of the steps after the first [`SKIPPED`] in FronTier++'s run
/// output: each step runs from `CLOCK (time_step)` to `CLOCK t
/// (time_step)`, and `solve` and `propagate` are summed within it.
fn mean_step(output: &str) -> Option<Step> {
    let mut steps: Vec<[f64; 3]> = Vec::new();
    let mut current: Option<[f64; 3]> = None;
    for line in output.lines() {
        let Some(rest) = line.trim_start().strip_prefix("CLOCK") else {
            continue;
        };
        let (time, name) = match rest.trim().split_once('(') {
            Some((t, n)) => (t.trim().parse::<f64>().ok(), n.trim_end_matches(')')),
            None => continue,
        };
        match (name, time, current.as_mut()) {
            ("time_step", None, _) => current = Some([0.0; 3]),
            ("time_step", Some(t), Some(c)) => {
                c[0] = t;
                steps.extend(current.take());
            }
            ("solve", Some(t), Some(c)) => c[1] += t,
            ("propagate", Some(t), Some(c)) => c[2] += t,
            _ => {}
        }
    }
    let timed = steps.get(SKIPPED..).filter(|s| !s.is_empty())?;
    let mean = |i: usize| timed.iter().map(|s| s[i]).sum::<f64>() / timed.len() as f64;
    Some(Step {
        total_s: mean(0),
        fluid_s: mean(1),
        structure_s: mean(2),
        steps: timed.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Steps are read between their opening and closing clocks, nested
    /// clocks summed by name, the first two left out.
    #[test]
    fn the_mean_step_of_a_run_output() {
        let step = |total: f64, solve: f64| {
            format!(
                "CLOCK           (time_step)\nCLOCK           (propagate)\n  CLOCK    0.03   \
                 (propagate_surface_points)\nCLOCK    1.50   (propagate)\nCLOCK    {solve}   \
                 (solve)\nCLOCK    {total}   (time_step)\n"
            )
        };
        let text = [
            step(99.0, 50.0),
            step(99.0, 50.0),
            step(10.0, 6.0),
            step(12.0, 7.0),
        ];
        let s = mean_step(&text.concat()).unwrap();
        assert_eq!(s.steps, 2);
        assert_eq!((s.total_s, s.fluid_s, s.structure_s), (11.0, 6.5, 1.5));
        assert!(mean_step(&text[..2].concat()).is_none());
    }
}
