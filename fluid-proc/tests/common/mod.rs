//! What the compressible tests share: the shipped scenes and a run to their end.

use fluid_proc::compressible::Compressible;
use fluid_proc::gas::Primitive;
use fluid_proc::setup::gas_from;
use fluid_section::Scene as Scenario;

/// One quantity of a cell's gas.
pub type Field = fn(&Primitive) -> f64;

/// The shipped scenario `scenarios/{name}.toml`.
pub fn shipped(name: &str) -> Scenario {
    let path = format!("{}/../scenarios/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    Scenario::load_file(std::path::Path::new(&path)).expect("shipped scenario")
}

/// The scene's gas run for `duration` from its initial state.
pub fn run_to(scenario: &Scenario, duration: f64) -> Compressible {
    let mut gas = gas_from(&scenario.fluid).expect("an euler scene");
    gas.advance(duration).expect("the run stays physical");
    gas
}

/// The scene's gas run from its start to its end time.
pub fn run_to_end(scenario: &Scenario) -> Compressible {
    run_to(scenario, scenario.run.end_time - scenario.run.start_time)
}
