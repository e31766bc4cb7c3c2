//! structure-proc: the spring-mass library driven by the coupler, advanced by
//! the integrator the scenario names.

use structure_proc::driver::{self, Scheme};

fn main() {
    driver::main("structure-proc", |section, _| Ok(Scheme::of(section)));
}
