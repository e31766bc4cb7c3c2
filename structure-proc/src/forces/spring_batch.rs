//! Springs laid out field by field (a structure of arrays) for the force
//! pass, which reads them every step: four springs' rest lengths are one
//! vector load ([`simd`](super::simd)). Each block of
//! [`SpringBlocks`](super::spring_blocks::SpringBlocks) holds one; the
//! [`Spring`]s stay the description every other part reads, and
//! [`Spring::force`] the law this pass follows bit for bit.

use super::assembly::Slot;
use super::simd;
use crate::network::Spring;

/// Springs of one kind: all Hookean, or all strings (tension only).
#[derive(Debug, Clone, Default)]
pub struct SpringBatch {
    /// End points, each below `nodes`.
    pub(super) i: Vec<u32>,
    pub(super) j: Vec<u32>,
    /// Stiffness [N/m].
    pub(super) k: Vec<f64>,
    /// Rest length [m].
    pub(super) rest: Vec<f64>,
    /// Strings only: the compressive tolerance ε [m]; empty for springs, so
    /// that a spring costs the pass 24 bytes.
    pub(super) eps: Vec<f64>,
    pub(super) strings: bool,
    nodes: usize,
}

impl SpringBatch {
    /// Springs of one kind (`strings`: tension only) of a network of `nodes`
    /// nodes; panics on an end beyond it or a spring of the other kind.
    pub fn new(springs: &[Spring], strings: bool, nodes: usize) -> SpringBatch {
        assert!(nodes <= u32::MAX as usize, "too many nodes: {nodes}");
        let end = |n: usize| {
            assert!(n < nodes, "spring end {n} of {nodes} nodes");
            n as u32
        };
        assert!(springs.iter().all(|s| s.tension_only == strings));
        SpringBatch {
            i: springs.iter().map(|s| end(s.i)).collect(),
            j: springs.iter().map(|s| end(s.j)).collect(),
            k: springs.iter().map(|s| s.k).collect(),
            rest: springs.iter().map(|s| s.rest).collect(),
            eps: if strings {
                springs.iter().map(|s| s.eps).collect()
            } else {
                Vec::new()
            },
            strings,
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

    /// out[k] ← the force of spring k on its node i at positions `x`
    /// ([`Spring::force`]; node j gets its opposite).
    pub fn forces(&self, x: &[f64], out: &mut [Slot]) {
        assert_eq!(out.len(), self.len(), "slot buffer of the wrong length");
        if !simd::spring_forces(self, x, out) {
            for (k, o) in out.iter_mut().enumerate() {
                *o = self.scalar_force(x, k);
            }
        }
    }

    /// Spring k's force on its node i, one spring at a time.
    #[inline]
    pub(super) fn scalar_force(&self, x: &[f64], k: usize) -> Slot {
        let spring = Spring {
            i: self.i[k] as usize,
            j: self.j[k] as usize,
            k: self.k[k],
            rest: self.rest[k],
            tension_only: self.strings,
            eps: if self.strings { self.eps[k] } else { 0.0 },
        };
        Slot::from(spring.force(x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Springs and strings of every kind the pass meets: stretched,
    /// compressed, slack and taut strings, a zero length, a zero stiffness (a
    /// broken line), in more than one vector's worth plus a remainder.
    fn springs(nodes: usize) -> (Vec<Spring>, Vec<f64>) {
        let x: Vec<f64> = (0..3 * nodes)
            .map(|k| ((k * 7919) % 1013) as f64 * 1e-3 - 0.5)
            .collect();
        let mut x = x;
        x.copy_within(0..3, 3); // nodes 0 and 1 coincide: a zero length
        let springs = (0..nodes * 3)
            .map(|k| {
                let (i, j) = (k % nodes, (k * 5 + 1) % nodes);
                let l = (0..3)
                    .map(|c| (x[3 * j + c] - x[3 * i + c]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                Spring {
                    i,
                    j,
                    k: if k % 11 == 0 { 0.0 } else { 100.0 + k as f64 },
                    rest: l * [0.9, 1.0, 1.1, 1.3][k % 4],
                    tension_only: k % 3 == 0,
                    eps: if k % 6 == 0 { 1e-3 } else { 0.0 },
                }
            })
            .collect();
        (springs, x)
    }

    /// The vector pass gives Spring::force's bits, the scalar law of thesis
    /// eqs. (3) and (67), for every spring.
    #[test]
    fn batch_is_spring_force_bit_for_bit() {
        let nodes = 347;
        let (all, x) = springs(nodes);
        for strings in [false, true] {
            let springs: Vec<Spring> = all
                .iter()
                .filter(|s| s.tension_only == strings)
                .copied()
                .collect();
            let batch = SpringBatch::new(&springs, strings, nodes);
            let mut out = vec![Slot::ZERO; springs.len()];
            batch.forces(&x, &mut out);
            for (k, s) in springs.iter().enumerate() {
                let f = s.force(&x);
                assert_eq!(out[k], Slot::from(f), "spring {k}: {s:?}");
            }
            assert!(out.iter().any(|s| s.0[0] != 0.0), "a test that cannot fail");
            if strings {
                assert!(out.iter().any(|s| s.0[0] == 0.0), "no slack string");
            }
        }
    }
}
