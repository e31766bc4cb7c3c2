//! Parallel, deterministic assembly of element contributions into node sums.
//!
//! Every element (spring, triangle edge, damper, pressure triangle) writes its
//! contribution into a slot of its own, in parallel with rayon; then every node
//! sums the slots that touch it, in parallel over nodes and in a fixed order.
//! No two threads write the same memory, no locks or atomics are needed, and
//! the result is bit-for-bit the same on any number of threads.

use nalgebra::Vector3;
use rayon::prelude::*;
use std::sync::Mutex;

/// One element's contribution to a node [N, or N/m·m for Jacobian products].
pub type Slot = Vector3<f64>;

/// Elements or nodes per rayon task. Below twice this a pass runs on the
/// calling thread, so small systems (the tests' oscillators) pay nothing.
pub const GRAIN: usize = 1024;

/// out[k·N..k·N+N] ← f(k, elems[k]) for every element k, in parallel.
pub fn fill<E: Sync, const N: usize>(
    out: &mut [Slot],
    elems: &[E],
    f: impl Fn(usize, &E) -> [Slot; N] + Sync,
) {
    debug_assert_eq!(out.len(), N * elems.len());
    out.par_chunks_exact_mut(N)
        .zip(elems.par_iter())
        .enumerate()
        .with_min_len(GRAIN)
        .for_each(|(k, (o, e))| o.copy_from_slice(&f(k, e)));
}

/// Which slots each node sums, and with which sign.
#[derive(Debug, Clone, Default)]
pub struct Assembly {
    /// Node n sums `entries[start[n]..start[n + 1]]`.
    start: Vec<usize>,
    /// slot << 1 | 1 when the slot is subtracted (the far end of a spring).
    entries: Vec<u32>,
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
            entries[next[n]] = (s as u32) << 1 | minus as u32;
            next[n] += 1;
        }
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

    fn sum_into(
        &self,
        slots: &[Slot],
        init: impl Fn(usize, &[f64]) -> Slot + Sync,
        out: &mut [f64],
    ) {
        debug_assert_eq!(slots.len(), self.slots);
        out.par_chunks_exact_mut(3)
            .enumerate()
            .with_min_len(GRAIN)
            .for_each(|(n, o)| {
                let mut sum = init(n, o);
                for &e in &self.entries[self.start[n]..self.start[n + 1]] {
                    let s = &slots[(e >> 1) as usize];
                    if e & 1 == 0 {
                        sum += s;
                    } else {
                        sum -= s;
                    }
                }
                o.copy_from_slice(sum.as_slice());
            });
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
            buf.resize(len, Slot::zeros());
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
