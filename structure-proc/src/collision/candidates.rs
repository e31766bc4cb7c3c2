//! The candidate pairs (the narrow phase's input): the elementary pairs
//! whose features' boxes overlap and that are near enough to matter, found
//! from the tree's primitive pairs and held from step to step like a
//! Verlet list. Each node has a reference box, its path over the next few
//! steps at the velocity it had when its pairs were found ([`LOOKAHEAD`]
//! steps, at most [`LOOKAHEAD_LAYERS`] layers); the pairs hold every pair
//! that can come within the layer while each node stays within its box
//! grown by the margin. A node that leaves it (impulses, a change of
//! course) has its pairs found again, node by node through the tree, or
//! all are found again when many nodes did.
//!
//! A held pair keeps a lower bound on its distance, not its nearest
//! points: each step lowers it by how far its nodes moved relative to each
//! other since the last, and only the pairs it leaves within reach of the
//! layer are measured again ([`Contacts::measure`]). Most held pairs of a
//! crumpled cloth are layers apart and moving together; they cost a few
//! subtractions a step.

use super::culled::{culled, Culled};
use super::geometry::{Closest, Kind, Stencil};
use super::sweep::Sweep;
use super::tree::NO_REGION;
use super::{filter_map, Contacts, MARGIN, PARALLEL_ITEMS};
use rayon::prelude::*;

/// When more than one node in this many has left its reference box, the
/// candidates are found again from the whole tree rather than node by node.
const SEARCH_AGAIN: usize = 4;

/// A node's reference box covers its path over this many steps at the
/// velocity it has when its pairs are found, so that a steady motion keeps
/// the candidates for that long...
pub const LOOKAHEAD: f64 = 8.0;

/// ... but reaches at most this many layers ahead, so that the boxes,
/// and the pairs they hold, stay few, and the triangles of regions the
/// tree skipped as smooth seldom turn by its margin while they are held
/// (which would have the candidates found anew).
pub const LOOKAHEAD_LAYERS: f64 = 2.0;

/// A held pair's bound is lowered by this fraction of the layer at every
/// step beyond its nodes' motion: more than the round-off of a distance
/// between features hundreds of metres from the origin (10⁻¹³ m) for a
/// layer of a millimetre.
pub(super) const ROUNDING: f64 = 1e-9;

/// The held pairs are measured in this many chunks, each on one thread
/// (rayon's pool shares them out).
const MEASURED_CHUNKS: usize = 64;

/// A held candidate pair: its stencil, with node numbers in 32 bits, and
/// a lower bound on its features' distance at the step's start [m]. Every
/// step streams each held pair a few times, so its size (32 bytes, a
/// [`Stencil`] with its nearest points took 96) is much of what a held
/// step costs.
#[derive(Debug, Clone, Copy)]
pub(super) struct Pair {
    nodes: [u32; 4],
    kind: Kind,
    /// At most the features' distance at the step's start; the distance
    /// itself once measured in the step.
    pub distance: f64,
}

impl Pair {
    /// The pair `st` at `distance` (the nodes are numbered below 2³², as
    /// [`Contacts::with_bodies`] checks).
    pub(super) fn new(st: &Stencil, distance: f64) -> Pair {
        Pair {
            nodes: st.nodes.map(|n| n as u32),
            kind: st.kind,
            distance,
        }
    }

    #[inline]
    pub fn stencil(&self) -> Stencil {
        let [a, b, c, d] = self.nodes;
        Stencil {
            kind: self.kind,
            nodes: [a as usize, b as usize, c as usize, d as usize],
        }
    }

    /// The order of the stencils' (kind, then node numbers).
    pub(super) fn key(&self) -> (Kind, [u32; 4]) {
        (self.kind, self.nodes)
    }
}

/// The candidate pairs and the paths they hold for.
pub(super) struct Candidates {
    /// Each pair with a lower bound on its distance at `at`.
    pub pairs: Vec<Pair>,
    /// The positions the distances are bounded at: the start of the step
    /// they were last brought to.
    at: Vec<f64>,
    /// Each node's reference box: the pairs hold while every node stays
    /// within its own, grown by [`MARGIN`] layers along every axis...
    pub reference: Sweep,
    /// ... and every triangle of the regions the tree skipped as smooth
    /// has turned by less than its allowance since the search, so that
    /// its region still faces its hemisphere with the tree's margin
    /// (`culled.rs`): a test of the region anew would skip it too.
    culled: Vec<Culled>,
    /// Each primitive's region skipped as smooth ([`NO_REGION`] if none):
    /// pairs found again node by node skip those within one region, as
    /// the search did.
    region: Vec<usize>,
    /// The pairs found within the layer in this step with their nearest
    /// points, in order, in [`MEASURED_CHUNKS`] lists that measure them in
    /// parallel: kept from step to step, so that measuring allocates
    /// nothing, and the impulses read them one after the other.
    near: Vec<Vec<(Stencil, Closest)>>,
}

