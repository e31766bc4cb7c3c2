//! Collisions of the structure (the dissertation §2.5 and §3.4, after
//! Bridson, Fedkiw & Anderson 2002): the fabric and the strings against
//! themselves and each other ([`Contacts`]), and free nodes against the
//! rigid bodies' shapes ([`Obstacles`], `bodies.rs`).
//!
//! [`Contacts::resolve`] follows the dissertation's summary of §2.5 after
//! each structure step that proposed positions x^can from x^n:
//! 1. the average motion over the step, dx = x^can − x^n (= v_ave·Δt);
//! 2. **proximity** at x^n: point–triangle and edge–edge pairs closer than
//!    the layer `thickness` get an inelastic impulse, eq. 3.30's repulsion
//!    and Coulomb friction (`impulse.rs`);
//! 3. **collisions** from x^n along dx: the first touch of each pair by the
//!    coplanarity cubic (`geometry.rs`), stopped by an inelastic impulse,
//!    for up to [`PASSES`] passes;
//! 4. **impact zones** for what is left: colliding nodes merge into zones
//!    that move rigidly (`zones.rs`), until no collision remains, so no
//!    step ends with an intersection;
//! 5. x^{n+1} = x^n + dx and v^{n+1} = v^can + (dx − dx^can)/Δt on the
//!    nodes the pass moved; the others keep x^can and v^can bit for bit.
//!
//! The candidates come from an AABB tree over triangles and segments with
//! normal-cone culling (`tree.rs`), found in parallel; the impulses are
//! applied one pair at a time in an order fixed by the tree, so a run is
//! the same on any number of threads.

mod bodies;
pub mod geometry;
mod impulse;
pub mod intersections;
pub mod surface;
mod tree;
mod zones;

pub use bodies::Obstacles;
pub use geometry::{Kind, Stencil};
pub use intersections::{intersections, Intersections};
pub use surface::Surface;

use crate::network::Network;
use geometry::V3;
use impulse::Repulsion;
use rayon::prelude::*;
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

/// Rounds of zone merging after which a step gives up (each round merges
/// at least two zones, so a structure of n nodes needs at most n − 1).
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
}

/// The fabric's and strings' contacts with themselves and each other.
pub struct Contacts {
    surface: Surface,
    tree: Tree,
    repulsion: Repulsion,
    /// Active string springs when the surface was made: a break, or a
    /// break undone by a checkpoint, changes it.
    strings: usize,
    /// Positions at the step's start, x^n.
    start: Vec<f64>,
    pub stats: Stats,
}

/// A pair found touching during the step.
struct Hit {
    stencil: Stencil,
    w: [f64; 4],
    normal: V3,
}

impl Contacts {
    /// The pass for `net`, or None when the section switches it off or
    /// nothing can collide.
    pub fn new(net: &Network, spec: &Collision) -> Option<Contacts> {
        if !spec.self_contact {
            return None;
        }
        let surface = Surface::of(net);
        if surface.is_empty() {
            return None;
        }
        // Eq. 3.30's k: the scenario's, else the network's mean stiffness
        // (Bridson et al. 2002 use the cloth's stretch stiffness).
        let mean =
            net.couplings.iter().map(|c| c.2).sum::<f64>() / net.couplings.len().max(1) as f64;
        Some(Contacts {
            strings: surface.len() - surface.triangles,
            surface,
            tree: Tree::default(),
            repulsion: Repulsion {
                thickness: spec.thickness,
                stiffness: spec.repulsion_stiffness.unwrap_or(mean),
                friction: spec.friction,
                dt: 0.0,
            },
            start: Vec::new(),
            stats: Stats::default(),
        })
    }

    /// Make the surface again if lines broke or a checkpoint mended them.
    pub fn sync(&mut self, net: &Network) {
        let surface = Surface::of(net);
        if surface.len() - surface.triangles != self.strings {
            self.strings = surface.len() - surface.triangles;
            self.surface = surface;
            self.tree = Tree::default();
        }
    }

    /// Remember x^n, the positions at the step's start.
    pub fn begin_step(&mut self, x: &[f64]) {
        self.start.clear();
        self.start.extend_from_slice(x);
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
        let proposed: Vec<f64> = x.iter().zip(&self.start).map(|(a, b)| a - b).collect();
        let mut dx = proposed.clone();
        self.tree
            .refit(&self.surface, &self.start, &dx, self.repulsion.thickness);
        let mut candidates = self.candidates(&dx);
        if self.proximity(&candidates, inv_mass, &mut dx) {
            candidates = self.refreshed(&dx);
        }
        let mut hits = self.detect(&candidates, &dx);
        for pass in 1..=PASSES {
            if hits.is_empty() {
                break;
            }
            for h in &hits {
                self.stats.collisions +=
                    impulse::stop(&h.stencil, &h.w, &h.normal, inv_mass, &mut dx) as u64;
            }
            candidates = self.refreshed(&dx);
            hits = self.detect(&candidates, &dx);
            if pass == PASSES && !hits.is_empty() {
                self.impact_zones(hits, mass, inv_mass, &mut dx)?;
                break;
            }
        }
        for (n, &w) in inv_mass.iter().enumerate() {
            if w == 0.0 {
                continue;
            }
            for c in 0..3 {
                let i = 3 * n + c;
                if dx[i] != proposed[i] {
                    x[i] = self.start[i] + dx[i];
                    v[i] += (dx[i] - proposed[i]) / dt;
                }
            }
        }
        Ok(())
    }

