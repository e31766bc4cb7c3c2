//! Collisions of the structure (the dissertation §2.5 and §3.4, after
//! Bridson, Fedkiw & Anderson 2002): the fabric and the strings against
//! themselves, each other and the shaped bodies' surfaces ([`Contacts`];
//! moving bodies in `carried.rs`), and free nodes against the rigid bodies'
//! shapes ([`Obstacles`], `bodies.rs`).
//!
//! [`Contacts::resolve`] follows the dissertation's summary of §2.5 after
//! each structure step that proposed positions x^can from x^n:
//! 1. the average motion over the step, dx = x^can − x^n (= v_ave·Δt);
//! 2. **proximity** at x^n: point–triangle and edge–edge pairs closer than
//!    the layer `thickness` get an inelastic impulse, eq. 3.30's repulsion
//!    and Coulomb friction (`impulse.rs`); a pair closer than half the
//!    layer is moved back out to it by its positions only (`push`);
//! 3. **collisions** from x^n along dx: the first touch of each pair by the
//!    coplanarity cubic (`hits.rs`, `geometry.rs`), stopped by an inelastic impulse,
//!    for up to [`PASSES`] passes;
//! 4. **impact zones** for what is left: colliding nodes merge into zones
//!    that move rigidly (`zones.rs`), until no collision remains, so no
//!    step ends with an intersection;
//! 5. x^{n+1} = x^n + dx and v^{n+1} = v^can + (dx − push − dx^can)/Δt on
//!    the nodes the pass moved; the others keep x^can and v^can bit for bit.
//!
//! The candidates come from an AABB tree over triangles and segments with
//! normal-hemisphere culling (`tree.rs`), found in parallel, held from
//! step to step and kept up to date node by node as nodes leave the boxes
//! they were found for (`candidates.rs`); the impulses are applied one
//! pair at a time in the order of the pairs' kinds and node numbers, so a
//! run is the same on any number of threads, and a restarted run the same
//! as one never stopped.
//!
//! That is the pairwise model (`[structure.collision] model = "pairwise"`,
//! the default). The layered model, for fabric pressed in layers, keeps
//! steps 1, 3, 4 and 5 and finds and pushes the pairs its own way: groups
//! of mesh patches (`patches.rs`, `groups.rs`) in place of the tree and the
//! held candidates, and one ramped push a contact (`layered.rs`).

mod bodies;
mod candidates;
mod carried;
mod culled;
pub mod geometry;
mod groups;
mod hits;
mod impulse;
pub mod intersections;
mod layered;
mod nearest;
mod patches;
mod quiet;
pub mod surface;
mod sweep;
mod tree;
mod zones;

pub use bodies::Obstacles;
pub use geometry::{Kind, Stencil};
pub use intersections::{intersections, triangles_through, Intersections};
pub use layered::Layers;
pub use surface::Surface;

use crate::network::Network;
use bodies::BodySurfaces;
use candidates::Candidates;
use geometry::V3;
use hits::Hit;
use impulse::Repulsion;
use patches::Patches;
use rayon::prelude::*;
use structure_section::collision::ContactModel;
use structure_section::Collision;
use tree::Tree;
use zones::Zones;

/// Passes of collision impulses before the impact zones take over
/// (Bridson et al. 2002 suggest a few).
pub const PASSES: usize = 5;

/// A pair is colliding when the cubic's root brings it closer than this
/// fraction of the layer (Bridson et al. 2002 test against a small
/// tolerance to catch the roots round-off moves).
pub const IMPACT_FRACTION: f64 = 1e-2;

/// The candidates' boxes reach this many layers beyond what the step's
/// motion needs, so that impulses smaller than that leave them valid.
pub const MARGIN: f64 = 0.1;

/// Rounds of zone merging after which a step gives up (each round merges
/// at least two zones, so a structure of n nodes needs at most n − 1; a
/// round that merges none fails at once).
const ZONE_ROUNDS: usize = 10_000;

/// Below this many items a loop of the pass runs on the calling thread:
/// handing work to rayon's pool costs a thread switch, tens of µs.
pub(crate) const PARALLEL_ITEMS: usize = 4096;

