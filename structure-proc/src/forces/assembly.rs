//! Parallel, deterministic assembly of element contributions into node sums.
//!
//! Every element (spring, triangle edge, damper, pressure triangle) writes its
//! contribution into a slot of its own, in parallel with rayon; then every node
//! sums the slots that touch it, in parallel over nodes and in a fixed order.
//! No two threads write the same memory, no locks or atomics are needed, and
//! the result is bit-for-bit the same on any number of threads.
//!
//! A slot holds its three components in four lanes, the last zero, so that
//! the node sums add a slot in one vector instruction where the CPU has AVX2
//! ([`simd`](super::simd)); either way a node adds its slots one by one in
//! the same order, so the sums are the same bits on every machine.

use super::simd;
use nalgebra::Vector3;
use rayon::prelude::*;
use std::sync::Mutex;

/// One element's contribution to a node [N, or N/m·m for Jacobian products]:
/// x, y, z and a zero lane.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[repr(C, align(32))]
pub struct Slot(pub [f64; 4]);

impl Slot {
    pub const ZERO: Slot = Slot([0.0; 4]);

    pub fn new(x: f64, y: f64, z: f64) -> Slot {
        Slot([x, y, z, 0.0])
    }
}

impl From<Vector3<f64>> for Slot {
    #[inline]
    fn from(v: Vector3<f64>) -> Slot {
        Slot::new(v.x, v.y, v.z)
    }
}

/// Elements or nodes per rayon task. Below twice this a pass runs on the
/// calling thread, so small systems (the tests' oscillators) pay nothing.
pub const GRAIN: usize = 1024;

/// out[k·N..k·N+N] ← f(k, elems[k]) for every element k, in parallel.
pub fn fill<E: Sync, const N: usize>(
    out: &mut [Slot],
    elems: &[E],
    f: impl Fn(usize, &E) -> [Vector3<f64>; N] + Sync,
) {
    debug_assert_eq!(out.len(), N * elems.len());
    out.par_chunks_exact_mut(N)
        .zip(elems.par_iter())
        .enumerate()
        .with_min_len(GRAIN)
        .for_each(|(k, (o, e))| {
            for (o, v) in o.iter_mut().zip(f(k, e)) {
                *o = Slot::from(v);
            }
        });
}

/// Which slots each node sums, and with which sign.
#[derive(Debug, Clone, Default)]
pub struct Assembly {
    /// Node n sums `entries[start[n]..start[n + 1]]`.
    pub(super) start: Vec<usize>,
    /// slot << 1 | 1 when the slot is subtracted (the far end of a spring).
    pub(super) entries: Vec<u32>,
    slots: usize,
}

impl Assembly {
    /// `touches()` yields (node, slot, subtracted) for every contribution; the
    /// order in which a node's touches come is the order it sums them in.
    pub fn new<I>(nodes: usize, slots: usize, touches: impl Fn() -> I) -> Assembly
    where
        I: Iterator<Item = (usize, usize, bool)>,
    {
        assert!(2 * slots < u32::MAX as usize, "too many elements: {slots}");
        let mut start = vec![0usize; nodes + 1];
        for (n, _, _) in touches() {
            start[n + 1] += 1;
        }
        for n in 0..nodes {
            start[n + 1] += start[n];
        }
        let mut next = start.clone();
        let mut entries = vec![0u32; start[nodes]];
        for (n, s, minus) in touches() {
            // The SIMD sums read slots unchecked (simd.rs).
            assert!(s < slots, "slot {s} of {slots}");
            entries[next[n]] = (s as u32) << 1 | minus as u32;
            next[n] += 1;
        }
        assert!(
            next[..nodes] == start[1..],
            "touches() changed between calls"
        );
        Assembly {
            start,
            entries,
            slots,
        }
    }

    pub fn slots(&self) -> usize {
        self.slots
    }

    pub fn nodes(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// out[node] ← base(node) + Σ ± slots, 3 values per node, in parallel over nodes.
    pub fn gather(&self, slots: &[Slot], base: impl Fn(usize) -> Slot + Sync, out: &mut [f64]) {
        self.sum_into(slots, |n, _| base(n), out);
    }

    /// out[node] ← out[node] + Σ ± slots.
    pub fn gather_add(&self, slots: &[Slot], out: &mut [f64]) {
        self.sum_into(slots, |_, o| Slot::new(o[0], o[1], o[2]), out);
    }

    /// [`gather`](Self::gather) on the calling thread alone, for a caller
    /// that already runs in parallel (one block of [`super::spring_blocks`]).
    pub fn gather_serial(&self, slots: &[Slot], base: impl Fn(usize) -> Slot, out: &mut [f64]) {
        self.check(slots, out);
        self.sum_chunk(slots, 0, out, &|n, _| base(n));
    }

    fn sum_into(
        &self,
        slots: &[Slot],
        init: impl Fn(usize, &[f64]) -> Slot + Sync,
        out: &mut [f64],
    ) {
        self.check(slots, out);
        out.par_chunks_mut(3 * GRAIN)
            .enumerate()
            .for_each(|(chunk, o)| self.sum_chunk(slots, chunk * GRAIN, o, &init));
    }

    fn check(&self, slots: &[Slot], out: &[f64]) {
        assert_eq!(slots.len(), self.slots, "slot buffer of the wrong length");
        assert_eq!(out.len(), 3 * self.nodes(), "output of the wrong length");
    }

    /// The sums of nodes `first..` into `out`, 3 values per node.
    fn sum_chunk(
        &self,
        slots: &[Slot],
        first: usize,
        out: &mut [f64],
        init: &impl Fn(usize, &[f64]) -> Slot,
    ) {
        if !simd::sum_nodes(self, slots, first, out, init) {
            for (k, o) in out.chunks_exact_mut(3).enumerate() {
                let s = self.sum_node(slots, first + k, init(first + k, o));
                o.copy_from_slice(&s.0[..3]);
            }
        }
    }

    /// start + Σ ± slots of node n, one slot after another in the order of
    /// its entries ([`simd::sum_nodes`] adds in the same order).
    fn sum_node(&self, slots: &[Slot], n: usize, start: Slot) -> Slot {
        let mut sum = start.0;
        for &e in &self.entries[self.start[n]..self.start[n + 1]] {
            let s = &slots[(e >> 1) as usize].0;
            for c in 0..4 {
                if e & 1 == 0 {
                    sum[c] += s[c];
                } else {
                    sum[c] -= s[c];
                }
            }
        }
        Slot(sum)
    }
}

/// The slot buffer, reused from call to call: force evaluations take `&self`.
#[derive(Debug, Default)]
pub struct Scratch(Mutex<Vec<Slot>>);

impl Scratch {
    /// Run `f` on a buffer of `len` slots (contents unspecified). The buffer
    /// only grows, so calls of different lengths do not refill it.
    pub fn with<R>(&self, len: usize, f: impl FnOnce(&mut [Slot]) -> R) -> R {
        let mut buf = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if buf.len() < len {
            buf.resize(len, Slot::ZERO);
        }
        f(&mut buf[..len])
    }
}

impl Clone for Scratch {
    /// A clone starts with its own empty buffer.
    fn clone(&self) -> Self {
        Scratch::default()
    }
}
