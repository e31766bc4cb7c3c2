//! Forces on the nodes, each term in its own file with its energy where one
//! exists: Hookean springs and strings (`spring.rs`), Delingette's triangular
//! springs (`delingette.rs`), viscous damping (`damping.rs`), the pressure
//! jump from the fluid or from the porous law (`pressure.rs`), and gravity here.

pub mod assembly;
pub mod damper_batch;
pub mod damping;
pub mod delingette;
pub mod jacobian;
pub mod kept;
pub mod membrane_batch;
pub mod pressure;
mod simd;
pub mod spring;
pub mod spring_batch;
pub mod spring_blocks;

use crate::network::{Assemblies, Layout, Network};
use crate::system::System;
use assembly::{fill, Slot};
pub use pressure::area_normal2;

/// Loads from other processes, held for one step and read in place.
#[derive(Debug, Clone, Copy, Default)]
pub struct Loads<'a> {
    /// Signed pressure jump per canopy triangle [Pa]; empty when no fluid takes part.
    pub pressure: &'a [f64],
}

/// The network under its loads: what the integrators advance.
pub struct Dynamics<'a> {
    pub net: &'a Network,
    pub loads: &'a Loads<'a>,
}

/// Gravitational energy −Σ m g·x [J].
pub fn gravity_energy(m: &Network, x: &[f64]) -> f64 {
    (0..m.nodes())
        .map(|n| -m.mass[n] * (0..3).map(|c| m.gravity[c] * x[3 * n + c]).sum::<f64>())
        .sum()
}

/// Elastic energy of springs, strings and triangular springs at `x` [J].
pub fn elastic_energy(m: &Network, x: &[f64]) -> f64 {
    m.springs.iter().map(|s| s.energy(x)).sum::<f64>()
        + m.membrane.iter().map(|t| t.energy(x)).sum::<f64>()
}

/// Splits the slot buffer into the families of `at`.
fn families<'s>(
    slots: &'s mut [Slot],
    at: &Layout,
) -> (&'s mut [Slot], &'s mut [Slot], &'s mut [Slot]) {
    let (springs, rest) = slots.split_at_mut(at.membrane);
    let (membrane, dampers) = rest.split_at_mut(at.dampers - at.membrane);
    (springs, membrane, dampers)
}

/// Total force at positions `x`, velocities `v`; `f` is overwritten. Only free
/// nodes are accelerated, but every node gets its force: on an attached node it is
/// what the structure exerts on the rigid body. Elements run in parallel (see
/// [`assembly`](mod@assembly)); the sum is the same on any number of threads.
pub fn total_force(m: &Network, loads: &Loads, x: &[f64], v: &[f64], f: &mut [f64]) {
    checked_layout(m);
    m.spring_blocks.forces(x, |n| weight(m, n), f);
    // Each node adds its membrane slots and then its dampers' after its
    // springs', as in the network's assembly.
    add_membrane(m, x, f);
    add_dampers(m, x, v, f);
    add_pressure(m, loads, x, v, f);
}

/// [`total_force`], the same bits, keeping the terms that read the
/// positions alone for the next call at the same positions and received
/// pressure, which then adds only the dampers and the pressure load's
/// slots to the kept sums ([`kept`]).
pub fn total_force_keeping(m: &Network, loads: &Loads, x: &[f64], v: &[f64], f: &mut [f64]) {
    checked_layout(m);
    // The pressure jump reads x alone unless the structure applies the porous law.
    let pressure_kept = m.porous.is_none() && !loads.pressure.is_empty();
    m.kept.with(|k| {
        if !k.hold_for(x, loads.pressure) {
            // Not valid until filled: a panic halfway leaves nothing to reuse.
            k.forget();
            k.sums.resize(f.len(), 0.0);
            m.spring_blocks.forces(x, |n| weight(m, n), &mut k.sums);
            add_membrane(m, x, &mut k.sums);
            if pressure_kept {
                k.triangles.resize(m.triangles.len(), Slot::ZERO);
                pressure_slots(m, loads, x, v, &mut k.triangles);
            }
            k.computed_at(x, loads.pressure);
        }
        kept::copy(f, &k.sums);
        add_dampers(m, x, v, f);
        if pressure_kept {
            m.assembly.pressure.gather_add(&k.triangles, f);
        } else {
            add_pressure(m, loads, x, v, f);
        }
    });
}

/// f ← f + the membrane's edge forces at `x`.
fn add_membrane(m: &Network, x: &[f64], f: &mut [f64]) {
    if m.membrane.is_empty() {
        return;
    }
    m.scratch.with(3 * m.membrane.len(), |slots| {
        m.membrane_batch.forces(x, slots);
        m.assembly.membrane.gather_add(slots, f);
    });
}

/// f ← f + the dampers' forces at (x, v) (zero when undamped).
fn add_dampers(m: &Network, x: &[f64], v: &[f64], f: &mut [f64]) {
    if m.dampers.is_empty() {
        return;
    }
    m.scratch.with(m.dampers.len(), |slots| {
        match m.damping {
            Some(law) => m.damper_batch.forces(law, x, v, slots),
            None => slots.fill(Slot::ZERO),
        }
        m.assembly.dampers.gather_add(slots, f);
    });
}