/// `f` over `items`, keeping the Some results in order: on rayon's pool
/// when there are many, on this thread when few.
fn filter_map<T: Sync, U: Send>(items: &[T], f: impl Fn(&T) -> Option<U> + Sync + Send) -> Vec<U> {
    if items.len() < PARALLEL_ITEMS {
        items.iter().filter_map(f).collect()
    } else {
        items.par_iter().filter_map(f).collect()
    }
}

/// Counts of what the pass did, for the monitors.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stats {
    /// Proximity impulses.
    pub proximity: u64,
    /// Collision impulses of the passes.
    pub collisions: u64,
    /// Steps that needed impact zones.
    pub zone_steps: u64,
    /// Impulses (proximity and collision) between two fabric features,
    /// between fabric and string, and between two string segments.
    pub fabric_fabric: u64,
    pub fabric_string: u64,
    pub string_string: u64,
    /// Impulses between the structure and a body's surface.
    #[serde(default)]
    pub structure_body: u64,
    /// Momentum the pass gave the structure's free nodes from outside them
    /// so far [N·s]: bodies' pushes, and zones that moved with a
    /// held node (self-contact impulses cancel).
    #[serde(default)]
    pub received: [f64; 3],
}

impl Stats {
    /// Count an impulse on `st`, whose nodes from `canopy_nodes` on are
    /// strings', and from `structure_nodes` on the bodies'.
    fn count(&mut self, st: &Stencil, canopy_nodes: usize, structure_nodes: usize) {
        if st.nodes.iter().any(|&n| n >= structure_nodes) {
            self.structure_body += 1;
            return;
        }
        let on_string = |n: usize| n >= canopy_nodes;
        let (first, second) = match st.kind {
            // A point is a string's if it is off the canopy; a triangle never is.
            Kind::PointTriangle => (on_string(st.nodes[0]), false),
            // An edge with an end off the canopy is a string segment.
            Kind::EdgeEdge => (
                st.nodes[..2].iter().any(|&n| on_string(n)),
                st.nodes[2..].iter().any(|&n| on_string(n)),
            ),
        };
        match (first, second) {
            (false, false) => self.fabric_fabric += 1,
            (true, true) => self.string_string += 1,
            _ => self.fabric_string += 1,
        }
    }
}

/// The fabric's and strings' contacts with themselves and each other.
pub struct Contacts {
    surface: Surface,
    tree: Tree,
    repulsion: Repulsion,
    /// Active string springs when the surface was made: a break, or a
    /// break undone by a checkpoint, changes it.
    strings: usize,
    /// Positions at the step's start, x^n, then the bodies' surface points.
    start: Vec<f64>,
    /// The shaped bodies' surfaces, numbered after the structure's nodes:
    /// their points take part in every test and no impulse moves them;
    /// static bodies' stay put, moving bodies' are carried by them.
    bodies: BodySurfaces,
    /// The carried points' motion over the coming step (xyz, zero for the
    /// static bodies' points), set by [`Contacts::move_bodies`].
    carried_dx: Vec<f64>,
    /// Each carried body's centre of mass at the step's start, and its motion.
    centres: Vec<(V3, V3)>,
    /// Each carried body's shape pose and centre when last placed.
    placed: Vec<(nalgebra::Isometry3<f64>, V3)>,
    /// Linear then angular momentum each carried body took in the last
    /// [`Contacts::resolve`] (world axes, about its centre), in
    /// [`BodySurfaces::carried`]'s order.
    momenta: Vec<(V3, V3)>,
    /// The structure's nodes; the bodies' points are numbered after them.
    nodes: usize,
    /// The candidates held from the last step.
    held: Option<Candidates>,
    /// Nodes from here on are the strings'.
    canopy_nodes: usize,
    /// The layered model's patches and groups (`layered.rs`); None in
    /// the pairwise model.
    layers: Option<Layers>,
    /// The pairwise model's quiet spell: steps it skips (`quiet.rs`).
    quiet: quiet::Quiet,
    pub stats: Stats,
}

impl Contacts {
    /// The pass for `net`, or None when the section switches it off or
    /// nothing can collide.
    pub fn new(net: &Network, spec: &Collision) -> Option<Contacts> {
        Contacts::with_bodies(net, spec, None).ok().flatten()
    }

