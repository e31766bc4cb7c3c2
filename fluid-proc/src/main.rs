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

/// The `--check` answer: restarts, a graded box's cells, which follow
/// from its core and are written nowhere else, and a warning where the
/// pressure solve's multigrid stops at a large level.
fn answer(scene: &Scene) -> scenario::Answer {
    let mut answer = scenario::Answer::with_restarts();
    answer.warnings.extend(multigrid_warning(scene));
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

/// Where the box's counts do not halve, the multigrid's coarsest level is
/// large and its sweeps take most of each V-cycle: worth a word, since a
/// count or two changed makes every step cheaper.
fn multigrid_warning(scene: &Scene) -> Option<String> {
    use fluid_proc::incompressible::{multigrid, setup};
    if scene.fluid.model != fluid_section::FluidModel::Incompressible {
        return None;
    }
    let (grid, _) = setup::grid_of(&scene.fluid)?;
    let levels = multigrid::level_cells(&grid);
    let share = multigrid::coarsest_share(&levels);
    let [nx, ny, nz] = *levels.last()?;
    (share > 0.5).then(|| {
        format!(
            "[fluid.box] cells: the pressure solve's multigrid stops at {nx} × {ny} × {nz} \
             cells (an axis halves while its count is even), whose sweeps take {:.0} % of \
             each V-cycle; counts with more factors of 2 make every step cheaper",
            100.0 * share
        )
    })
}
