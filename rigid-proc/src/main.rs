//! rigid-proc: the rigid-body library taking part in a coupled run.

use rigid_section::Scene;

fn main() {
    // `rigid-proc --check SCENARIO`: the [rigid] table, checked.
    scenario::answer_check(|path, text| Scene::load(path, text).map(|_| Default::default()));
    if let Err(e) = rigid_proc::driver::run() {
        eprintln!("rigid-proc: {e}");
        std::process::exit(1);
    }
}