    /// The pass for `net` with the surfaces of `rigid`'s shaped bodies:
    /// their edges and faces meet the structure's (a thin rod between two
    /// nodes stops a cloth). Static bodies' stay put; moving bodies, with
    /// `moving_body_surfaces`, carry theirs ([`Contacts::place_bodies`],
    /// [`Contacts::move_bodies`]) and take the reaction of every impulse
    /// they give ([`Contacts::body_momenta`]); without it they meet nodes
    /// only, in the node–body pass ([`Obstacles`]).
    pub fn with_bodies(
        net: &Network,
        spec: &Collision,
        rigid: Option<&rigid_section::RigidSection>,
    ) -> Result<Option<Contacts>, String> {
        if !spec.self_contact {
            return Ok(None);
        }
        let bodies = bodies::surfaces(rigid, net.nodes(), spec.moving_body_surfaces)?;
        let surface = Surface::with_fixed(net, &bodies.triangles);
        if surface.len() == bodies.triangles.len() {
            return Ok(None);
        }
        // The held pairs number their nodes in 32 bits.
        let points = net.nodes() + bodies.points.len() / 3;
        if u32::try_from(points).is_err() {
            return Err(format!(
                "the collision pass takes at most {} nodes and body points; this structure has {points}",
                u32::MAX
            ));
        }
        // Eq. 3.30's k: the scenario's, else the network's mean stiffness
        // (Bridson et al. 2002 use the cloth's stretch stiffness).
        let mean =
            net.couplings.iter().map(|c| c.2).sum::<f64>() / net.couplings.len().max(1) as f64;
        let layered = spec.model == ContactModel::Layered;
        Ok(Some(Contacts {
            layers: layered.then(|| Layers::new(Patches::new(&surface, points))),
            strings: surface.len() - surface.triangles,
            surface,
            tree: Tree::default(),
            repulsion: Repulsion {
                thickness: spec.thickness,
                stiffness: spec.repulsion_stiffness.unwrap_or(mean),
                friction: spec.friction,
                dt: 0.0,
                ramped: layered,
            },
            start: Vec::new(),
            carried_dx: vec![0.0; bodies.points.len()],
            centres: bodies
                .carried
                .iter()
                .map(|c| (c.centre, V3::zeros()))
                .collect(),
            placed: bodies.carried.iter().map(|c| (c.pose, c.centre)).collect(),
            momenta: vec![(V3::zeros(), V3::zeros()); bodies.carried.len()],
            bodies,
            nodes: net.nodes(),
            held: None,
            canopy_nodes: net.canopy_nodes,
            quiet: quiet::Quiet::default(),
            stats: Stats::default(),
        }))
    }

    /// Make the surface again if lines broke or a checkpoint mended them
    /// (called after every restore, so it first counts the segments alone).
    pub fn sync(&mut self, net: &Network) {
        self.quiet.end();
        if surface::segments(net).count() != self.strings {
            self.surface = Surface::with_fixed(net, &self.bodies.triangles);
            self.strings = self.surface.len() - self.surface.triangles;
            self.tree = Tree::default();
            self.quiet = quiet::Quiet::default();
            self.held = None;
            if self.layers.is_some() {
                let points = self.nodes + self.bodies.points.len() / 3;
                self.layers = Some(Layers::new(Patches::new(&self.surface, points)));
            }
        }
    }

    /// Remember x^n, the positions at the step's start.
    pub fn begin_step(&mut self, x: &[f64]) {
        self.start.clear();
        self.start.extend_from_slice(x);
        self.start.extend_from_slice(&self.bodies.points);
    }

