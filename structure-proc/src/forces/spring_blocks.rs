//! The springs' part of the force, block by block of nodes, so that a
//! spring's force is summed by its nodes while it is still in cache.
//!
//! The nodes are cut into blocks of [`BLOCK_NODES`] consecutive indices. A
//! block holds every spring with an end in it (a spring across two blocks is
//! in both, and computed by both) as two [`SpringBatch`]es, Hookean springs
//! and strings, and an [`Assembly`] of its own nodes over their slots. Blocks run in parallel; each
//! writes its springs' forces into a buffer of the thread's and sums its
//! nodes from there at once. One slot buffer for every spring, written by one
//! pass and read by the next, would make each step write and read 32 bytes a
//! spring through main memory once the network outgrows the caches (about 10⁵
//! springs here), and its time per spring grow with the size; the blocks'
//! buffers stay in each core's cache.
//!
//! A node's block lists its springs in the order of their index, as the
//! network's assembly does, and a spring's force is the same bits whichever
//! block computes it: the force does not depend on the blocking or the
//! number of threads, and it is the bits of the one-buffer assembly.

use super::assembly::{Assembly, Slot};
use super::spring_batch::SpringBatch;
use crate::network::Spring;
use rayon::prelude::*;
use std::cell::RefCell;

/// Nodes per block: about 6 000 springs and 190 KiB of slots on a cloth, so
/// that a block's slots, positions and sums stay in a core's L2 cache.
pub const BLOCK_NODES: usize = 1024;

#[derive(Debug, Clone, Default)]
pub struct SpringBlocks {
    blocks: Vec<Block>,
    springs: usize,
    nodes: usize,
}

#[derive(Debug, Clone)]
struct Block {
    /// The block's nodes are `first..first + assembly.nodes()`.
    first: usize,
    /// Slots `0..springs.len()`, then the strings'.
    springs: SpringBatch,
    strings: SpringBatch,
    assembly: Assembly,
}

thread_local! {
    /// Each thread's slot buffer, reused from block to block and step to step.
    static SLOTS: RefCell<Vec<Slot>> = const { RefCell::new(Vec::new()) };
}

impl SpringBlocks {
    pub fn new(springs: &[Spring], nodes: usize) -> SpringBlocks {
        let count = nodes.div_ceil(BLOCK_NODES);
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); count];
        for (k, s) in springs.iter().enumerate() {
            let (bi, bj) = (s.i / BLOCK_NODES, s.j / BLOCK_NODES);
            members[bi].push(k);
            if bj != bi {
                members[bj].push(k);
            }
        }
        let blocks = members
            .iter()
            .enumerate()
            .map(|(b, ks)| Block::new(springs, ks, b * BLOCK_NODES, nodes))
            .collect();
        SpringBlocks {
            blocks,
            springs: springs.len(),
            nodes,
        }
    }

    /// How many springs the blocks were built from.
    pub fn springs(&self) -> usize {
        self.springs
    }

    /// f[n] ← base(n) + Σ the spring forces on node n at positions `x`,
    /// 3 values per node, in parallel over blocks.
    pub fn forces(&self, x: &[f64], base: impl Fn(usize) -> Slot + Sync, f: &mut [f64]) {
        assert_eq!(f.len(), 3 * self.nodes, "output of the wrong length");
        f.par_chunks_mut(3 * BLOCK_NODES)
            .zip(&self.blocks)
            .for_each(|(f, block)| block.forces(x, &base, f));
    }
}

