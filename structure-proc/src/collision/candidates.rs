//! The candidate pairs of a step (the narrow phase's input): the
//! elementary pairs whose features' swept boxes overlap and that are near
//! enough to matter, found from the tree's primitive pairs, and kept up to
//! date while impulses change the motion: a node that leaves the motion
//! they were found for by more than the margin has its pairs found again,
//! node by node through the tree, or all of them when many nodes did.

use super::geometry::{Closest, Stencil};
use super::sweep::Sweep;
use super::{filter_map, Contacts, IMPACT_FRACTION, MARGIN};

/// When more than one node in this many has left the candidates' motion
/// by more than the margin, they are found again from the whole tree
/// rather than node by node.
const SEARCH_AGAIN: usize = 4;

/// The candidate pairs of a step and the motion they were found for: they
/// hold every pair that can come within the layer while no node's motion
/// leaves that one by more than [`MARGIN`] layers.
pub(super) struct Candidates {
    /// Each pair with its nearest points at the step's start.
    pub pairs: Vec<(Stencil, Closest)>,
    /// The motion over the step each node's pairs were found for.
    pub dx: Vec<f64>,
}

impl Contacts {
    /// The tree refitted to the motion `dx`, and its candidates.
    pub(super) fn refreshed(&mut self, dx: &[f64]) -> Candidates {
        let sweep = Sweep::new(&self.start, dx);
        let reach = self.reach();
        self.tree
            .refit(&self.surface, &self.start, dx, &sweep, reach);
        Candidates {
            pairs: self.candidates(dx, &sweep),
            dx: dx.to_vec(),
        }
    }

    /// `c` if no node's motion has left `c`'s by more than the margin since
    /// it was found; else `c` brought up to date for the nodes that left
    /// it, or, when many did, the candidates found again.
    pub(super) fn current(&mut self, c: Candidates, dx: &[f64]) -> Candidates {
        let margin = MARGIN * self.repulsion.thickness;
        let drifted: Vec<bool> = dx
            .chunks_exact(3)
            .zip(c.dx.chunks_exact(3))
            .map(|(a, b)| (0..3).any(|i| (a[i] - b[i]).abs() > margin))
            .collect();
        let count = drifted.iter().filter(|&&d| d).count();
        if count == 0 {
            c
        } else if count * SEARCH_AGAIN > drifted.len() {
            self.refreshed(dx)
        } else {
            self.updated(c, dx, &drifted)
        }
    }

    /// `c` with the pairs of the `drifted` nodes found again for their
    /// motion in `dx`: the others keep the motion `c` was found for, so
    /// every pair stays valid while each node stays within the margin of
    /// its own reference. The primitives with a drifted node are looked up
    /// in the tree one by one.
    fn updated(&mut self, c: Candidates, dx: &[f64], drifted: &[bool]) -> Candidates {
        let mut reference = c.dx;
        for n in (0..drifted.len()).filter(|&n| drifted[n]) {
            reference[3 * n..3 * n + 3].copy_from_slice(&dx[3 * n..3 * n + 3]);
        }
        let sweep = Sweep::new(&self.start, &reference);
        let reach = self.reach();
        self.tree
            .refit(&self.surface, &self.start, &reference, &sweep, reach);
        let moved = |p: usize| self.surface.vertices(p).iter().any(|&n| drifted[n]);
        let touched: Vec<usize> = (0..self.surface.len()).filter(|&p| moved(p)).collect();
        let found = filter_map(&touched, |&p| {
            let (lo, hi) = sweep.feature_box_v3(self.surface.vertices(p), reach);
            let mut others = Vec::new();
            self.tree.overlapping(&lo, &hi, &mut others);
            let mut near = Vec::new();
            for q in others {
                // A pair of two touched primitives is visited from its first.
                if q == p
                    || (q < p && moved(q))
                    || (self.surface.is_body(p) && self.surface.is_body(q))
                {
                    continue;
                }
                // In the order the whole search gives them, (smaller, larger).
                let (a, b) = (p.min(q), p.max(q));
                self.surface.each_stencil(a, b, |st| {
                    if st.nodes.iter().any(|&n| drifted[n]) {
                        near.extend(self.kept(st, &reference, &sweep));
                    }
                });
            }
            Some(near)
        });
        let mut pairs: Vec<_> = c
            .pairs
            .into_iter()
            .filter(|(st, _)| !st.nodes.iter().any(|&n| drifted[n]))
            .collect();
        pairs.extend(found.into_iter().flatten());
        Candidates {
            pairs,
            dx: reference,
        }
    }