impl Contacts {
    /// The candidates for this step, moving by `dx`: those held from the
    /// last step with their distances bounded anew and brought up to date,
    /// or found anew.
    pub(super) fn step_candidates(&mut self, dx: &[f64]) -> Candidates {
        match self.held.take() {
            Some(c) if c.at.len() == self.start.len() => {
                let c = self.brought_up(c);
                self.current(c, dx)
            }
            _ => self.refreshed(dx),
        }
    }

    /// `c` with its distances bounded at this step's start: each lowered
    /// by the largest motion of a node of one feature relative to a node
    /// of the other since `c.at` (the features' points are weighted means
    /// of their nodes, so no two of them came closer by more), and by
    /// [`ROUNDING`] of the layer, so that round-off never leaves a bound
    /// above the distance a run restarted here would measure.
    fn brought_up(&self, mut c: Candidates) -> Candidates {
        let moved: Vec<f64> = self.start.iter().zip(&c.at).map(|(a, b)| a - b).collect();
        let rounding = ROUNDING * self.repulsion.thickness;
        let lower = |p: &mut Pair| p.distance -= p.stencil().approach(&moved) + rounding;
        for_each_mut(&mut c.pairs, lower);
        c.at.copy_from_slice(&self.start);
        c
    }

    /// The pairs of `c` that may act in the step moving by `dx` (their
    /// bound within the layer and their relative motion) measured at its
    /// start, in place; those closer than the layer, with their nearest
    /// points, listed in `c.near` (read by [`Contacts::within`]).
    pub(super) fn measure(&self, c: &mut Candidates, dx: &[f64]) {
        let layer = self.repulsion.thickness;
        let x = &self.start;
        let job = |(pairs, near): (&mut [Pair], &mut Vec<(Stencil, Closest)>)| {
            near.clear();
            for p in pairs {
                let st = p.stencil();
                if p.distance - st.approach(dx) < layer {
                    let c = st.closest(&st.at(x, x, 0.0));
                    p.distance = c.distance();
                    if p.distance < layer {
                        near.push((st, c));
                    }
                }
            }
        };
        let size = c.pairs.len().div_ceil(MEASURED_CHUNKS).max(1);
        c.near.resize_with(c.pairs.len().div_ceil(size), Vec::new);
        if c.pairs.len() < PARALLEL_ITEMS {
            let near = c.near.iter_mut();
            c.pairs.chunks_mut(size).zip(near).for_each(job);
        } else {
            let near = c.near.par_iter_mut();
            c.pairs.par_chunks_mut(size).zip(near).for_each(job);
        }
    }

    /// The pairs of `c` closer than the layer with their nearest points,
    /// in order, once [`Contacts::measure`]d.
    pub(super) fn within(c: &Candidates) -> impl Iterator<Item = &(Stencil, Closest)> {
        c.near.iter().flatten()
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
        let region = self.tree.regions(self.surface.len());
        Candidates {
            pairs: self.candidates(&reference),
            at: self.start.clone(),
            reference,
            culled: culled(&self.tree, &self.surface, &region, &self.start),
            region,
            near: Vec::new(),
        }
    }

    /// `c` if every node's path moving by `dx` stays within its reference
    /// box grown by the margin and no culled triangle turned; else `c`
    /// brought up to date for the nodes that left their boxes, or, when
    /// many did or a culled triangle turned, the candidates found anew.
    pub(super) fn current(&mut self, c: Candidates, dx: &[f64]) -> Candidates {
        let margin = MARGIN * self.repulsion.thickness;
        let now = Sweep::new(&self.start, dx);
        let drifted: Vec<bool> = (0..dx.len() / 3)
            .map(|n| !c.reference.holds(&now, n, margin))
            .collect();
        let count = drifted.iter().filter(|&&d| d).count();
        if count * SEARCH_AGAIN > drifted.len() || self.turned(&c, dx) {
            self.refreshed(dx)
        } else if count == 0 {
            c
        } else {
            self.updated(c, dx, &drifted)
        }
    }

