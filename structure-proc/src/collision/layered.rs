//! The layered contact model (`[structure.collision] model = "layered"`):
//! the pairwise pass of `mod.rs` made affordable for fabric pressed in
//! layers, a packed canopy, where every node has hundreds of candidate
//! pairs and tens of them within the layer.
//!
//! The pairwise pass bounds every candidate pair at every step, pushes
//! every pair within the layer, and finds a node's pairs again whenever
//! the node leaves the box it was found for: on a crumpled 100 × 100 cloth
//! that is 1.8 million bounds and 370 thousand pushes a step, one contact
//! of two layers pushed through some fifty pairs that share its nearest
//! points, and a collapsing stack finds pairs again at every step. Here:
//!
//! 1. **Groups of patches.** The surface is cut into patches of a few
//!    cells (`patches.rs`); two patches whose boxes come within the layer
//!    and a slack make a group, which holds the pairs their primitives
//!    bring that were within a cutoff when it was formed, and a bound on
//!    all the others. At each step a group's bounds are lowered once, by
//!    how far any node of one patch moved relative to any of the other
//!    (the two patches' boxes of motion), and its pairs are looked at only
//!    while that lets one of them within reach. A group is formed anew
//!    when its bound on the pairs it does not hold wears down to the
//!    layer, and let go when its patches part: nodes that change course
//!    cost nothing while their patches stay near.
//! 2. **One push a contact.** The repulsion of the dissertation's eq. 3.30
//!    acts on the point–triangle pairs within the layer whose triangle owns
//!    the nearest point (its face, or the edge or node the nearest point
//!    lies on, by the surface's ownership: the lowest-numbered triangle
//!    that has it), so each point meets each layer once. Edge–edge pairs
//!    of fabric are pushed only within the layer's inner half and where
//!    their nearest points lie inside both edges (two edges crossing); at
//!    an edge's end the point–triangle pair has the contact. Pairs with a
//!    string's edge are pushed as in the pairwise model. The push grows
//!    from nothing at the layer's edge to the pairwise model's whole
//!    impulse at its inner half (`Repulsion::ramped`), so that a pair
//!    crossing the edge between two tries of an implicit window changes
//!    the step's outcome by little.
//! 3. **The same guarantee.** The continuous test and the impact zones are
//!    the pairwise pass's, over the pairs of the groups whose bound lets
//!    their motion reach within the tolerance: no step ends crossed.
//!
//! The pairs that act are a function of the positions alone (a group not
//! looked at holds none within reach, and a pair's group is that of the
//! one primitive pair that brings it), taken in the order of their groups
//! and stencils, so a run is the same on any number of threads and a
//! restarted run the same as one never stopped, as in the pairwise model.

use super::candidates::Pair;
use super::geometry::{Closest, Kind, Stencil};
use super::groups::Group;
use super::impulse::{Repulsion, PUSH_WITHIN};
use super::patches::{approach, Patches};
use super::{Contacts, Hit, IMPACT_FRACTION, PARALLEL_ITEMS};
use rayon::prelude::*;

/// The layered model's state between steps: the patches and the groups.
#[derive(Debug, Clone)]
pub struct Layers {
    pub patches: Patches,
    /// In the order of their patches.
    pub(super) groups: Vec<Group>,
    /// The positions the groups' bounds are lowered to: the start of the
    /// last step.
    pub(super) at: Vec<f64>,
    /// The motion the groups were last brought up to date for.
    pub(super) followed: Vec<f64>,
}

impl Layers {
    pub fn new(patches: Patches) -> Layers {
        Layers {
            patches,
            groups: Vec::new(),
            at: Vec::new(),
            followed: Vec::new(),
        }
    }

    /// Forget the groups: the next step forms them anew.
    pub fn forget(&mut self) {
        self.groups.clear();
        self.at.clear();
        self.followed.clear();
    }
}

impl Contacts {
    /// The layered model's groups as they stand (None in the pairwise
    /// model), for a window's start: a try taken again starts from them,
    /// not from where the last try left them, so it forms no group the
    /// window's start did not need.
    pub fn groups(&self) -> Option<Layers> {
        self.layers.clone()
    }

    /// Take the layered model's groups `kept` by [`Contacts::groups`].
    pub fn restore_groups(&mut self, kept: &Layers) {
        if let Some(l) = &mut self.layers {
            l.clone_from(kept);
        }
    }