    /// The tree refitted to the motion `dx`, and its candidates.
    fn refreshed(&mut self, dx: &[f64]) -> Vec<Stencil> {
        self.tree
            .refit(&self.surface, &self.start, dx, self.repulsion.thickness);
        self.candidates(dx)
    }

    /// The elementary pairs whose features' swept boxes, grown by half the
    /// layer, overlap: the tree's primitive pairs, refined.
    fn candidates(&self, dx: &[f64]) -> Vec<Stencil> {
        let pairs = self.tree.pairs();
        let (x, layer) = (&self.start, self.repulsion.thickness);
        let chunks: Vec<&[(usize, usize)]> = pairs.chunks(256).collect();
        let found = filter_map(&chunks, |chunk| {
            let mut out = Vec::new();
            for &(p, q) in *chunk {
                self.surface.stencils(p, q, &mut out);
            }
            out.retain(|st| features_near(st, x, dx, layer));
            Some(out)
        });
        found.concat()
    }

    /// Proximity impulses at x^n; true if any acted.
    fn proximity(&mut self, candidates: &[Stencil], inv_mass: &[f64], dx: &mut [f64]) -> bool {
        let (x, layer) = (&self.start, self.repulsion.thickness);
        let moving: &[f64] = dx;
        let near = filter_map(candidates, |st| {
            let c = st.closest(&st.at(x, moving, 0.0));
            (c.distance() < layer).then_some((*st, c))
        });
        let mut acted = false;
        for (st, c) in &near {
            if self.repulsion.act(st, c, inv_mass, dx) {
                self.stats.proximity += 1;
                acted = true;
            }
        }
        acted
    }

    /// The pairs that touch during the step from x^n along `dx`, with the
    /// normal that points from the second feature to the first as they
    /// stood at the start.
    fn detect(&self, candidates: &[Stencil], dx: &[f64]) -> Vec<Hit> {
        let x = &self.start;
        let eta = IMPACT_FRACTION * self.repulsion.thickness;
        filter_map(candidates, |st| {
            let s = st.impact(x, dx, eta)?;
            let at = st.at(x, dx, s);
            let touch = st.closest(&at);
            let start = st.at(x, dx, 0.0);
            let before: V3 = (0..4).map(|i| start[i] * touch.w[i]).sum();
            let rel = impulse::relative(st, &touch.w, dx);
            let normal = st
                .plane_normal(&at)
                .try_normalize(1e-300)
                .or_else(|| touch.separation.try_normalize(1e-300))
                .or_else(|| (-rel).try_normalize(1e-300))?;
            // The side the first feature stood on at the start; if the
            // start says nothing, the side the motion leaves.
            let side = normal.dot(&before);
            let sign = if side != 0.0 {
                side.signum()
            } else {
                -normal.dot(&rel).signum()
            };
            Some(Hit {
                stencil: *st,
                w: touch.w,
                normal: normal * sign,
            })
        })
    }

    /// Merge colliding nodes into rigid zones until no collision is left.
    fn impact_zones(
        &mut self,
        mut hits: Vec<Hit>,
        mass: &[f64],
        inv_mass: &[f64],
        dx: &mut [f64],
    ) -> Result<(), String> {
        self.stats.zone_steps += 1;
        let mut zones = Zones::new(inv_mass.len());
        for _ in 0..ZONE_ROUNDS {
            for h in &hits {
                let [a, b, c, d] = h.stencil.nodes;
                zones.join(a, b);
                zones.join(a, c);
                zones.join(a, d);
            }
            for zone in zones.groups() {
                zones::rigidify(&zone, &self.start, dx, mass, inv_mass);
            }
            let candidates = self.refreshed(dx);
            hits = self.detect(&candidates, dx);
            if hits.is_empty() {
                return Ok(());
            }
        }
        Err(format!(
            "impact zones did not end the collisions in {ZONE_ROUNDS} rounds ({} pairs left)",
            hits.len()
        ))
    }
}

/// Whether the features' boxes over the step, grown by half the layer each, overlap.
fn features_near(st: &Stencil, x: &[f64], dx: &[f64], layer: f64) -> bool {
    let split = match st.kind {
        Kind::PointTriangle => 1,
        Kind::EdgeEdge => 2,
    };
    let (alo, ahi) = tree::swept_box(&st.nodes[..split], x, dx, 0.5 * layer);
    let (blo, bhi) = tree::swept_box(&st.nodes[split..], x, dx, 0.5 * layer);
    (0..3).all(|c| alo[c] <= bhi[c] && blo[c] <= ahi[c])
}
