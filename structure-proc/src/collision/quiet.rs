//! Quiet spells of the pairwise model: steps the pass skips because
//! nothing can come within the layer in them, as on an open canopy whose
//! gores and lines are centimetres apart.
//!
//! When a step ends holding no candidate pair, the pass measures the
//! *clearance* at the next step's start: a lower bound g on the distance
//! between the two features of every pair it could test, from a search of
//! its own tree (`Tree::unculled`: no region skipped as smooth, so none
//! has to be watched as it turns) with the boxes grown to reach R; every
//! pair found is measured, every pair not found is farther than R. The
//! features of a pair are weighted means of their nodes, so over any steps
//! a pair comes closer by at most twice u, the largest motion of a node
//! relative to a common translation summed over the steps (each step's
//! translation its own: no distance sees one). While g − 2u stays at least
//! the layer, no pair is within the layer at a step's start and none
//! touches during it: the pass would find nothing, and it is skipped, the
//! same run to the bit. A step that would spend more than the budget ends
//! the spell, and the pass searches anew. Whatever moves the nodes between
//! steps (the node–body pass, a restored checkpoint) spends the budget too.
//!
//! On the open C-9 dome of `c9-drop.toml` (a 5 mm layer, nothing within
//! 5 cm) the pass skips 99.5 % of its steps while nothing touches.

use super::candidates::{Candidates, ROUNDING};
use super::sweep::Sweep;
use super::tree::Tree;
use super::{Contacts, Stencil};

/// The clearance search reaches as far as this many steps of the motion
/// of the step it follows, so that a spell lasts about as long where
/// nothing is within reach.
const SPELL_STEPS: f64 = 256.0;

/// The clearance search reaches at least this many layers, so that a
/// structure setting out from rest is not searched step after step.
const SHORTEST_REACH: f64 = 3.0;

/// A spell shorter than this many steps of the motion it follows is not
/// worth its search: the next search waits this many steps, twice as many
/// after each one in a row that fails, up to [`LONGEST_WAIT`] (a fine cloth
/// whose own triangles are closer than the layer never has a spell).
const WORTH_STEPS: u32 = 4;
const LONGEST_WAIT: u32 = 1024;

/// The spell under way, or the wait for the next clearance search.
#[derive(Debug, Clone)]
pub(super) struct Quiet {
    spell: Option<Spell>,
    /// Steps until the next search, and the wait after a failed one.
    wait: u32,
    backoff: u32,
    /// The clearance search's tree, fitted to the nodes' positions.
    tree: Tree,
    /// Steps skipped so far.
    skipped: u64,
}

/// A spell: the budget of relative motion u [m] the clearance allows,
/// how much of it the steps have spent, and where the last step left the
/// nodes.
#[derive(Debug, Clone)]
struct Spell {
    budget: f64,
    spent: f64,
    left: Vec<f64>,
}

impl Spell {
    /// Whether the step that took the structure's nodes from `start` (the
    /// bodies' points after them) to `end`, and carries the points by
    /// `carried`, stays within the budget, what moved the nodes from where
    /// the last step left them counted too; if it does, spent, and the
    /// nodes left at its end: one pass over the nodes, which every step of
    /// a spell pays.
    fn advance(&mut self, start: &[f64], end: &[f64], carried: &[f64]) -> bool {
        let n = end.len();
        if self.left.len() != start.len() || n + carried.len() != start.len() {
            return false;
        }
        let (mut jump, mut motion) = (Extent::default(), Extent::default());
        let (left, left_points) = self.left.split_at_mut(n);
        let (from, points) = start.split_at(n);
        let triples = from.chunks_exact(3).zip(end.chunks_exact(3));
        for ((s, e), l) in triples.zip(left.chunks_exact_mut(3)) {
            jump.hold([s[0] - l[0], s[1] - l[1], s[2] - l[2]]);
            motion.hold([e[0] - s[0], e[1] - s[1], e[2] - s[2]]);
            // Where the next step starts, to the bit.
            l.copy_from_slice(e);
        }
        let carried_points = points.chunks_exact(3).zip(carried.chunks_exact(3));
        for ((s, d), l) in carried_points.zip(left_points.chunks_exact_mut(3)) {
            jump.hold([s[0] - l[0], s[1] - l[1], s[2] - l[2]]);
            motion.hold([d[0], d[1], d[2]]);
            (0..3).for_each(|c| l[c] = s[c] + d[c]);
        }
        self.spent += jump.reach() + motion.reach();
        self.spent <= self.budget
    }
}

/// The box that holds motions (xyz), and whether all were numbers.
#[derive(Debug, Clone, Copy)]
struct Extent {
    lo: [f64; 3],
    hi: [f64; 3],
    /// Their sum: not finite if one was not.
    sum: f64,
}

impl Default for Extent {
    fn default() -> Extent {
        Extent {
            lo: [f64::INFINITY; 3],
            hi: [f64::NEG_INFINITY; 3],
            sum: 0.0,
        }
    }
}

impl Extent {
    #[inline]
    fn hold(&mut self, d: [f64; 3]) {
        for (c, d) in d.into_iter().enumerate() {
            self.lo[c] = if d < self.lo[c] { d } else { self.lo[c] };
            self.hi[c] = if d > self.hi[c] { d } else { self.hi[c] };
            self.sum += d;
        }
    }

