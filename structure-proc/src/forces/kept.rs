//! The force's terms that depend on the positions alone, kept from one
//! evaluation to the next at the same positions.
//!
//! Velocity Verlet evaluates the force twice a step (thesis eqs. 37–40):
//! at the end of a step, at (x_{n+1}, v_p) with the predicted velocity,
//! and at the start of the next, at (x_{n+1}, v_{n+1}). Only the dampers
//! (and a porous load the structure applies itself) read the velocities;
//! the springs, the membrane's triangles, gravity and the fluid's pressure
//! jump read x alone, and on the C-9 they take about half of the force's
//! time (`cargo bench -p structure-proc --bench parachute`). [`Kept`]
//! holds each node's sum of them from the first evaluation
//! (a node adds its dampers' slots after those terms', see
//! [`crate::network::Assemblies`]), and the pressure load's slots; the
//! second evaluation adds the dampers' new slots and the pressure's to the
//! kept sums in the same order, so the force is the same bits as a fresh one.
//!
//! What is kept is valid for the positions and the received pressure it was
//! computed from (both compared bit for bit: a collision pass, a moved
//! attachment or a new try's load simply misses) and for the network it
//! was computed on: [`crate::Network::prepare`], which every change of the
//! network must call, forgets it.

use super::assembly::{Slot, GRAIN};
use rayon::prelude::*;
use std::sync::Mutex;

/// The position-only terms of the last kept evaluation.
#[derive(Debug, Default)]
pub struct Terms {
    /// The positions and the received pressure they were computed at;
    /// `valid` is false until a kept evaluation fills them.
    pub(super) x: Vec<f64>,
    pub(super) pressure: Vec<f64>,
    pub(super) valid: bool,
    /// Each node's sum so far: gravity, its springs' forces and its
    /// membrane edges' (3 per node), which the dampers' slots continue.
    pub(super) sums: Vec<f64>,
    /// The pressure load's slot per triangle, kept when it reads x alone
    /// (no porous load in the structure).
    pub(super) triangles: Vec<Slot>,
}

impl Terms {
    /// Whether the terms were computed at positions `x` under the received
    /// pressure `pressure`, bit for bit (−0 is not +0 here, nor NaN a miss).
    pub(super) fn hold_for(&self, x: &[f64], pressure: &[f64]) -> bool {
        self.valid && same_bits(&self.x, x) && same_bits(&self.pressure, pressure)
    }

    /// Mark the terms as not computed at any positions.
    pub(super) fn forget(&mut self) {
        self.valid = false;
    }

    /// Mark the terms as computed at `x` under `pressure`.
    pub(super) fn computed_at(&mut self, x: &[f64], pressure: &[f64]) {
        self.x.resize(x.len(), 0.0);
        copy(&mut self.x, x);
        self.pressure.resize(pressure.len(), 0.0);
        copy(&mut self.pressure, pressure);
        self.valid = true;
    }
}

/// Values per rayon task of the comparisons and copies: each pass reads a
/// few hundred kilobytes on a large canopy, worth both cores; below two
/// such chunks it stays on the calling thread.
const CHUNK: usize = 3 * GRAIN;

fn same_bits(a: &[f64], b: &[f64]) -> bool {
    let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(p, q)| p.to_bits() == q.to_bits());
    a.len() == b.len()
        && if a.len() < 2 * CHUNK {
            same(a, b)
        } else {
            a.par_chunks(CHUNK)
                .zip(b.par_chunks(CHUNK))
                .all(|(a, b)| same(a, b))
        }
}

/// to ← from, in parallel on large slices.
pub(super) fn copy(to: &mut [f64], from: &[f64]) {
    if to.len() < 2 * CHUNK {
        to.copy_from_slice(from);
    } else {
        to.par_chunks_mut(CHUNK)
            .zip(from.par_chunks(CHUNK))
            .for_each(|(t, f)| t.copy_from_slice(f));
    }
}

/// [`Terms`] behind a lock: force evaluations take the network by `&`.
#[derive(Debug, Default)]
pub struct Kept(Mutex<Terms>);

impl Kept {
    /// Run `f` on the kept terms.
    pub fn with<R>(&self, f: impl FnOnce(&mut Terms) -> R) -> R {
        let mut terms = self.0.lock().unwrap_or_else(|e| e.into_inner());
        f(&mut terms)
    }
}

impl Clone for Kept {
    /// A clone keeps nothing: its network may change apart from this one's.
    fn clone(&self) -> Self {
        Kept::default()
    }
}
