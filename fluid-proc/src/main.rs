//! fluid-proc: the flow models taking part in a coupled run.

use fluid_section::Scene;

fn main() {
    // `fluid-proc --check SCENARIO`: the [fluid] table, checked.
    // The incompressible and porous models save and restore window
    // checkpoints (implicit coupling); the euler model does not yet.
    scenario::answer_check(|path, text| {
        Scene::load(path, text).map(|s| scenario::Answer {
            checkpoints: s.fluid.model != fluid_section::FluidModel::Euler,
            ..Default::default()
        })
    });
    if let Err(e) = fluid_proc::driver::run() {
        eprintln!("fluid-proc: {e}");
        std::process::exit(1);
    }
}