    /// Whether the repulsion pushes the pair `st` when it is within the
    /// layer: a point against a triangle, or two edges one of which is a
    /// string's (nodes from `canopy_nodes` up to the bodies' points).
    pub(super) fn pushed(&self, st: &Stencil) -> bool {
        let string = |n: &usize| (self.canopy_nodes..self.nodes).contains(n);
        st.kind == Kind::PointTriangle || st.nodes.iter().any(string)
    }

    /// The repulsion the pair `st` takes: the scene's, but for the
    /// fabric's edge–edge pairs in the layered model, whose layer is the
    /// inner half of the scene's ([`Contacts::layered_near`]).
    pub(super) fn repulsion_of(&self, st: &Stencil) -> Repulsion {
        let mut r = self.repulsion;
        if self.layers.is_some() && !self.pushed(st) {
            r.thickness *= PUSH_WITHIN;
        }
        r
    }

    /// Whether the point–triangle pair `st`, its nearest points `w`, is
    /// the one that pushes its contact: its triangle owns the feature the
    /// nearest point lies on (the face itself, an edge, a node). Any
    /// other pair is its own contact.
    fn owns_contact(&self, patches: &Patches, st: &Stencil, w: &[f64; 4]) -> bool {
        if st.kind != Kind::PointTriangle {
            return true;
        }
        let mut on = [0; 3];
        let mut count = 0;
        for (&n, &wi) in st.nodes[1..].iter().zip(&w[1..]) {
            if wi != 0.0 {
                on[count] = n;
                count += 1;
            }
        }
        let owner = match count {
            1 => patches.first_triangle(on[0], None),
            2 => patches.first_triangle(on[0], Some(on[1])),
            _ => return true,
        };
        owner.is_none_or(|t| self.surface.nodes[t] == [st.nodes[1], st.nodes[2], st.nodes[3]])
    }

    /// The layered model's proximity impulses at x^n: in every group whose
    /// bound lets a pushed pair within the layer, those pairs measured (in
    /// parallel), and the ones that own their contact pushed in order;
    /// true if any acted.
    pub(super) fn layered_proximity(
        &mut self,
        inv_mass: &[f64],
        dx: &mut [f64],
        push: &mut [f64],
    ) -> bool {
        let mut layers = self.layers.take().expect("the layered model");
        let near = self.layered_near(&mut layers);
        self.layers = Some(layers);
        let mut acted = false;
        for (st, closest) in &near {
            acted |= self.repel(st, closest, inv_mass, dx, push);
        }
        acted
    }

    /// The pairs pushed at x^n, in order: the point–triangle pairs (and
    /// string pairs) within the layer that own their contact, then the
    /// fabric's edge–edge pairs within the layer's inner part
    /// ([`PUSH_WITHIN`]) whose nearest points lie inside both edges (where
    /// one lies on an end, a point–triangle pair has the contact); each
    /// with its nearest points. The measured pairs' stored distances and
    /// their groups' least are set anew.
    fn layered_near(&self, layers: &mut Layers) -> Vec<(Stencil, Closest)> {
        let layer = self.repulsion.thickness;
        let inner = PUSH_WITHIN * layer;
        let x = &self.start;
        let patches = &layers.patches;
        let open =
            |g: &Group| g.pushed_least - g.eroded < layer || g.others_least - g.eroded < inner;
        // The pairs of `list` under `within`, measured; those that `acts`
        // keeps, with their nearest points; the least stored distance.
        let measure = |list: &mut [Pair],
                       eroded: f64,
                       within: f64,
                       acts: &dyn Fn(&Stencil, &Closest) -> bool| {
            let mut near = Vec::new();
            let mut least = f64::INFINITY;
            for p in list.iter_mut() {
                if p.distance - eroded < within {
                    let st = p.stencil();
                    let closest = st.closest(&st.at(x, x, 0.0));
                    let d = closest.distance();
                    p.distance = d + eroded;
                    if d < within && acts(&st, &closest) {
                        near.push((st, closest));
                    }
                }
                least = least.min(p.distance);
            }
            (near, least)
        };
        let owns = |st: &Stencil, c: &Closest| self.owns_contact(patches, st, &c.w);
        let crossing = |_: &Stencil, c: &Closest| c.w.iter().all(|&w| w != 0.0);
        let job = |g: &mut Group| {
            let (mut near, least) = measure(&mut g.pushed, g.eroded, layer, &owns);
            g.pushed_least = least;
            let (edges, least) = measure(&mut g.others, g.eroded, inner, &crossing);
            g.others_least = least;
            near.extend(edges);
            near
        };
        in_groups(&mut layers.groups, open, job).concat()
    }

