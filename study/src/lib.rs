//! study: canopy's integrators compared by error against CPU time, the
//! comparison of thesis §2.4–§2.5 done with exact solutions and measured
//! orders. `coupler study accuracy` runs [`accuracy::sweep`] and writes what
//! [`report`] and [`plot`] make of it.

pub mod accuracy;
pub mod cpu;
pub mod elliptic;
pub mod plot;
pub mod reference;
pub mod report;
pub mod scene;
pub mod stability;

use structure_section::Integrator;

/// The distinct integrators of `items`, in the order they first appear.
pub fn integrators_in(items: impl IntoIterator<Item = Integrator>) -> Vec<Integrator> {
    let mut out: Vec<Integrator> = Vec::new();
    for i in items {
        if !out.contains(&i) {
            out.push(i);
        }
    }
    out
}
