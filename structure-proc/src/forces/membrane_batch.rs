//! The membrane's triangles laid out field by field (a structure of arrays)
//! for the force pass, which reads them every evaluation: four triangles'
//! rest lengths, or one entry of their matrices Q, are one vector load
//! ([`simd`](super::simd)). The [`TriangleSprings`] stay the description
//! every other part reads, and [`TriangleSprings::edge_forces`] the law
//! this pass follows bit for bit.

use super::assembly::{Slot, GRAIN};
use super::delingette::TriangleSprings;
use super::simd;
use nalgebra::Matrix3;
use rayon::prelude::*;

#[derive(Debug, Clone, Default)]
pub struct MembraneBatch {
    /// `nodes[v][k]`: vertex v of triangle k, each below `nodes_count`.
    pub(super) nodes: [Vec<u32>; 3],
    /// `rest[e][k]`: rest length of triangle k's edge e [m].
    pub(super) rest: [Vec<f64>; 3],
    /// `q[3e + f][k]`: entry (e, f) of triangle k's Q (eqs. 2.30–2.31) [N/m].
    pub(super) q: [Vec<f64>; 9],
    nodes_count: usize,
}

impl MembraneBatch {
    /// The triangles of a network of `nodes` nodes; panics on a vertex beyond it.
    pub fn new(triangles: &[TriangleSprings], nodes: usize) -> MembraneBatch {
        assert!(nodes <= u32::MAX as usize, "too many nodes: {nodes}");
        let vertex = |t: &TriangleSprings, v: usize| {
            assert!(t.nodes[v] < nodes, "vertex {} of {nodes} nodes", t.nodes[v]);
            t.nodes[v] as u32
        };
        MembraneBatch {
            nodes: std::array::from_fn(|v| triangles.iter().map(|t| vertex(t, v)).collect()),
            rest: std::array::from_fn(|e| triangles.iter().map(|t| t.rest[e]).collect()),
            q: std::array::from_fn(|ef| triangles.iter().map(|t| t.q[(ef / 3, ef % 3)]).collect()),
            nodes_count: nodes,
        }
    }

    pub fn len(&self) -> usize {
        self.nodes[0].len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn nodes(&self) -> usize {
        self.nodes_count
    }

    /// out[3k + e] ← the force of triangle k's edge e on the edge's first
    /// vertex at positions `x` ([`TriangleSprings::edge_forces`]), in
    /// parallel over triangles.
    pub fn forces(&self, x: &[f64], out: &mut [Slot]) {
        assert_eq!(out.len(), 3 * self.len(), "slot buffer of the wrong length");
        assert!(
            3 * self.nodes_count <= x.len(),
            "positions of too few nodes"
        );
        // Below two grains the pass stays on the calling thread, as
        // assembly.rs's passes do: waking the pool costs more than it saves.
        if self.len() < 2 * GRAIN {
            self.chunk(x, 0, out);
        } else {
            out.par_chunks_mut(3 * GRAIN)
                .enumerate()
                .for_each(|(c, o)| self.chunk(x, c * GRAIN, o));
        }
    }

    /// Triangles `first..first + out.len() / 3`.
    fn chunk(&self, x: &[f64], first: usize, out: &mut [Slot]) {
        if !simd::membrane_forces(self, x, first, out) {
            for (k, o) in out.chunks_exact_mut(3).enumerate() {
                o.copy_from_slice(&self.scalar_forces(x, first + k));
            }
        }
    }

    /// Triangle k's edge forces, one triangle at a time.
    #[inline]
    pub(super) fn scalar_forces(&self, x: &[f64], k: usize) -> [Slot; 3] {
        let t = TriangleSprings {
            nodes: self.nodes.each_ref().map(|n| n[k] as usize),
            rest: self.rest.each_ref().map(|r| r[k]),
            q: Matrix3::from_fn(|e, f| self.q[3 * e + f][k]),
        };
        t.edge_forces(x).map(Slot::from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::delingette::lame;

    /// The vector pass gives TriangleSprings::edge_forces' bits on
    /// stretched, compressed and sheared triangles, in more than one
    /// vector's worth plus a remainder and over more than one chunk.
    #[test]
    fn batch_is_edge_forces_bit_for_bit() {
        let (side, nodes) = (40, 1600);
        let rest: Vec<f64> = (0..nodes)
            .flat_map(|n| [(n % side) as f64 * 0.1, (n / side) as f64 * 0.1, 0.0])
            .collect();
        let (lambda, mu) = lame(1e8, 0.3, 1e-4);
        let mut triangles = Vec::new();
        for r in 0..side - 1 {
            for c in 0..side - 1 {
                let n = r * side + c;
                for tri in [[n, n + 1, n + side + 1], [n, n + side + 1, n + side]] {
                    triangles.push(TriangleSprings::new(&rest, tri, lambda, mu).unwrap());
                }
            }
        }
        let x: Vec<f64> = rest
            .iter()
            .enumerate()
            .map(|(k, r)| {
                r * (0.9 + 0.2 * ((k * 7919) % 101) as f64 / 101.0) + 1e-3 * (k % 5) as f64
            })
            .collect();
        let batch = MembraneBatch::new(&triangles, nodes);
        let mut out = vec![Slot::ZERO; 3 * triangles.len()];
        batch.forces(&x, &mut out);
        assert!(triangles.len() > 2 * GRAIN && triangles.len() % 4 != 0);
        for (k, t) in triangles.iter().enumerate() {
            let expected = t.edge_forces(&x).map(|f| Slot::from(f).0.map(f64::to_bits));
            let got: Vec<[u64; 4]> = out[3 * k..3 * k + 3]
                .iter()
                .map(|s| s.0.map(f64::to_bits))
                .collect();
            assert_eq!(got, expected, "triangle {k}: {t:?}");
        }
        assert!(
            out.iter().all(|s| s.0[0] != 0.0 || s.0[1] != 0.0),
            "a test that cannot fail"
        );
    }
}