    /// The elementary pairs that can matter to the step, with their
    /// nearest points at its start: those of the tree's primitive pairs
    /// that [`Contacts::kept`] keeps.
    fn candidates(&self, dx: &[f64], sweep: &Sweep) -> Vec<(Stencil, Closest)> {
        let pairs = self.tree.pairs();
        let chunks: Vec<&[(usize, usize)]> = pairs.chunks(256).collect();
        let found = filter_map(&chunks, |chunk| {
            let mut near = Vec::new();
            for &(p, q) in *chunk {
                self.surface
                    .each_stencil(p, q, |st| near.extend(self.kept(st, dx, sweep)));
            }
            Some(near)
        });
        found.concat()
    }

    /// The pair `st` with its nearest points at the step's start if it can
    /// matter to the step moving by `dx` (whose paths are `sweep`): its
    /// features' swept boxes, grown by [`Contacts::reach`], overlap, and it
    /// is within the layer at the start or close enough to touch while its
    /// nodes move by `dx` and up to the margin more.
    #[inline]
    fn kept(&self, st: Stencil, dx: &[f64], sweep: &Sweep) -> Option<(Stencil, Closest)> {
        let layer = self.repulsion.thickness;
        // A node moving by the margin in each axis moves by at most √3
        // margins: four margins cover both features.
        let slack = IMPACT_FRACTION * layer + 4.0 * MARGIN * layer;
        let (a, b) = st.features();
        if !sweep.near(a, b, self.reach()) {
            return None;
        }
        let c = st.closest(&st.at(&self.start, dx, 0.0));
        let d = c.distance();
        (d < layer || d - sweep.reach(&st) <= slack).then_some((st, c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::Network;
    use std::collections::HashSet;
    use structure_section::Collision;

    /// A fixed pseudo-random sequence in [−1, 1).
    fn noise(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// Whether the pair can come within the layer over the step moving by
    /// `dx`: closer than the layer at the start, or no farther than the
    /// impact tolerance plus what its nodes move (what the narrow phase
    /// must see).
    fn matters(c: &Contacts, st: &Stencil, dx: &[f64]) -> bool {
        let layer = c.repulsion.thickness;
        let d = st.closest(&st.at(&c.start, dx, 0.0)).distance();
        d < layer || d - Sweep::new(&c.start, dx).reach(st) <= IMPACT_FRACTION * layer
    }

    /// The candidates brought up to date node by node miss no pair that
    /// can touch, and hold none twice (each would give its impulse twice):
    /// a 21 × 21 cloth pleated into layers 0.8 of the layer apart, a tenth
    /// of its nodes pushed three margins off the motion the candidates
    /// were found for.
    #[test]
    fn updated_candidates_hold_every_pair_that_can_touch() {
        let (n, h) = (21, 0.01);
        let m = crate::rectangle::rectangle(1.0, 1.0, n, n, [0.0; 3]);
        let layer = Collision::default().thickness;
        let mut x = m.points.clone();
        for k in 0..n * n {
            let u = k % n;
            let (pleat, s) = (u / 4, (u % 4) as f64 * h);
            x[3 * k] = if pleat % 2 == 0 { s } else { 4.0 * h - s };
            x[3 * k + 1] = (k / n) as f64 * h;
            x[3 * k + 2] = pleat as f64 * 0.8 * layer;
        }
        let net = Network {
            mass: vec![1e-3; n * n],
            inv_mass: vec![1e3; n * n],
            triangles: m.triangles.clone(),
            canopy_nodes: n * n,
            ..Network::default()
        };
        let mut c = Contacts::new(&net, &Collision::default()).expect("a surface");
        c.begin_step(&x);
        let mut r = noise(3);
        let dx0: Vec<f64> = x.iter().map(|_| 0.05 * layer * r()).collect();
        let found = c.refreshed(&dx0);
        let mut dx1 = dx0.clone();
        for k in (0..n * n).step_by(10) {
            for i in 0..3 {
                dx1[3 * k + i] += 3.0 * MARGIN * layer * r().signum();
            }
        }
        let updated = c.current(found, &dx1);
        let held: HashSet<Stencil> = updated.pairs.iter().map(|(st, _)| *st).collect();
        assert_eq!(held.len(), updated.pairs.len(), "a pair is held twice");
        let again = c.refreshed(&dx1);
        let needed: Vec<&Stencil> = again
            .pairs
            .iter()
            .map(|(st, _)| st)
            .filter(|st| matters(&c, st, &dx1))
            .collect();
        assert!(needed.len() > 1000, "{} pairs matter", needed.len());
        for st in needed {
            assert!(held.contains(st), "{st:?} missed");
        }
    }
}