    /// Whether a culled triangle of `c` may have turned by more than its
    /// allowance since the search, at the start or the end of the step
    /// moving by `dx`.
    fn turned(&self, c: &Candidates, dx: &[f64]) -> bool {
        let turns = |t: &Culled| t.may_have_turned(&self.start, dx);
        if c.culled.len() < PARALLEL_ITEMS {
            c.culled.iter().any(turns)
        } else {
            c.culled.par_iter().with_min_len(PARALLEL_ITEMS).any(turns)
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
                let smooth = c.region[p] != NO_REGION && c.region[p] == c.region[q];
                // A pair of two touched primitives is visited from its first.
                if q == p
                    || (q < p && moved(q))
                    || (self.surface.is_body(p) && self.surface.is_body(q))
                    || smooth
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
            .filter(|p| !p.nodes.iter().any(|&n| drifted[n as usize]))
            .collect();
        let pairs = merged(kept, in_order(found.concat()));
        Candidates {
            pairs,
            at: c.at,
            reference,
            culled: c.culled,
            region: c.region,
            near: c.near,
        }
    }

    /// The elementary pairs of the tree's primitive pairs that
    /// [`Contacts::kept`] keeps for the reference boxes `reference`.
    fn candidates(&self, reference: &Sweep) -> Vec<Pair> {
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

    /// The pair `st` with its distance at the step's start if it can
    /// come within the layer while each node stays within its reference
    /// box grown by the margin m: the features' boxes grown by half the
    /// layer and m overlap, and their distance d at the start less what
    /// their nodes can move is within the layer. A node's start and every
    /// later position lie in its box grown by m, whose diagonal is at most
    /// its reference motion plus 2√3·m; for both features that is the
    /// pair's reference reach plus 4√3·m < 7m.
    #[inline]
    fn kept(&self, st: Stencil, reference: &Sweep) -> Option<Pair> {
        let layer = self.repulsion.thickness;
        let slack = layer + 7.0 * MARGIN * layer;
        let (a, b) = st.features();
        if !reference.near(a, b, self.reach()) {
            return None;
        }
        let d = st.closest(&st.at(&self.start, &self.start, 0.0)).distance();
        (d - reference.reach(&st) <= slack).then(|| Pair::new(&st, d))
    }
}

/// `pairs` in the order of their stencils (kind, then node numbers): the
/// order the impulses are applied in, which then depends on the state
/// alone and not on the tree's history or on which pairs were held, so a
/// restarted run is the same as one never stopped. Every list of
/// candidates holds every pair that can act; the others do nothing.
fn in_order(mut pairs: Vec<Pair>) -> Vec<Pair> {
    if pairs.len() < PARALLEL_ITEMS {
        pairs.sort_unstable_by_key(Pair::key);
    } else {
        pairs.par_sort_unstable_by_key(Pair::key);
    }
    pairs
}

/// `f` on each of `items`: on rayon's pool when there are many.
fn for_each_mut<T: Send>(items: &mut [T], f: impl Fn(&mut T) + Sync + Send) {
    if items.len() < PARALLEL_ITEMS {
        items.iter_mut().for_each(f);
    } else {
        items.par_iter_mut().with_min_len(1024).for_each(f);
    }
}

/// Two lists in stencil order as one.
fn merged(a: Vec<Pair>, b: Vec<Pair>) -> Vec<Pair> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut a, mut b) = (a.into_iter().peekable(), b.into_iter().peekable());
    while let (Some(x), Some(y)) = (a.peek(), b.peek()) {
        let next = if x.key() < y.key() {
            a.next()
        } else {
            b.next()
        };
        out.extend(next);
    }
    out.extend(a);
    out.extend(b);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::{noise, IMPACT_FRACTION};
    use crate::network::Network;
    use std::collections::HashSet;
    use structure_section::Collision;

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
    /// every step. Every held distance is at most the true one, and the
    /// pairs measured for the proximity impulses are exactly those within
    /// the layer, at their true distance.
    #[test]
    fn held_candidates_hold_every_pair_that_can_touch() {
        let n = 21;
        let m = crate::rectangle::rectangle(0.2, 0.2, n, n, [0.0; 3]);
        let layer = Collision::default().thickness;
        let x = m.pleated(4, 0.8 * layer);
        let mut r = noise(3);
        let velocity: Vec<f64> = x.iter().map(|_| 0.1 * layer * r()).collect();
        let motions = (1..=18).map(|step| {
            let mut dx = velocity.clone();
            if step >= 13 {
                dx.iter_mut().for_each(|d| *d = -*d);
            }
            if step == 4 {
                for k in (0..n * n).step_by(10) {
                    dx[3 * k + 2] += 2.0 * layer * r().signum();
                }
            }
            dx
        });
        let (checked, lowered) = follow(&m.triangles, x, motions);
        assert!(checked > 10_000, "{checked} pairs checked");
        assert!(lowered > 10_000, "{lowered} bounds lowered");
    }