    /// The layered model's pairs that touch during the step from x^n
    /// along `dx` ([`Contacts::detect`]), looked for only in the groups
    /// whose bound less their patches' relative motion is within the
    /// tolerance. A pair looked at whose bound is within reach is measured
    /// first, and its stored distance set anew, so that resting layers'
    /// bounds do not wear down to the cubic.
    pub(super) fn layered_detect(&mut self, dx: &[f64]) -> Vec<Hit> {
        let mut layers = self.layers.take().expect("the layered model");
        let motion = layers.patches.boxes(dx);
        let eta = IMPACT_FRACTION * self.repulsion.thickness;
        let x = &self.start;
        let reach = |g: &Group| approach(&motion[g.a as usize], &motion[g.b as usize]);
        let open = |g: &Group| g.least() - g.eroded - reach(g) <= eta;
        let job = |g: &mut Group| {
            let mut hits = Vec::new();
            let eroded = g.eroded;
            for p in g.pushed.iter_mut().chain(g.others.iter_mut()) {
                let st = p.stencil();
                if p.distance - eroded - st.approach(dx) <= eta {
                    let d = st.closest(&st.at(x, x, 0.0)).distance();
                    p.distance = d + eroded;
                    hits.extend(self.hit(&st, d, dx, eta));
                }
            }
            self.set_least(g);
            hits
        };
        let hits = in_groups(&mut layers.groups, open, job)
            .into_iter()
            .flatten()
            .collect();
        self.layers = Some(layers);
        hits
    }
}

