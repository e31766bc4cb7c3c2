//! Forces on the nodes, each term in its own file with its energy where one
//! exists: Hookean springs and strings (`spring.rs`), Delingette's triangular
//! springs (`delingette.rs`), viscous damping (`damping.rs`), the fluid's
//! pressure jump (`pressure.rs`), and gravity here.

pub mod damping;
pub mod delingette;
pub mod pressure;
pub mod spring;

use crate::model::Model;
use crate::system::System;
pub use pressure::area_normal2;

/// Loads from other processes, held for one step and read in place.
#[derive(Debug, Clone, Copy, Default)]
pub struct Loads<'a> {
    /// Signed pressure jump per canopy triangle [Pa]; empty when no fluid takes part.
    pub pressure: &'a [f64],
}

/// The model under its loads: what the integrators advance.
pub struct Dynamics<'a> {
    pub model: &'a Model,
    pub loads: &'a Loads<'a>,
}

/// Gravitational energy −Σ m g·x [J].
pub fn gravity_energy(m: &Model, x: &[f64]) -> f64 {
    (0..m.nodes())
        .map(|n| -m.mass[n] * (0..3).map(|c| m.gravity[c] * x[3 * n + c]).sum::<f64>())
        .sum()
}

/// Elastic energy of springs, strings and triangular springs at `x` [J].
pub fn elastic_energy(m: &Model, x: &[f64]) -> f64 {
    m.springs.iter().map(|s| s.energy(x)).sum::<f64>()
        + m.membrane.iter().map(|t| t.energy(x)).sum::<f64>()
}

/// Total force at positions `x`, velocities `v`; `f` is overwritten. Only free
/// nodes are accelerated, but every node gets its force: on an attached node it is
/// what the structure exerts on the rigid body.
pub fn total_force(m: &Model, loads: &Loads, x: &[f64], v: &[f64], f: &mut [f64]) {
    for n in 0..m.nodes() {
        for c in 0..3 {
            f[3 * n + c] = m.mass[n] * m.gravity[c];
        }
    }
    for s in &m.springs {
        s.add_force(x, f);
    }
    for t in &m.membrane {
        t.add_force(x, f);
    }
    if let Some(law) = m.damping {
        for d in &m.dampers {
            d.add_force(law, x, v, f);
        }
    }
    pressure::add_pressure(&m.triangles, loads.pressure, x, f);
}

impl System for Dynamics<'_> {
    fn nodes(&self) -> usize {
        self.model.nodes()
    }

    fn inv_mass(&self) -> &[f64] {
        &self.model.inv_mass
    }

    fn force(&self, x: &[f64], v: &[f64], f: &mut [f64]) {
        total_force(self.model, self.loads, x, v, f);
    }

    /// The elastic and viscous terms; gravity is constant and the pressure
    /// load's dependence on the canopy's shape is left to the Newton iterations.
    fn jacobian_product(&self, x: &[f64], _v: &[f64], a: f64, b: f64, p: &[f64], out: &mut [f64]) {
        let m = self.model;
        out.fill(0.0);
        if a != 0.0 {
            for s in &m.springs {
                s.add_stiffness_product(x, a, p, out);
            }
            for t in &m.membrane {
                t.add_stiffness_product(x, a, p, out);
            }
        }
        if let (Some(law), true) = (m.damping, b != 0.0) {
            for d in &m.dampers {
                d.add_damping_product(law, x, b, p, out);
            }
        }
    }

    fn couplings(&self) -> &[(usize, usize, f64)] {
        &self.model.couplings
    }
}