/// The external loads alone, gravity and the pressure jump (the fluid's and
/// the porous law's), at positions `x` and velocities `v`; `f` is
/// overwritten. For solvers that treat the elastic and viscous terms as
/// constraints.
pub fn external_force(m: &Network, loads: &Loads, x: &[f64], v: &[f64], f: &mut [f64]) {
    checked_layout(m);
    for (n, fn_) in f.chunks_exact_mut(3).enumerate() {
        fn_.copy_from_slice(&weight(m, n).0[..3]);
    }
    add_pressure(m, loads, x, v, f);
}

/// m·g of node n [N].
fn weight(m: &Network, n: usize) -> Slot {
    let [gx, gy, gz] = m.gravity.map(|g| g * m.mass[n]);
    Slot::new(gx, gy, gz)
}

/// f ← f + the pressure jump's load: the fluid's when one sends it, plus the
/// porous law's when the structure applies it (`[structure.porous]`).
fn add_pressure(m: &Network, loads: &Loads, x: &[f64], v: &[f64], f: &mut [f64]) {
    if loads.pressure.is_empty() && m.porous.is_none() {
        return;
    }
    m.scratch.with(m.triangles.len(), |slots| {
        pressure_slots(m, loads, x, v, slots);
        m.assembly.pressure.gather_add(slots, f);
    });
}

/// Each canopy triangle's share of the pressure load on each of its
/// vertices, into its slot.
fn pressure_slots(m: &Network, loads: &Loads, x: &[f64], v: &[f64], slots: &mut [Slot]) {
    let fluid = !loads.pressure.is_empty();
    fill(slots, &m.triangles, |k, tri| {
        let received = if fluid { loads.pressure[k] } else { 0.0 };
        let porous = m
            .porous
            .as_ref()
            .map_or(0.0, |p| p.triangle_jump(x, v, tri));
        [pressure::vertex_load(x, tri, received + porous)]
    });
}

/// The slot layout of `m`, checked against the assembly [`Network::prepare`] built.
fn checked_layout(m: &Network) -> Layout {
    let at = Layout::of(m);
    let Assemblies {
        elements,
        membrane,
        dampers,
        pressure,
    } = &m.assembly;
    assert!(
        at.end == elements.slots()
            && at.dampers - at.membrane == membrane.slots()
            && 3 * m.membrane_batch.len() == membrane.slots()
            && m.damper_batch.len() == dampers.slots()
            && at.end - at.dampers == dampers.slots()
            && m.spring_blocks.springs() == m.springs.len()
            && m.triangles.len() == pressure.slots()
            && m.nodes() == elements.nodes(),
        "the model changed after Network::prepare: call it again"
    );
    at
}

impl System for Dynamics<'_> {
    fn nodes(&self) -> usize {
        self.net.nodes()
    }

    fn inv_mass(&self) -> &[f64] {
        &self.net.inv_mass
    }

    fn force(&self, x: &[f64], v: &[f64], f: &mut [f64]) {
        total_force(self.net, self.loads, x, v, f);
    }

    fn force_keeping(&self, x: &[f64], v: &[f64], f: &mut [f64]) {
        total_force_keeping(self.net, self.loads, x, v, f);
    }

    /// The elastic and viscous terms and the porous load's resistance to
    /// motion; gravity is constant and the pressure load's dependence on the
    /// canopy's shape is left to the Newton iterations.
    fn jacobian_product(&self, x: &[f64], v: &[f64], a: f64, b: f64, p: &[f64], out: &mut [f64]) {
        let m = self.net;
        let at = checked_layout(m);
        m.scratch.with(at.end, |slots| {
            let (springs, membrane, dampers) = families(slots, &at);
            if a != 0.0 {
                fill(springs, &m.springs, |_, s| [s.stiffness_product(x, a, p)]);
                fill(membrane, &m.membrane, |_, t| t.stiffness_product(x, a, p));
            } else {
                springs.fill(Slot::ZERO);
                membrane.fill(Slot::ZERO);
            }
            match (m.damping, b != 0.0) {
                (Some(law), true) => {
                    fill(
                        dampers,
                        &m.dampers,
                        |_, d| [d.damping_product(law, x, b, p)],
                    )
                }
                _ => dampers.fill(Slot::ZERO),
            }
            m.assembly.elements.gather(slots, |_| Slot::ZERO, out);
        });
        if let (Some(law), true) = (&m.porous, b != 0.0) {
            m.scratch.with(m.triangles.len(), |slots| {
                fill(slots, &m.triangles, |_, tri| {
                    [pressure::porous_damping_product(law, x, v, tri, b, p)]
                });
                m.assembly.pressure.gather_add(slots, out);
            });
        }
    }

    fn jacobian_blocks(
        &self,
        x: &[f64],
        v: &[f64],
        a: f64,
        b: f64,
        out: &mut Vec<jacobian::Block>,
    ) -> bool {
        jacobian::blocks(self.net, x, v, a, b, out);
        true
    }

    fn couplings(&self) -> &[(usize, usize, f64)] {
        &self.net.couplings
    }
}
