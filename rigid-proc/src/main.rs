//! rigid-proc: the rigid-body library taking part in a coupled run.

use rigid_section::Scene;

fn main() {
    // `rigid-proc --check SCENARIO`: the [rigid] table, checked.
    // It saves and restores window checkpoints (implicit coupling).
    scenario::answer_check(|path, text| {
        Scene::load(path, text).map(|_| scenario::Answer::with_restarts())
    });
    if let Err(e) = rigid_proc::driver::run() {
        eprintln!("rigid-proc: {e}");
        std::process::exit(1);
    }
}
