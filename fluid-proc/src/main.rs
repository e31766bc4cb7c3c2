//! fluid-proc: the flow models taking part in a coupled run.

use fluid_section::Scene;

fn main() {
    // `fluid-proc --check SCENARIO`: the [fluid] table, checked.
    // Every model saves and restores window checkpoints (implicit
    // coupling) and writes run checkpoints (restart).
    scenario::answer_check(|path, text| {
        Scene::load(path, text).map(|_| scenario::Answer::with_restarts())
    });
    if let Err(e) = fluid_proc::driver::run() {
        eprintln!("fluid-proc: {e}");
        std::process::exit(1);
    }
}