    /// A flat cloth's self-pairs are skipped as smooth; when it is then
    /// pleated by motions that keep every node within its reference box,
    /// its triangles turn out of their hemisphere and the held candidates
    /// must hold the pairs a fresh search then tests: a 21 × 21 cloth of
    /// cells a tenth of the layer, its rows moving up and down in turn by
    /// 0.025 layer a step for eight steps (the last normals 76° from the
    /// vertical). Holding the flat cloth's empty list misses them.
    #[test]
    fn held_candidates_hold_the_pairs_of_a_smooth_region_that_folds() {
        let n = 21;
        let layer = Collision::default().thickness;
        let size = 0.1 * layer * (n - 1) as f64;
        let m = crate::rectangle::rectangle(size, size, n, n, [0.0; 3]);
        let zigzag: Vec<f64> = (0..3 * n * n)
            .map(|i| match (i % 3, (i / 3) % n % 2) {
                (2, 0) => 0.025 * layer,
                (2, _) => -0.025 * layer,
                _ => 0.0,
            })
            .collect();
        let (checked, _) = follow(
            &m.triangles,
            m.points.clone(),
            (0..8).map(|_| zigzag.clone()),
        );
        assert!(checked > 1_000, "{checked} pairs checked");
    }

    /// Step a cloth of `triangles` from `x` through `motions` twice, once
    /// holding its candidates and once finding them anew at every step,
    /// and assert that the held ones hold every pair that matters, none
    /// twice, with their distances bounded from below, and that the pairs
    /// measured for the proximity impulses are exactly those within the
    /// layer, at their true distance. Returns how many pairs that matter
    /// were checked and how many held bounds were below the true distance.
    fn follow(
        triangles: &[[usize; 3]],
        mut x: Vec<f64>,
        motions: impl Iterator<Item = Vec<f64>>,
    ) -> (usize, usize) {
        let nodes = x.len() / 3;
        let net = Network {
            mass: vec![1e-3; nodes],
            inv_mass: vec![1e3; nodes],
            triangles: triangles.to_vec(),
            canopy_nodes: nodes,
            ..Network::default()
        };
        let layer = Collision::default().thickness;
        let mut c = Contacts::new(&net, &Collision::default()).expect("a surface");
        let mut fresh = Contacts::new(&net, &Collision::default()).expect("a surface");
        let (mut checked, mut lowered) = (0, 0);
        for (step, dx) in motions.enumerate() {
            c.begin_step(&x);
            let mut held = c.step_candidates(&dx);
            let set: HashSet<Stencil> = held.pairs.iter().map(Pair::stencil).collect();
            assert_eq!(set.len(), held.pairs.len(), "a pair is held twice");
            let now: Vec<f64> = distances(&held, &x);
            for (p, d) in held.pairs.iter().zip(&now) {
                assert!(p.distance <= d + 1e-12 * layer, "{p:?}: bound above {d}");
            }
            lowered += held
                .pairs
                .iter()
                .zip(&now)
                .filter(|(p, d)| p.distance < **d)
                .count();
            c.measure(&mut held, &dx);
            let within: Vec<(Stencil, f64)> = (held.pairs.iter().zip(&now))
                .filter(|(_, d)| **d < layer)
                .map(|(p, d)| (p.stencil(), *d))
                .collect();
            let measured: Vec<(Stencil, f64)> = Contacts::within(&held)
                .map(|(st, c)| (*st, c.distance()))
                .collect();
            assert_eq!(measured, within, "step {step}");
            fresh.begin_step(&x);
            fresh.forget_candidates();
            let again = fresh.refreshed(&dx);
            for st in again.pairs.iter().map(Pair::stencil) {
                if matters(&fresh, &st, &dx) {
                    assert!(set.contains(&st), "step {step}: {st:?} missed");
                    checked += 1;
                }
            }
            c.held = Some(held);
            x.iter_mut().zip(&dx).for_each(|(a, d)| *a += d);
        }
        (checked, lowered)
    }

    /// The distances of `c`'s pairs at `x`.
    fn distances(c: &Candidates, x: &[f64]) -> Vec<f64> {
        let at = |st: Stencil| st.closest(&st.at(x, x, 0.0)).distance();
        c.pairs.iter().map(|p| at(p.stencil())).collect()
    }
}