    /// A bound on the largest motion relative to a common translation:
    /// half the box's diagonal, the farthest any motion lies from its
    /// centre (0 for none; unbounded if one was not a number).
    fn reach(&self) -> f64 {
        if !self.sum.is_finite() {
            return f64::INFINITY;
        }
        if self.lo[0] > self.hi[0] {
            return 0.0;
        }
        0.5 * (0..3)
            .map(|c| (self.hi[c] - self.lo[c]).powi(2))
            .sum::<f64>()
            .sqrt()
    }
}

impl Default for Quiet {
    fn default() -> Quiet {
        Quiet {
            spell: None,
            wait: 0,
            backoff: 0,
            tree: Tree::unculled(),
            skipped: 0,
        }
    }
}

impl Quiet {
    /// End the spell (a restore, a broken line, a benchmark's fresh
    /// start): the next step searches.
    pub fn end(&mut self) {
        self.spell = None;
        self.wait = 0;
    }
}

/// A bound on the largest motion of a node of `dx` relative to a common
/// translation [m] ([`Extent::reach`]).
fn spread(dx: &[f64]) -> f64 {
    let mut e = Extent::default();
    for d in dx.chunks_exact(3) {
        e.hold([d[0], d[1], d[2]]);
    }
    e.reach()
}

/// The distance between the boxes of the two features of `st` at `x`: at
/// most the features' own.
fn boxes_apart(st: &Stencil, x: &[f64]) -> f64 {
    let (a, b) = st.features();
    let bounds = |nodes: &[usize]| {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for &n in nodes {
            for c in 0..3 {
                lo[c] = lo[c].min(x[3 * n + c]);
                hi[c] = hi[c].max(x[3 * n + c]);
            }
        }
        (lo, hi)
    };
    let ((alo, ahi), (blo, bhi)) = (bounds(a), bounds(b));
    (0..3)
        .map(|c| (alo[c] - bhi[c]).max(blo[c] - ahi[c]).max(0.0).powi(2))
        .sum::<f64>()
        .sqrt()
}

impl Contacts {
    /// Whether the step that took the structure's nodes to `x` lies within
    /// the spell under way (the pass then has nothing to do in it); a step
    /// that does not ends it.
    pub(super) fn quiet_through(&mut self, x: &[f64]) -> bool {
        let Some(spell) = &mut self.quiet.spell else {
            return false;
        };
        if spell.advance(&self.start, x, &self.carried_dx) {
            self.quiet.skipped += 1;
            return true;
        }
        // The held candidates were found before the spell: search anew.
        self.quiet.spell = None;
        self.held = None;
        false
    }

    /// After a step that moved the nodes by `dx` and ends holding the
    /// pairwise model's `candidates` (None in the layered model, whose
    /// groups always hold its neighbouring patches): begin a spell if they
    /// hold no pair and the clearance at the step's end allows one worth
    /// its search.
    pub(super) fn maybe_quiet(&mut self, dx: &[f64], candidates: &Option<Candidates>) {
        if candidates.as_ref().is_none_or(|c| !c.pairs.is_empty()) {
            return;
        }
        if self.quiet.wait > 0 {
            self.quiet.wait -= 1;
            return;
        }
        let step = spread(dx).max(ROUNDING * self.repulsion.thickness);
        let layer = self.repulsion.thickness;
        let reach = (layer + 2.0 * SPELL_STEPS * step).max(SHORTEST_REACH * layer);
        let end: Vec<f64> = self.start.iter().zip(dx).map(|(x, d)| x + d).collect();
        let budget = self.clearance(&end, reach);
        if budget >= WORTH_STEPS as f64 * step {
            self.quiet.backoff = WORTH_STEPS;
            self.quiet.spell = Some(Spell {
                budget,
                spent: 0.0,
                left: end,
            });
        } else {
            let q = &mut self.quiet;
            q.backoff = (2 * q.backoff).clamp(WORTH_STEPS, LONGEST_WAIT);
            q.wait = q.backoff;
        }
    }

    /// The budget of relative motion u [m] the nodes at `x` may spend
    /// before a pair may come within the layer, from a search of every
    /// pair within `reach`.
    fn clearance(&mut self, x: &[f64], reach: f64) -> f64 {
        let still = vec![0.0; x.len()];
        let tree = &mut self.quiet.tree;
        tree.refit(
            &self.surface,
            x,
            &still,
            &Sweep::new(x, &still),
            0.5 * reach,
        );
        let mut nearest = reach;
        for (p, q) in tree.pairs() {
            self.surface.each_stencil(p, q, |st| {
                // The features' boxes apart by no less than the nearest yet
                // hold nothing nearer (most pairs of neighbouring triangles).
                if boxes_apart(&st, x) < nearest {
                    nearest = nearest.min(st.closest(&st.at(x, x, 0.0)).distance());
                }
            });
        }
        let layer = self.repulsion.thickness;
        (0.5 * (nearest - layer * (1.0 + ROUNDING))).max(0.0)
    }

    /// How many steps the pass has skipped in quiet spells.
    pub fn quiet_steps(&self) -> u64 {
        self.quiet.skipped
    }
}
