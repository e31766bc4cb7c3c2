//! The candidate pairs (the narrow phase's input): the elementary pairs
//! whose features' boxes overlap and that are near enough to matter, found
//! from the tree's primitive pairs and held from step to step like a
//! Verlet list. Each node has a reference box, its path over the next few
//! steps at the velocity it had when its pairs were found ([`LOOKAHEAD`]
//! steps, at most [`LOOKAHEAD_LAYERS`] layers); the pairs hold every pair
//! that can come within the layer while each node stays within its box
//! grown by the margin. A node that leaves it (impulses, a change of
//! course) has its pairs found again, node by node through the tree, or
//! all are found again when many nodes did. Each step measures the held
//! pairs again at its start.

use super::geometry::{Closest, Stencil};
use super::sweep::Sweep;
use super::{filter_map, Contacts, MARGIN, PARALLEL_ITEMS};
use rayon::prelude::*;

/// When more than one node in this many has left its reference box, the
/// candidates are found again from the whole tree rather than node by node.
const SEARCH_AGAIN: usize = 4;

/// A node's reference box covers its path over this many steps at the
/// velocity it has when its pairs are found, so that a steady motion keeps
/// the candidates for that long...
pub const LOOKAHEAD: f64 = 8.0;

/// ... but reaches at most this many layers ahead, so that the normals
/// the tree's hemisphere test saw turn by little while the pairs are held.
pub const LOOKAHEAD_LAYERS: f64 = 0.5;

/// The candidate pairs and the paths they hold for.
pub(super) struct Candidates {
    /// Each pair with its nearest points at the current step's start.
    pub pairs: Vec<(Stencil, Closest)>,
    /// Each node's reference box: the pairs hold while every node stays
    /// within its own, grown by [`MARGIN`] layers along every axis.
    pub reference: Sweep,
}

impl Contacts {
    /// The candidates for this step, moving by `dx`: those held from the
    /// last step, measured again and brought up to date, or found anew.
    pub(super) fn step_candidates(&mut self, dx: &[f64]) -> Candidates {
        match self.held.take() {
            Some(c) => {
                let c = self.measured(c);
                self.current(c, dx)
            }
            None => self.refreshed(dx),
        }
    }

    /// `c` with its nearest points measured at this step's start, in place.
    fn measured(&self, mut c: Candidates) -> Candidates {
        let x = &self.start;
        let measure = |(st, near): &mut (Stencil, Closest)| *near = st.closest(&st.at(x, x, 0.0));
        if c.pairs.len() < PARALLEL_ITEMS {
            c.pairs.iter_mut().for_each(measure);
        } else {
            c.pairs.par_iter_mut().with_min_len(1024).for_each(measure);
        }
        c
    }

    /// Each node's reference box for the motion `dx`: its path over up to
    /// [`LOOKAHEAD`] steps like this one, at most [`LOOKAHEAD_LAYERS`]
    /// layers long unless this step alone is longer.
    fn ahead(&self, dx: &[f64]) -> Sweep {
        let reach = LOOKAHEAD_LAYERS * self.repulsion.thickness;
        let mut far = dx.to_vec();
        for d in far.chunks_exact_mut(3) {
            let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let steps = (reach / length).clamp(1.0, LOOKAHEAD);
            d.iter_mut().for_each(|c| *c *= steps);
        }
        Sweep::new(&self.start, &far)
    }

    /// The tree refitted to the reference boxes of the motion `dx`, and
    /// every candidate found anew.
    pub(super) fn refreshed(&mut self, dx: &[f64]) -> Candidates {
        let reference = self.ahead(dx);
        let reach = self.reach();
        self.tree
            .refit(&self.surface, &self.start, dx, &reference, reach);
        Candidates {
            pairs: self.candidates(&reference),
            reference,
        }
    }

