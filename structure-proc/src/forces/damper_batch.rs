//! The dampers laid out field by field (a structure of arrays) for the
//! force pass, which recomputes them at every evaluation (they read the
//! velocities, see [`kept`](super::kept)): four dampers' coefficients are
//! one vector load ([`simd`](super::simd), for thesis eq. 68's law; the
//! axial law runs one damper at a time). The [`Damper`]s stay the
//! description every other part reads, and [`Damper::force`] the law this
//! pass follows bit for bit.

use super::assembly::{Slot, GRAIN};
use super::damping::{Damper, Law};
use super::simd;
use rayon::prelude::*;

#[derive(Debug, Clone, Default)]
pub struct DamperBatch {
    /// End points, each below `nodes`.
    pub(super) i: Vec<u32>,
    pub(super) j: Vec<u32>,
    /// Coefficient [N·s/m].
    pub(super) c: Vec<f64>,
    /// Length below which the damper idles [m].
    pub(super) slack_below: Vec<f64>,
    nodes: usize,
}

impl DamperBatch {
    /// The dampers of a network of `nodes` nodes; panics on an end beyond it.
    pub fn new(dampers: &[Damper], nodes: usize) -> DamperBatch {
        assert!(nodes <= u32::MAX as usize, "too many nodes: {nodes}");
        let end = |n: usize| {
            assert!(n < nodes, "damper end {n} of {nodes} nodes");
            n as u32
        };
        DamperBatch {
            i: dampers.iter().map(|d| end(d.i)).collect(),
            j: dampers.iter().map(|d| end(d.j)).collect(),
            c: dampers.iter().map(|d| d.c).collect(),
            slack_below: dampers.iter().map(|d| d.slack_below).collect(),
            nodes,
        }
    }

    pub fn len(&self) -> usize {
        self.i.len()
    }

    pub fn is_empty(&self) -> bool {
        self.i.is_empty()
    }

    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// out[k] ← damper k's force on its node i at (x, v) under `law`
    /// ([`Damper::force`]; node j gets its opposite), in parallel.
    pub fn forces(&self, law: Law, x: &[f64], v: &[f64], out: &mut [Slot]) {
        assert_eq!(out.len(), self.len(), "slot buffer of the wrong length");
        assert!(
            3 * self.nodes <= x.len().min(v.len()),
            "state of too few nodes"
        );
        let chunk = |first: usize, o: &mut [Slot]| {
            if !simd::damper_forces(self, law, x, v, first, o) {
                for (k, o) in o.iter_mut().enumerate() {
                    *o = self.scalar_force(law, x, v, first + k);
                }
            }
        };
        // Below two grains the pass stays on the calling thread, as
        // assembly.rs's passes do: waking the pool costs more than it saves.
        if self.len() < 2 * GRAIN {
            chunk(0, out);
        } else {
            out.par_chunks_mut(GRAIN)
                .enumerate()
                .for_each(|(c, o)| chunk(c * GRAIN, o));
        }
    }

    /// Damper k's force on its node i, one damper at a time.
    #[inline]
    pub(super) fn scalar_force(&self, law: Law, x: &[f64], v: &[f64], k: usize) -> Slot {
        let d = Damper {
            i: self.i[k] as usize,
            j: self.j[k] as usize,
            c: self.c[k],
            slack_below: self.slack_below[k],
        };
        Slot::from(d.force(law, x, v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vector pass gives Damper::force's bits under both laws: dampers
    /// acting and idle (a slack string's, a zero length), in more than one
    /// vector's worth plus a remainder and over more than one chunk.
    #[test]
    fn batch_is_damper_force_bit_for_bit() {
        let nodes = 701;
        let mut x: Vec<f64> = (0..3 * nodes)
            .map(|k| ((k * 7919) % 1013) as f64 * 1e-3 - 0.5)
            .collect();
        x.copy_within(0..3, 3); // nodes 0 and 1 coincide: a zero length
        let v: Vec<f64> = (0..3 * nodes)
            .map(|k| ((k * 104_729) % 997) as f64 * 1e-2 - 5.0)
            .collect();
        let dampers: Vec<Damper> = (0..3 * GRAIN + 3)
            .map(|k| Damper {
                i: k % nodes,
                j: if k == 0 { 1 } else { (k * 5 + 1) % nodes },
                c: 0.01 * (1 + k % 13) as f64,
                slack_below: [0.0, 0.0, 0.3, 0.8][k % 4],
            })
            .collect();
        let batch = DamperBatch::new(&dampers, nodes);
        for law in [Law::RelativeVelocity, Law::Axial] {
            let mut out = vec![Slot([f64::NAN; 4]); dampers.len()];
            batch.forces(law, &x, &v, &mut out);
            for (k, d) in dampers.iter().enumerate() {
                let expected = Slot::from(d.force(law, &x, &v)).0.map(f64::to_bits);
                assert_eq!(
                    out[k].0.map(f64::to_bits),
                    expected,
                    "{law:?} damper {k}: {d:?}"
                );
            }
            let idle = out.iter().filter(|s| **s == Slot::ZERO).count();
            assert!(idle > 0 && idle < dampers.len() / 2, "{law:?}: {idle} idle");
        }
    }
}
