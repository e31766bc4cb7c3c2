//! fluid-proc: the flow models taking part in a coupled run.

use fluid_section::Scene;

fn main() {
    // `fluid-proc --check SCENARIO`: the [fluid] table, checked.
    // The incompressible and porous models save and restore window
    // checkpoints (implicit coupling) and write run checkpoints (restart);
    // the euler model does neither yet.
    scenario::answer_check(|path, text| {
        use fluid_section::FluidModel;
        Scene::load(path, text).map(|s| scenario::Answer {
            checkpoints: s.fluid.model != FluidModel::Euler,
            restarts: s.fluid.model != FluidModel::Euler,
            ..Default::default()
        })
    });
    if let Err(e) = fluid_proc::driver::run() {
        eprintln!("fluid-proc: {e}");
        std::process::exit(1);
    }
}
