//! fluid-proc: the flow models taking part in a coupled run.

use fluid_section::{Device, Scene};
use scenario::{section, ScenarioError};
use std::path::Path;

fn main() {
    // `fluid-proc --check SCENARIO`: the [fluid] table, checked.
    // Every model saves and restores window checkpoints (implicit
    // coupling) and writes run checkpoints (restart).
    scenario::answer_check(|path, text| {
        let scene = Scene::load(path, text)?;
        let device = check_device(&scene, path, text)?;
        let mut answer = answer(&scene);
        answer.notes.extend(device);
        Ok(answer)
    });
    if let Err(e) = fluid_proc::driver::run() {
        eprintln!("fluid-proc: {e}");
        std::process::exit(1);
    }
}

/// The `--check` answer: restarts, and a graded box's cells, which follow
/// from its core and are written nowhere else.
fn answer(scene: &Scene) -> scenario::Answer {
    let mut answer = scenario::Answer::with_restarts();
    if let Some((b, core)) = scene.fluid.flow_box.and_then(|b| Some((b, b.core?))) {
        let [nx, ny, nz] = b.cells;
        answer.notes.push(format!(
            "cells {nx} × {ny} × {nz}, graded from a core of {} m cells growing by at most {}",
            core.spacing, core.growth
        ));
        let cells: Vec<i64> = b.cells.iter().map(|&n| i64::from(n)).collect();
        answer.manifest.insert("cells".into(), cells.into());
    }
    answer
}

/// `device = "gpu"` needs an adapter that takes the box: where none does,
/// that is a problem of the key that asks for it. Where one does, a note
/// names it.
fn check_device(scene: &Scene, path: &Path, text: &str) -> Result<Option<String>, ScenarioError> {
    if scene.fluid.device != Device::Gpu {
        return Ok(None);
    }
    let why = match fluid_proc::incompressible::device::probe(&scene.fluid) {
        Ok(adapter) => return Ok(Some(format!("the flow runs on {adapter}"))),
        Err(why) => why,
    };
    section::checked(path, text, |c| {
        c.within("fluid", None, |c| {
            c.problem(&["device"], format!("device = \"gpu\": {why}"))
        })
    })?;
    Ok(None)
}