    /// `c` if every node's path moving by `dx` stays within its reference
    /// box grown by the margin; else `c` brought up to date for the nodes
    /// that left theirs, or, when many did, the candidates found anew.
    pub(super) fn current(&mut self, c: Candidates, dx: &[f64]) -> Candidates {
        let margin = MARGIN * self.repulsion.thickness;
        let now = Sweep::new(&self.start, dx);
        let drifted: Vec<bool> = (0..dx.len() / 3)
            .map(|n| !c.reference.holds(&now, n, margin))
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

    /// `c` with the pairs of the `drifted` nodes found again, their
    /// reference boxes made anew for the motion `dx`; the other nodes keep
    /// theirs. The primitives with a drifted node are looked up in the
    /// tree one by one.
    fn updated(&mut self, c: Candidates, dx: &[f64], drifted: &[bool]) -> Candidates {
        let mut reference = c.reference;
        let ahead = self.ahead(dx);
        for n in (0..drifted.len()).filter(|&n| drifted[n]) {
            reference.take(&ahead, n);
        }
        let reach = self.reach();
        self.tree
            .refit(&self.surface, &self.start, dx, &reference, reach);
        let moved = |p: usize| self.surface.vertices(p).iter().any(|&n| drifted[n]);
        let touched: Vec<usize> = (0..self.surface.len()).filter(|&p| moved(p)).collect();
        let found = filter_map(&touched, |&p| {
            let (lo, hi) = reference.feature_box_v3(self.surface.vertices(p), reach);
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
                        near.extend(self.kept(st, &reference));
                    }
                });
            }
            Some(near)
        });
        let kept: Vec<_> = c
            .pairs
            .into_iter()
            .filter(|(st, _)| !st.nodes.iter().any(|&n| drifted[n]))
            .collect();
        let pairs = merged(kept, in_order(found.concat()));
        Candidates { pairs, reference }
    }

    /// The elementary pairs of the tree's primitive pairs that
    /// [`Contacts::kept`] keeps for the reference boxes `reference`.
    fn candidates(&self, reference: &Sweep) -> Vec<(Stencil, Closest)> {
        let pairs = self.tree.pairs();
        let chunks: Vec<&[(usize, usize)]> = pairs.chunks(256).collect();
        let found = filter_map(&chunks, |chunk| {
            let mut near = Vec::new();
            for &(p, q) in *chunk {
                self.surface
                    .each_stencil(p, q, |st| near.extend(self.kept(st, reference)));
            }
            Some(near)
        });
        in_order(found.concat())
    }

    /// The pair `st` with its nearest points at the step's start if it can
    /// come within the layer while each node stays within its reference
    /// box grown by the margin m: the features' boxes grown by half the
    /// layer and m overlap, and their distance d at the start less what
    /// their nodes can move is within the layer. A node's start and every
    /// later position lie in its box grown by m, whose diagonal is at most
    /// its reference motion plus 2√3·m; for both features that is the
    /// pair's reference reach plus 4√3·m < 7m.
    #[inline]
    fn kept(&self, st: Stencil, reference: &Sweep) -> Option<(Stencil, Closest)> {
        let layer = self.repulsion.thickness;
        let slack = layer + 7.0 * MARGIN * layer;
        let (a, b) = st.features();
        if !reference.near(a, b, self.reach()) {
            return None;
        }
        let c = st.closest(&st.at(&self.start, &self.start, 0.0));
        (c.distance() - reference.reach(&st) <= slack).then_some((st, c))
    }
}

/// `pairs` in the order of their stencils (kind, then node numbers): the
/// order the impulses are applied in, which then depends on the state
/// alone and not on the tree's history or on which pairs were held, so a
/// restarted run is the same as one never stopped. Every list of
/// candidates holds every pair that can act; the others do nothing.
fn in_order(mut pairs: Vec<(Stencil, Closest)>) -> Vec<(Stencil, Closest)> {
    if pairs.len() < PARALLEL_ITEMS {
        pairs.sort_unstable_by_key(|(st, _)| *st);
    } else {
        pairs.par_sort_unstable_by_key(|(st, _)| *st);
    }
    pairs
}