    /// Resolve the contacts of the step of `dt` that took the nodes from
    /// the positions given to [`Contacts::begin_step`] to `x`, `v`: the
    /// nodes it moves get new positions and velocities. Nodes with
    /// `inv_mass` 0 take part but do not move. Fails only if the impact
    /// zones cannot end the collisions (nodes held apart by supports that
    /// move differently).
    pub fn resolve(
        &mut self,
        x: &mut [f64],
        v: &mut [f64],
        mass: &[f64],
        inv_mass: &[f64],
        dt: f64,
    ) -> Result<(), String> {
        self.repulsion.dt = dt;
        self.momenta.fill((V3::zeros(), V3::zeros()));
        // In a quiet spell nothing can come within the layer (`quiet.rs`).
        if self.quiet_through(x) {
            self.carry();
            return Ok(());
        }
        let mut proposed: Vec<f64> = x.iter().zip(&self.start).map(|(a, b)| a - b).collect();
        // The bodies' points: no mass, the motion their bodies give them.
        proposed.extend_from_slice(&self.carried_dx);
        // The bodies' points have no mass (copied only if there are any).
        let nodes = self.start.len() / 3;
        let (mass, inv_mass) = (padded(mass, nodes), padded(inv_mass, nodes));
        let (mass, inv_mass) = (&mass[..], &inv_mass[..]);
        let mut dx = proposed.clone();
        let structure_nodes = self.nodes;
        // The pairwise model's candidates; None in the layered model, whose
        // groups are its own (`self.layers`).
        let mut candidates = if self.layers.is_some() {
            self.layered_begin(&dx);
            None
        } else {
            Some(self.step_candidates(&dx))
        };
        // What the repulsion moves the positions only ([`Repulsion::act`]):
        // part of the motion from here on, never of the velocity.
        let mut push = vec![0.0; dx.len()];
        let pushed = match &mut candidates {
            Some(c) => self.proximity(c, inv_mass, &mut dx, &mut push),
            None => self.layered_proximity(inv_mass, &mut dx, &mut push),
        };
        if pushed {
            for (a, p) in dx.iter_mut().zip(&push) {
                *a += p;
            }
            candidates = self.brought_current(candidates, &dx);
        }
        let mut hits = self.touching(&candidates, &dx);
        for pass in 1..=PASSES {
            if hits.is_empty() {
                break;
            }
            for h in &hits {
                if let Some(jdt) =
                    impulse::stop(&h.stencil, &h.w, &h.normal, inv_mass, &mut dx, &mut push)
                {
                    self.credit(&h.stencil, &h.w, jdt);
                    self.stats.collisions += 1;
                    self.stats
                        .count(&h.stencil, self.canopy_nodes, structure_nodes);
                }
            }
            candidates = self.brought_current(candidates, &dx);
            hits = self.touching(&candidates, &dx);
            if pass == PASSES && !hits.is_empty() {
                let motion = (&mut dx[..], &mut push[..]);
                candidates = self.impact_zones(hits, candidates, mass, inv_mass, motion)?;
                break;
            }
        }
        self.commit((x, v), (mass, inv_mass), [&dx, &push, &proposed], dt);
        self.maybe_quiet(&dx, &candidates);
        self.carry();
        self.held = candidates;
        Ok(())
    }

    /// Step 5: x^{n+1} = x^n + dx and v^{n+1} = v^can + (dx − push −
    /// dx^can)/Δt on the nodes the pass moved (`proposed` is dx^can); the
    /// others keep x^can and v^can bit for bit.
    fn commit(
        &mut self,
        (x, v): (&mut [f64], &mut [f64]),
        (mass, inv_mass): (&[f64], &[f64]),
        [dx, push, proposed]: [&[f64]; 3],
        dt: f64,
    ) {
        for (n, &w) in inv_mass.iter().enumerate().take(x.len() / 3) {
            if w == 0.0 {
                continue;
            }
            for c in 0..3 {
                let i = 3 * n + c;
                if dx[i] != proposed[i] {
                    x[i] = self.start[i] + dx[i];
                    let dv = (dx[i] - push[i] - proposed[i]) / dt;
                    v[i] += dv;
                    self.stats.received[c] += mass[n] * dv;
                }
            }
        }
    }

    /// The pairwise model's candidates brought up to date for the motion
    /// `dx`, or the layered model's groups (None).
    fn brought_current(&mut self, c: Option<Candidates>, dx: &[f64]) -> Option<Candidates> {
        match c {
            Some(c) => Some(self.current(c, dx)),
            None => {
                self.layered_refollow(dx);
                None
            }
        }
    }

    /// Drop the candidates held from earlier steps: the next step finds
    /// them anew (what the first step of a run pays; for benchmarks).
    pub fn forget_candidates(&mut self) {
        self.held = None;
        self.quiet.end();
        if let Some(l) = &mut self.layers {
            l.forget();
        }
    }

    /// How far the boxes reach beyond the features [m]: half the layer,
    /// and the margin within which impulses may move a path before the
    /// candidates must be found again.
    fn reach(&self) -> f64 {
        (0.5 + MARGIN) * self.repulsion.thickness
    }

