//! The springs' part of the force, block by block of nodes, so that a
//! spring's force is summed by its nodes while it is still in cache.
//!
//! The nodes are cut into blocks of consecutive indices, [`BLOCK_NODES`] to
//! [`MOST_BLOCK_NODES`] of them (see [`block_nodes`]). A
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
use std::ops::Range;

/// The fewest nodes a block holds: about 6 000 springs and 190 KiB of
/// slots on a cloth, so that a block's slots, positions and sums stay in a
/// core's L2 cache, and a 100 × 100 cloth still makes 10 blocks for two
/// threads to share.
pub const BLOCK_NODES: usize = 1024;

/// The most: about 24 000 springs and 770 KiB of slots on a cloth, still
/// inside a core's 1 MiB L2 here.
pub const MOST_BLOCK_NODES: usize = 4096;

/// A block spans at least this many times the index reach of most springs
/// (their 90th percentile of |i − j|), so that few cross into the next
/// block: a crossing spring is computed by both. On a 412 × 412 cloth (10⁶
/// springs, bending springs reaching 824 nodes) blocks of 1 024 nodes
/// computed a third of the springs twice and the force took 4.3 ms on one
/// thread; blocks of 4 096, 3.4 ms.
const REACH_MULTIPLE: usize = 4;

/// The block size for `springs`: [`REACH_MULTIPLE`] times their reach, a
/// power of two within [`BLOCK_NODES`]..=[`MOST_BLOCK_NODES`].
fn block_nodes(springs: &[Spring]) -> usize {
    let mut reach: Vec<usize> = springs.iter().map(|s| s.i.abs_diff(s.j)).collect();
    if reach.is_empty() {
        return BLOCK_NODES;
    }
    let k = reach.len() * 9 / 10;
    let (_, most, _) = reach.select_nth_unstable(k);
    (REACH_MULTIPLE * *most)
        .next_power_of_two()
        .clamp(BLOCK_NODES, MOST_BLOCK_NODES)
}

#[derive(Debug, Clone, Default)]
pub struct SpringBlocks {
    blocks: Vec<Block>,
    /// Nodes per block (the last may hold fewer).
    block_nodes: usize,
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
        SpringBlocks::with_block_nodes(springs, nodes, block_nodes(springs))
    }

    /// Blocks of `block_nodes` nodes.
    fn with_block_nodes(springs: &[Spring], nodes: usize, block_nodes: usize) -> SpringBlocks {
        let count = nodes.div_ceil(block_nodes);
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); count];
        for (k, s) in springs.iter().enumerate() {
            let (bi, bj) = (s.i / block_nodes, s.j / block_nodes);
            members[bi].push(k);
            if bj != bi {
                members[bj].push(k);
            }
        }
        let blocks = members
            .iter()
            .enumerate()
            .map(|(b, ks)| {
                let own = b * block_nodes..nodes.min((b + 1) * block_nodes);
                Block::new(springs, ks, own, nodes)
            })
            .collect();
        SpringBlocks {
            blocks,
            block_nodes,
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
        f.par_chunks_mut(3 * self.block_nodes.max(1))
            .zip(&self.blocks)
            .for_each(|(f, block)| block.forces(x, &base, f));
    }
}

impl Block {
    /// The springs `members` (ascending) of the block of nodes `own`, of
    /// `nodes` in all.
    fn new(springs: &[Spring], members: &[usize], own: Range<usize>, nodes: usize) -> Block {
        let (first, last) = (own.start, own.end);
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
    /// and on two, with the smallest and the largest blocks.
    #[test]
    fn blocks_sum_as_one_buffer_on_any_thread_count() {
        let nodes = 2 * MOST_BLOCK_NODES + 100;
        let (springs, x) = network(nodes);
        let expected = reference(&springs, &x, nodes);
        for size in [BLOCK_NODES, MOST_BLOCK_NODES] {
            let blocks = SpringBlocks::with_block_nodes(&springs, nodes, size);
            for threads in [1, 2] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let mut f = vec![f64::NAN; 3 * nodes];
                pool.install(|| blocks.forces(&x, |_| Slot::ZERO, &mut f));
                assert!(
                    f == expected,
                    "blocks of {size}, {threads} thread(s): not one buffer's"
                );
            }
        }
        let total: f64 = expected.iter().sum();
        let scale: f64 = expected.iter().map(|v| v.abs()).sum();
        assert!(
            scale > 0.0 && total.abs() < 1e-12 * scale,
            "Σf = {total} of {scale}"
        );
    }

    /// An n × n cloth's springs reach 2n nodes (bending springs two rows
    /// down): blocks of four times that, as a power of two within the bounds.
    #[test]
    fn blocks_span_four_times_the_springs_reach() {
        let cloth = |n: usize| -> Vec<Spring> {
            let spring = |i: usize, j: usize| Spring {
                i,
                j,
                k: 1.0,
                rest: 1.0,
                tension_only: false,
                eps: 0.0,
            };
            (0..n * (n - 2))
                .flat_map(|i| [spring(i, i + 1), spring(i, i + n), spring(i, i + 2 * n)])
                .collect()
        };
        assert_eq!(block_nodes(&cloth(100)), BLOCK_NODES); // 4 · 200 → 1 024
        assert_eq!(block_nodes(&cloth(200)), 2048); // 4 · 400 → 2 048
        assert_eq!(block_nodes(&cloth(600)), MOST_BLOCK_NODES); // 4 · 1 200, capped
        assert_eq!(block_nodes(&[]), BLOCK_NODES);
    }
}