/// Two lists in stencil order as one.
fn merged(a: Vec<(Stencil, Closest)>, b: Vec<(Stencil, Closest)>) -> Vec<(Stencil, Closest)> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut a, mut b) = (a.into_iter().peekable(), b.into_iter().peekable());
    while let (Some(x), Some(y)) = (a.peek(), b.peek()) {
        let next = if x.0 < y.0 { a.next() } else { b.next() };
        out.extend(next);
    }
    out.extend(a);
    out.extend(b);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::IMPACT_FRACTION;
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

    /// Whether the narrow phase must see the pair in the step moving by
    /// `dx`: it is closer than the layer at the start or at the end, or
    /// touches during the step (the cubic's test).
    fn matters(c: &Contacts, st: &Stencil, dx: &[f64]) -> bool {
        let layer = c.repulsion.thickness;
        let at = |s: f64| st.closest(&st.at(&c.start, dx, s)).distance();
        at(0.0) < layer
            || at(1.0) < layer
            || st.impact(&c.start, dx, IMPACT_FRACTION * layer).is_some()
    }

    /// The candidates held from step to step and brought up to date node
    /// by node miss no pair that can touch, and hold none twice (each would
    /// give its impulse twice): a 21 × 21 cloth pleated into layers 0.8 of
    /// the layer apart, each node moving by up to 0.1 layer a step along
    /// each axis, for eighteen steps (past its look-ahead); at the fourth a
    /// tenth of the nodes jump two layers up or down, and from the
    /// thirteenth all turn back. The reference is a search of its own at
    /// every step.
    #[test]
    fn held_candidates_hold_every_pair_that_can_touch() {
        let n = 21;
        let m = crate::rectangle::rectangle(0.2, 0.2, n, n, [0.0; 3]);
        let layer = Collision::default().thickness;
        let mut x = m.pleated(4, 0.8 * layer);
        let net = Network {
            mass: vec![1e-3; n * n],
            inv_mass: vec![1e3; n * n],
            triangles: m.triangles.clone(),
            canopy_nodes: n * n,
            ..Network::default()
        };
        let mut c = Contacts::new(&net, &Collision::default()).expect("a surface");
        let mut fresh = Contacts::new(&net, &Collision::default()).expect("a surface");
        let mut r = noise(3);
        let velocity: Vec<f64> = x.iter().map(|_| 0.1 * layer * r()).collect();
        let mut checked = 0;
        for step in 1..=18 {
            let mut dx = velocity.clone();
            if step >= 13 {
                dx.iter_mut().for_each(|d| *d = -*d);
            }
            if step == 4 {
                for k in (0..n * n).step_by(10) {
                    dx[3 * k + 2] += 2.0 * layer * r().signum();
                }
            }
            c.begin_step(&x);
            let held = c.step_candidates(&dx);
            let set: HashSet<Stencil> = held.pairs.iter().map(|(st, _)| *st).collect();
            assert_eq!(set.len(), held.pairs.len(), "a pair is held twice");
            for (st, near) in &held.pairs {
                let now = st.closest(&st.at(&x, &x, 0.0)).distance();
                assert_eq!(near.distance(), now, "{st:?} measured at another start");
            }
            fresh.begin_step(&x);
            fresh.forget_candidates();
            let again = fresh.refreshed(&dx);
            for (st, _) in again
                .pairs
                .iter()
                .filter(|(st, _)| matters(&fresh, st, &dx))
            {
                assert!(set.contains(st), "step {step}: {st:?} missed");
                checked += 1;
            }
            c.held = Some(held);
            x.iter_mut().zip(&dx).for_each(|(a, d)| *a += d);
        }
        assert!(checked > 10_000, "{checked} pairs checked");
    }
}