impl Block {
    /// The springs `members` (ascending) of the block whose nodes start at `first`.
    fn new(springs: &[Spring], members: &[usize], first: usize, nodes: usize) -> Block {
        let last = (first + BLOCK_NODES).min(nodes);
        let (strings, hooke): (Vec<usize>, Vec<usize>) =
            members.iter().partition(|&&k| springs[k].tension_only);
        let batch = |ks: &[usize], kind| {
            let own: Vec<Spring> = ks.iter().map(|&k| springs[k]).collect();
            SpringBatch::new(&own, kind, nodes)
        };
        // Each member's slot, in the order of the members: the nodes sum them
        // in the order of the spring index, as the network's assembly does.
        let slot: Vec<(usize, usize)> = {
            let (mut h, mut t) = (0, hooke.len());
            members
                .iter()
                .map(|&k| {
                    let at = if springs[k].tension_only {
                        &mut t
                    } else {
                        &mut h
                    };
                    *at += 1;
                    (k, *at - 1)
                })
                .collect()
        };
        let inside = move |n: usize| (first..last).contains(&n).then(|| n - first);
        let assembly = Assembly::new(last - first, members.len(), || {
            slot.iter().flat_map(move |&(k, t)| {
                let s = &springs[k];
                let i = inside(s.i).map(|n| (n, t, false));
                let j = inside(s.j).map(|n| (n, t, true));
                i.into_iter().chain(j)
            })
        });
        Block {
            first,
            springs: batch(&hooke, false),
            strings: batch(&strings, true),
            assembly,
        }
    }

    fn forces(&self, x: &[f64], base: &(impl Fn(usize) -> Slot + Sync), f: &mut [f64]) {
        SLOTS.with_borrow_mut(|buffer| {
            let len = self.assembly.slots();
            if buffer.len() < len {
                buffer.resize(len, Slot::ZERO);
            }
            let slots = &mut buffer[..len];
            let (springs, strings) = slots.split_at_mut(self.springs.len());
            self.springs.forces(x, springs);
            self.strings.forces(x, strings);
            self.assembly
                .gather_serial(slots, |n| base(self.first + n), f);
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Springs and strings between nodes far apart (most cross blocks) and
    /// near (within one), over three blocks and a part.
    fn network(nodes: usize) -> (Vec<Spring>, Vec<f64>) {
        let x: Vec<f64> = (0..3 * nodes)
            .map(|k| ((k * 7919) % 1013) as f64 * 1e-3)
            .collect();
        let springs = (0..4 * nodes)
            .map(|k| {
                let i = (k * 37) % nodes;
                let j = if k % 2 == 0 {
                    (i + 1) % nodes
                } else {
                    (k * 101 + 7) % nodes
                };
                Spring {
                    i,
                    j,
                    k: 50.0 + (k % 13) as f64,
                    rest: 0.2 + (k % 7) as f64 * 0.05,
                    tension_only: k % 5 == 0,
                    eps: 1e-3,
                }
            })
            .collect();
        (springs, x)
    }

    /// Each node's sum of ± Spring::force over its springs in the order of
    /// their index, on one buffer: the assembly the blocks replace.
    fn reference(springs: &[Spring], x: &[f64], nodes: usize) -> Vec<f64> {
        let mut f = vec![0.0; 3 * nodes];
        for s in springs {
            let fs = s.force(x);
            for c in 0..3 {
                f[3 * s.i + c] += fs[c];
                f[3 * s.j + c] -= fs[c];
            }
        }
        f
    }

    /// The blocks give the one-buffer sums bit for bit (Newton's third law
    /// holds pair by pair, so the total is zero to round-off), on one thread
    /// and on two.
    #[test]
    fn blocks_sum_as_one_buffer_on_any_thread_count() {
        let nodes = 3 * BLOCK_NODES + 100;
        let (springs, x) = network(nodes);
        let blocks = SpringBlocks::new(&springs, nodes);
        let expected = reference(&springs, &x, nodes);
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut f = vec![f64::NAN; 3 * nodes];
            pool.install(|| blocks.forces(&x, |_| Slot::ZERO, &mut f));
            assert!(f == expected, "{threads} thread(s) differ from one buffer");
        }
        let total: f64 = expected.iter().sum();
        let scale: f64 = expected.iter().map(|v| v.abs()).sum();
        assert!(
            scale > 0.0 && total.abs() < 1e-12 * scale,
            "Σf = {total} of {scale}"
        );
    }
}