    /// Proximity impulses at x^n, the pairs that may act measured first
    /// (in parallel, then applied in order); true if any acted.
    fn proximity(
        &mut self,
        candidates: &mut Candidates,
        inv_mass: &[f64],
        dx: &mut [f64],
        push: &mut [f64],
    ) -> bool {
        let mut acted = false;
        self.measure(candidates, dx);
        for (st, c) in Contacts::within(candidates) {
            acted |= self.repel(st, c, inv_mass, dx, push);
        }
        acted
    }

    /// The proximity impulse on the pair `st` within the layer at x^n,
    /// `c` its nearest points there ([`Repulsion::act`]), credited to the
    /// bodies and counted; true if it acted.
    fn repel(
        &mut self,
        st: &Stencil,
        c: &geometry::Closest,
        inv_mass: &[f64],
        dx: &mut [f64],
        push: &mut [f64],
    ) -> bool {
        // A body pushes along its true normal, not its facet's.
        let c = &match self.body_normal(st, &c.w, dx, 0.0) {
            Some(n) => geometry::Closest {
                w: c.w,
                separation: n * c.distance(),
            },
            None => *c,
        };
        let Some(jdt) = self.repulsion_of(st).act(st, c, inv_mass, dx, push) else {
            return false;
        };
        self.credit(st, &c.w, jdt);
        self.stats.proximity += 1;
        self.stats.count(st, self.canopy_nodes, self.nodes);
        true
    }

    /// Merge colliding nodes into rigid zones until no collision is left;
    /// the candidates brought up to date. A zone's nodes first give up
    /// what the repulsion pushed them (`motion` is dx and the push), so
    /// that the zone's rigid motion, a velocity, holds none of it.
    fn impact_zones(
        &mut self,
        mut hits: Vec<Hit>,
        mut candidates: Option<Candidates>,
        mass: &[f64],
        inv_mass: &[f64],
        motion: (&mut [f64], &mut [f64]),
    ) -> Result<Option<Candidates>, String> {
        let (dx, push) = motion;
        self.stats.zone_steps += 1;
        let mut zones = Zones::new(inv_mass.len());
        for _ in 0..ZONE_ROUNDS {
            let mut merged = false;
            for h in &hits {
                let [a, b, c, d] = h.stencil.nodes;
                for other in [b, c, d] {
                    merged |= zones.join(a, other);
                }
            }
            if !merged {
                // Every colliding pair is inside one zone already: moving
                // rigidly they were touching at the step's start.
                return Err(format!(
                    "{} pairs touch within {:e} m at the step's start (nodes {:?} …): the structure starts, or was put, in contact with itself",
                    hits.len(),
                    IMPACT_FRACTION * self.repulsion.thickness,
                    hits[0].stencil.nodes
                ));
            }
            for zone in zones.groups() {
                let carrier = zone.iter().find_map(|&n| self.mover(n));
                for &n in &zone {
                    for i in 3 * n..3 * n + 3 {
                        dx[i] -= std::mem::take(&mut push[i]);
                    }
                }
                let before = carrier.map(|k| self.zone_momentum(&zone, k, dx, mass));
                zones::rigidify(&zone, &self.start, dx, mass, inv_mass);
                if let (Some(k), Some((lin, ang))) = (carrier, before) {
                    // The zone moves with the body: the body takes what the
                    // zone's free nodes gained.
                    let (lin1, ang1) = self.zone_momentum(&zone, k, dx, mass);
                    self.momenta[k].0 -= lin1 - lin;
                    self.momenta[k].1 -= ang1 - ang;
                }
            }
            candidates = self.brought_current(candidates, dx);
            hits = self.touching(&candidates, dx);
            if hits.is_empty() {
                return Ok(candidates);
            }
        }
        Err(format!(
            "impact zones did not end the collisions in {ZONE_ROUNDS} rounds ({} pairs left)",
            hits.len()
        ))
    }
}

/// `a` with zeros up to `len`, borrowed when it is that long already.
fn padded(a: &[f64], len: usize) -> std::borrow::Cow<'_, [f64]> {
    if a.len() == len {
        a.into()
    } else {
        let mut v = a.to_vec();
        v.resize(len, 0.0);
        v.into()
    }
}

/// A fixed pseudo-random sequence in [−1, 1), for the tests' motions.
#[cfg(test)]
fn noise(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}