/// `job` on each of `groups` that `open` picks, in parallel when they
/// hold many pairs; the results in the groups' order.
fn in_groups<T: Send>(
    groups: &mut [Group],
    open: impl Fn(&Group) -> bool + Sync,
    job: impl Fn(&mut Group) -> T + Sync + Send,
) -> Vec<T> {
    let mut jobs: Vec<&mut Group> = groups.iter_mut().filter(|g| open(g)).collect();
    let pairs: usize = jobs.iter().map(|g| g.pushed.len() + g.others.len()).sum();
    if pairs < PARALLEL_ITEMS {
        jobs.iter_mut().map(|g| job(g)).collect()
    } else {
        jobs.par_iter_mut()
            .with_max_len(16)
            .map(|g| job(g))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::noise;
    use crate::network::Network;
    use std::collections::HashSet;
    use structure_section::collision::ContactModel;
    use structure_section::Collision;

    /// The layered model's groups hold every pair that can act, and its
    /// pushes go to exactly one pair per contact: a 21 × 21 cloth pleated
    /// into layers 0.8 of the layer apart, each node moving by up to 0.1
    /// layer a step along each axis for eighteen steps, a tenth of the
    /// nodes jumping two layers at the fourth (past the slack) and all
    /// turning back from the thirteenth. At every step, against every pair
    /// the surface has measured by brute force: (1) each pair within the
    /// layer at the start or the end, or touching during the step, is held
    /// with a stored distance that less its group's erosion is at most its
    /// distance; (2) the pairs pushed are the point–triangle pairs within
    /// the layer whose triangle owns their nearest feature and the
    /// edge–edge pairs within its inner half whose nearest points lie
    /// inside both edges; and every point within the layer of some
    /// triangle has one of them.
    #[test]
    fn the_groups_hold_every_pair_that_can_act_and_push_each_contact_once() {
        let n = 21;
        let m = crate::rectangle::rectangle(0.2, 0.2, n, n, [0.0; 3]);
        let spec = Collision {
            model: ContactModel::Layered,
            ..Collision::default()
        };
        let layer = spec.thickness;
        let mut x = m.pleated(4, 0.8 * layer);
        let nodes = n * n;
        let net = Network {
            mass: vec![1e-3; nodes],
            inv_mass: vec![1e3; nodes],
            triangles: m.triangles.clone(),
            canopy_nodes: nodes,
            ..Network::default()
        };
        let mut c = Contacts::new(&net, &spec).expect("a surface");
        let mut r = noise(3);
        let velocity: Vec<f64> = x.iter().map(|_| 0.1 * layer * r()).collect();
        let (mut checked_pairs, mut pushed) = (0, 0);
        for step in 1..=18 {
            let mut dx = velocity.clone();
            if step >= 13 {
                dx.iter_mut().for_each(|d| *d = -*d);
            }
            if step == 4 {
                for k in (0..nodes).step_by(10) {
                    dx[3 * k + 2] += 2.0 * layer * r().signum();
                }
            }
            c.begin_step(&x);
            c.layered_begin(&dx);
            let mut layers = c.layers.take().unwrap();
            let near = c.layered_near(&mut layers);
            let (held, acted) = checked(&c, &layers, &near, &x, &dx, step);
            checked_pairs += held;
            pushed += acted;
            c.layers = Some(layers);
            x.iter_mut().zip(&dx).for_each(|(a, d)| *a += d);
        }
        assert!(checked_pairs > 10_000, "{checked_pairs} pairs checked");
        assert!(pushed > 1_000, "{pushed} contacts pushed");
    }

    /// The checks of one step at x^n moving by `dx`, `near` the pairs
    /// pushed: how many pairs that can act it checked were held, and how
    /// many pairs were pushed.
    fn checked(
        c: &Contacts,
        layers: &Layers,
        near: &[(Stencil, Closest)],
        x: &[f64],
        dx: &[f64],
        step: usize,
    ) -> (usize, usize) {
        let layer = c.repulsion.thickness;
        let mut checked = 0;
        let held: Vec<(Stencil, f64)> = (layers.groups.iter())
            .flat_map(|g| {
                let all = g.pushed.iter().chain(&g.others);
                all.map(move |p| (p.stencil(), p.distance - g.eroded))
            })
            .collect();
        let set: HashSet<Stencil> = held.iter().map(|h| h.0).collect();
        assert_eq!(set.len(), held.len(), "step {step}: a pair held twice");
        let distance = |st: &Stencil, s: f64| st.closest(&st.at(x, dx, s)).distance();
        for (st, bound) in &held {
            assert!(
                *bound <= distance(st, 0.0) + 1e-12 * layer,
                "step {step}: {st:?}"
            );
        }
        let (mut expected, mut edges) = (Vec::new(), Vec::new());
        for p in 0..c.surface.len() {
            for q in p + 1..c.surface.len() {
                c.surface.each_stencil(p, q, |st| {
                    let eta = IMPACT_FRACTION * layer;
                    let (d0, d1) = (distance(&st, 0.0), distance(&st, 1.0));
                    if d0 < layer || d1 < layer || st.impact(x, dx, eta).is_some() {
                        assert!(set.contains(&st), "step {step}: {st:?} missed");
                        checked += 1;
                    }
                    let w = st.closest(&st.at(x, x, 0.0)).w;
                    if st.kind == Kind::PointTriangle && d0 < layer {
                        let owns = c.owns_contact(&layers.patches, &st, &w);
                        expected.push((st, owns));
                    }
                    let inside = w.iter().all(|&w| w != 0.0);
                    if st.kind == Kind::EdgeEdge && d0 < PUSH_WITHIN * layer && inside {
                        edges.push(st);
                    }
                });
            }
        }
        // Every point within the layer of a triangle has a pushed pair.
        let points: HashSet<usize> = expected.iter().map(|(st, _)| st.nodes[0]).collect();
        let owned: HashSet<usize> = (expected.iter().filter(|e| e.1))
            .map(|(st, _)| st.nodes[0])
            .collect();
        assert_eq!(points, owned, "step {step}: a point has no contact");
        let mut want: Vec<Stencil> = expected.iter().filter(|e| e.1).map(|e| e.0).collect();
        want.extend(edges);
        let mut got: Vec<Stencil> = near.iter().map(|(st, _)| *st).collect();
        want.sort();
        got.sort();
        assert!(
            got == want,
            "step {step}: {} pushed, {} expected",
            got.len(),
            want.len()
        );
        (checked, got.len())
    }
}
