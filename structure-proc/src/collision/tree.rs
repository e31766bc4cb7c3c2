//! The broad phase: a bounding-volume hierarchy (AABB tree) over the
//! fabric's triangles and the strings' segments, with a normal hemisphere on each
//! node for self-collision culling.
//!
//! Each leaf's box holds its primitive at the step's start and end (a swept
//! box), grown by half the proximity layer (and a margin), so every pair
//! closer than the layer at the start or meeting during the step shares a
//! box overlap. The
//! tree is built top-down by median splits once, refitted every step, and
//! rebuilt when refitting has let its boxes grow to twice their summed area
//! at the last build.
//!
//! A fabric region that is one connected piece and whose normals, at the
//! start and end of the step, all lie in one open hemisphere (a normal cone
//! of half-angle under π/2) cannot meet itself (Volino & Magnenat-Thalmann
//! 1994; Provot 1997, the curvature criterion, without the contour test):
//! its self-test is skipped, so a flat or gently curved cloth costs a refit
//! and no pair tests. The hemisphere is sought among 26 fixed directions
//! ([`Facing`]). parry's BVH has no per-node data for this, hence a tree of
//! our own; its layout is flat arrays, children after their parent.

use super::geometry::V3;
use super::surface::Surface;
use super::sweep::Sweep;
use rayon::prelude::*;

/// Subtrees with more leaves than this split their work between two threads.
const PARALLEL_LEAVES: usize = 4096;

/// A box grown to this many times its summed area at the last build asks for a rebuild.
const REBUILD_GROWTH: f64 = 2.0;

#[derive(Debug, Clone, Copy)]
enum Node {
    Leaf(usize),
    Inner(usize, usize),
}

/// Which of 26 fixed directions every normal of a region, at the step's
/// start and end, lies within 90° − [`FACING_MARGIN`] of: bit k for
/// direction k. A region with any bit set has all its normals in one open
/// hemisphere with room to spare (tested against fixed axes, so that two
/// regions merge by a bitwise and). Its cone is caught when its axis lies
/// within 75° minus its half-angle of one of the 26 directions of the
/// cube's faces, edges and corners, which are at most 27.6° from any axis:
/// every region whose normals lie within 47° of one axis is.
type Facing = u32;

/// How far past perpendicular a normal must point along a direction to
/// count as facing it [rad]: a region judged smooth stays in one
/// hemisphere while its normals turn by less than this after the test
/// (impulses within the margin), and two triangles folded onto each other
/// more sharply than 2 × 15° are never culled, whatever their tilt.
pub const FACING_MARGIN: f64 = 15.0 * std::f64::consts::PI / 180.0;

/// No direction: strings, degenerate or flipping triangles.
const FACING_NOWHERE: Facing = 0;

/// The directions the normal `n` (any length) faces by more than
/// [`FACING_MARGIN`]: the 13 directions (1, 0, 0), (0, 1, 0), (0, 0, 1),
/// (1, ±1, 0), (1, 0, ±1), (0, 1, ±1), (1, ±1, ±1) in bits 0–12 and their
/// opposites in bits 13–25; the components along them are sums of n's,
/// compared with sin(margin)·|n|·|direction|.
#[inline(always)]
fn facing(n: &V3) -> Facing {
    let unit = FACING_MARGIN.sin() * n.norm();
    let mut bits = 0;
    for (k, (a, length)) in AXES.iter().zip(AXIS_LENGTHS).enumerate() {
        let along = a[0] * n.x + a[1] * n.y + a[2] * n.z;
        let least = unit * length;
        bits |= ((along > least) as Facing) << k | ((along < -least) as Facing) << (k + 13);
    }
    bits
}

/// The 13 directions of [`Facing`]'s bits 0–12 (their opposites are bits
/// 13–25), not normalised: the cube's faces, edges and corners.
const AXES: [[f64; 3]; 13] = [
    [1., 0., 0.],
    [0., 1., 0.],
    [0., 0., 1.],
    [1., 1., 0.],
    [1., -1., 0.],
    [1., 0., 1.],
    [1., 0., -1.],
    [0., 1., 1.],
    [0., 1., -1.],
    [1., 1., 1.],
    [1., 1., -1.],
    [1., -1., 1.],
    [1., -1., -1.],
];

/// The lengths of [`AXES`] (√3 correctly rounded), so that facing a
/// direction costs no square root.
const AXIS_LENGTHS: [f64; 13] = {
    use std::f64::consts::SQRT_2;
    const SQRT_3: f64 = 1.7320508075688772;
    [
        1.0, 1.0, 1.0, SQRT_2, SQRT_2, SQRT_2, SQRT_2, SQRT_2, SQRT_2, SQRT_3, SQRT_3, SQRT_3,
        SQRT_3,
    ]
};

/// The unit direction of [`Facing`]'s bit k.
fn direction(k: usize) -> V3 {
    let a = AXES[k % 13];
    let d = V3::new(a[0], a[1], a[2]).normalize();
    if k < 13 {
        d
    } else {
        -d
    }
}

#[derive(Debug, Clone, Default)]
pub struct Tree {
    /// Node 0 is the root; an inner node's children come after it.
    nodes: Vec<Node>,
    /// Leaves under each node.
    leaves: Vec<usize>,
    /// Whether a node's primitives are triangles that form one connected
    /// piece through shared nodes.
    connected: Vec<bool>,
    /// Whether a node's primitives are all bodies' (no pair among them is tested).
    inert: Vec<bool>,
    lo: Vec<V3>,
    hi: Vec<V3>,
    facing: Vec<Facing>,
    /// The boxes' summed surface area right after the last build.
    built_area: f64,
    /// Whether every pair is tested, no region skipped as smooth
    /// ([`Tree::unculled`]).
    unculled: bool,
}

impl Tree {
    /// A tree whose [`Tree::pairs`] skips no region as smooth: every pair
    /// whose boxes overlap, for a bound on every pair's distance (its
    /// regions then hold nothing to watch as they turn).
    pub fn unculled() -> Tree {
        Tree {
            unculled: true,
            ..Tree::default()
        }
    }

    /// Fit the boxes and facings to the step from `x` to `x + dx` (whose
    /// paths are `sweep`), with the boxes grown by `reach` [m]; build the
    /// tree first if it has none yet or it has degraded.
    pub fn refit(&mut self, s: &Surface, x: &[f64], dx: &[f64], sweep: &Sweep, reach: f64) {
        let leaf = |p: usize| {
            // An unculled tree reads no facing.
            let facing = match self.unculled {
                true => FACING_NOWHERE,
                false => leaf_facing(s, p, x, dx),
            };
            (sweep.feature_box_v3(s.vertices(p), reach), facing)
        };
        let (boxes, facings): (Vec<(V3, V3)>, Vec<Facing>) = if s.len() < super::PARALLEL_ITEMS {
            (0..s.len()).map(leaf).unzip()
        } else {
            (0..s.len()).into_par_iter().map(leaf).unzip()
        };
        if s.is_empty() {
            return;
        }
        let degraded = |t: &mut Tree| t.fit(&boxes, &facings) > REBUILD_GROWTH * t.built_area;
        if self.nodes.is_empty() || degraded(self) {
            self.build(s, &boxes);
            self.built_area = self.fit(&boxes, &facings);
        }
    }

    /// Boxes and facings from the leaves up; returns the summed box area.
    fn fit(&mut self, boxes: &[(V3, V3)], facings: &[Facing]) -> f64 {
        let mut area = 0.0;
        for n in (0..self.nodes.len()).rev() {
            let (lo, hi, facing) = match self.nodes[n] {
                Node::Leaf(p) => (boxes[p].0, boxes[p].1, facings[p]),
                Node::Inner(l, r) => (
                    self.lo[l].inf(&self.lo[r]),
                    self.hi[l].sup(&self.hi[r]),
                    self.facing[l] & self.facing[r],
                ),
            };
            let e = hi - lo;
            area += 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
            (self.lo[n], self.hi[n], self.facing[n]) = (lo, hi, facing);
        }
        area
    }

    /// Build top-down by median splits of the boxes' centres along their
    /// widest spread.
    fn build(&mut self, s: &Surface, boxes: &[(V3, V3)]) {
        let n = 2 * s.len().max(1) - 1;
        self.nodes = Vec::with_capacity(n);
        self.leaves = Vec::with_capacity(n);
        self.connected = Vec::with_capacity(n);
        self.inert = Vec::with_capacity(n);
        // The fabric, the bodies and the strings each get a subtree of their
        // own under the root, so that strings (which face nowhere) and bodies
        // never spoil a fabric region's hemisphere test.
        let kind = |p: usize| match (s.is_triangle(p), s.is_body(p)) {
            (true, false) => 0,
            (true, true) => 1,
            (false, _) => 2,
        };
        let mut groups: Vec<Vec<usize>> = (0..3)
            .map(|k| (0..s.len()).filter(|&p| kind(p) == k).collect())
            .filter(|g: &Vec<usize>| !g.is_empty())
            .collect();
        if !groups.is_empty() {
            self.join(s, boxes, &mut groups);
        }
        let m = self.nodes.len();
        self.lo = vec![V3::zeros(); m];
        self.hi = vec![V3::zeros(); m];
        self.facing = vec![FACING_NOWHERE; m];
    }

    /// Add a subtree with one subtree below for each of `groups`.
    fn join(&mut self, s: &Surface, boxes: &[(V3, V3)], groups: &mut [Vec<usize>]) {
        let [first, rest @ ..] = groups else {
            return;
        };
        if rest.is_empty() {
            return self.split(s, boxes, first);
        }
        let me = self.nodes.len();
        self.leaves.push(groups.iter().map(Vec::len).sum());
        // Groups of different kinds: fabric and bodies share no node and
        // segments are no triangles, so the union is never one connected
        // piece, and at most one group is the bodies'.
        self.connected.push(false);
        self.inert.push(false);
        self.nodes.push(Node::Leaf(usize::MAX));
        let (first, rest) = groups.split_at_mut(1);
        let l = self.nodes.len();
        self.split(s, boxes, &mut first[0]);
        let r = self.nodes.len();
        self.join(s, boxes, rest);
        self.nodes[me] = Node::Inner(l, r);
    }

    /// Add the subtree over `prims`.
    fn split(&mut self, s: &Surface, boxes: &[(V3, V3)], prims: &mut [usize]) {
        let me = self.nodes.len();
        self.leaves.push(prims.len());
        self.connected.push(is_connected(s, prims));
        self.inert.push(prims.iter().all(|&p| s.is_body(p)));
        if let [p] = prims {
            self.nodes.push(Node::Leaf(*p));
            return;
        }
        self.nodes.push(Node::Leaf(usize::MAX));
        let centre = |p: usize| boxes[p].0 + boxes[p].1;
        let (lo, hi) = prims.iter().fold(
            (V3::repeat(f64::INFINITY), V3::repeat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.inf(&centre(p)), hi.sup(&centre(p))),
        );
        let axis = (hi - lo).imax();
        let mid = prims.len() / 2;
        prims.select_nth_unstable_by(mid, |&a, &b| {
            centre(a)[axis].total_cmp(&centre(b)[axis]).then(a.cmp(&b))
        });
        let (left, right) = prims.split_at_mut(mid);
        let l = self.nodes.len();
        self.split(s, boxes, left);
        let r = self.nodes.len();
        self.split(s, boxes, right);
        self.nodes[me] = Node::Inner(l, r);
    }

    /// Every pair of primitives whose boxes overlap, but for those inside a
    /// region that cannot meet itself; each pair (p, q) once, p < q, in an
    /// order that does not depend on the thread count.
    pub fn pairs(&self) -> Vec<(usize, usize)> {
        if self.nodes.is_empty() {
            return Vec::new();
        }
        self.self_pairs(0)
    }

    /// The primitives whose boxes overlap the box `lo`–`hi`, in the
    /// tree's order, appended to `out`.
    pub fn overlapping(&self, lo: &V3, hi: &V3, out: &mut Vec<usize>) {
        let mut stack = Vec::with_capacity(64);
        if !self.nodes.is_empty() {
            stack.push(0);
        }
        while let Some(n) = stack.pop() {
            if !(0..3).all(|c| self.lo[n][c] <= hi[c] && lo[c] <= self.hi[n][c]) {
                continue;
            }
            match self.nodes[n] {
                Node::Leaf(p) => out.push(p),
                Node::Inner(l, r) => stack.extend([r, l]),
            }
        }
    }

    /// For each of the `primitives`, the region [`Tree::pairs`] skips as
    /// smooth that holds it (the bodies' aside), as the number of the
    /// region's top tree node, or [`NO_REGION`]: no pair within one region
    /// is tested.
    pub fn regions(&self, primitives: usize) -> Vec<usize> {
        let mut out = vec![NO_REGION; primitives];
        let mut stack = Vec::with_capacity(64);
        if !self.nodes.is_empty() {
            stack.push((0, NO_REGION));
        }
        while let Some((n, region)) = stack.pop() {
            match self.nodes[n] {
                Node::Leaf(p) => out[p] = region,
                Node::Inner(l, r) => {
                    let smooth = region == NO_REGION && self.smooth(n) && !self.inert[n];
                    let region = if smooth { n } else { region };
                    stack.extend([(r, region), (l, region)]);
                }
            }
        }
        out
    }

    /// The unit directions whose hemispheres, with the margin, hold every
    /// normal of the region of [`Tree::regions`] numbered `region`.
    pub fn directions(&self, region: usize) -> impl Iterator<Item = V3> + '_ {
        let bits = self.facing[region];
        (0..26).filter(move |k| bits >> k & 1 == 1).map(direction)
    }

    /// Whether node n's region cannot meet itself, or is all bodies'.
    fn smooth(&self, n: usize) -> bool {
        self.inert[n] || (!self.unculled && self.connected[n] && self.facing[n] != FACING_NOWHERE)
    }

    fn self_pairs(&self, n: usize) -> Vec<(usize, usize)> {
        let Node::Inner(l, r) = self.nodes[n] else {
            return Vec::new();
        };
        if self.smooth(n) {
            return Vec::new();
        }
        let both = || {
            let mut out = Vec::new();
            self.cross(l, r, &mut out);
            out
        };
        let (mut out, (a, b)) = if self.leaves[n] > PARALLEL_LEAVES {
            rayon::join(both, || {
                rayon::join(|| self.self_pairs(l), || self.self_pairs(r))
            })
        } else {
            (both(), (self.self_pairs(l), self.self_pairs(r)))
        };
        out.extend(a);
        out.extend(b);
        out
    }

    /// The overlapping leaf pairs between subtrees a and b.
    fn cross(&self, a: usize, b: usize, out: &mut Vec<(usize, usize)>) {
        let overlap =
            (0..3).all(|c| self.lo[a][c] <= self.hi[b][c] && self.lo[b][c] <= self.hi[a][c]);
        if !overlap || (self.inert[a] && self.inert[b]) {
            return;
        }
        match (self.nodes[a], self.nodes[b]) {
            (Node::Leaf(p), Node::Leaf(q)) => out.push((p.min(q), p.max(q))),
            (Node::Inner(l, r), Node::Leaf(_)) => {
                self.cross(l, b, out);
                self.cross(r, b, out);
            }
            (Node::Leaf(_), Node::Inner(l, r)) => {
                self.cross(a, l, out);
                self.cross(a, r, out);
            }
            (Node::Inner(al, ar), Node::Inner(bl, br)) => {
                if self.leaves[a] >= self.leaves[b] {
                    self.cross(al, b, out);
                    self.cross(ar, b, out);
                } else {
                    self.cross(a, bl, out);
                    self.cross(a, br, out);
                }
            }
        }
    }
}

/// The directions a triangle faces at both the step's start and end;
/// none for a segment.
fn leaf_facing(s: &Surface, p: usize, x: &[f64], dx: &[f64]) -> Facing {
    if !s.is_triangle(p) {
        return FACING_NOWHERE;
    }
    let normal = |scale: f64| {
        let q = s.nodes[p].map(|n| {
            V3::new(
                x[3 * n] + scale * dx[3 * n],
                x[3 * n + 1] + scale * dx[3 * n + 1],
                x[3 * n + 2] + scale * dx[3 * n + 2],
            )
        });
        (q[1] - q[0]).cross(&(q[2] - q[0]))
    };
    facing(&normal(0.0)) & facing(&normal(1.0))
}

/// No region skipped as smooth ([`Tree::regions`]).
pub const NO_REGION: usize = usize::MAX;

/// Whether `prims` are triangles forming one piece through shared nodes.
fn is_connected(s: &Surface, prims: &[usize]) -> bool {
    if prims.iter().any(|&p| !s.is_triangle(p)) {
        return false;
    }
    let mut zones = super::zones::Zones::new(prims.len());
    let mut first = std::collections::HashMap::with_capacity(2 * prims.len());
    for (k, &p) in prims.iter().enumerate() {
        for &n in s.vertices(p) {
            let other = *first.entry(n).or_insert(k);
            zones.join(k, other);
        }
    }
    let root = zones.root(0);
    (0..prims.len()).all(|k| zones.root(k) == root)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::Network;

    #[test]
    fn two_triangles_folded_onto_each_other_are_tested() {
        // A = (s0, a, s1) and B = (s0, s1, b) share the edge s0 s1 along y;
        // B is folded back over A to 0.07 above it. Their normals,
        // (0.02, 0, 1) and (0.05, 0, −1), both lean along +x: without a
        // margin they would count as facing one hemisphere and the pair
        // would be skipped, though b lies within the layer of A.
        let x = [0., 0., 0., 1., 0., -0.02, 0., 1., 0., 1., 0., 0.05];
        let net = Network {
            mass: vec![1.0; 4],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            canopy_nodes: 4,
            ..Network::default()
        };
        let s = Surface::of(&net);
        let mut t = Tree::default();
        let dx = vec![0.0; x.len()];
        t.refit(&s, &x, &dx, &Sweep::new(&x, &dx), 0.1);
        assert_eq!(t.pairs(), vec![(0, 1)]);
    }

    /// The table of the directions' lengths is their square roots, to the
    /// last bit (the facing test compares with it).
    #[test]
    fn the_axis_lengths_are_the_axes_lengths() {
        for (a, length) in AXES.iter().zip(AXIS_LENGTHS) {
            let exact = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            assert_eq!(exact.to_bits(), length.to_bits(), "{a:?}");
        }
    }

    #[test]
    fn a_flat_sheet_needs_no_pair_test() {
        let m = crate::rectangle::rectangle(1.0, 1.0, 11, 11, [0.0; 3]);
        let n = m.points.len() / 3;
        let net = Network {
            mass: vec![1.0; n],
            triangles: m.triangles.clone(),
            canopy_nodes: n,
            ..Network::default()
        };
        let s = Surface::of(&net);
        let mut t = Tree::default();
        let dx = vec![0.0; m.points.len()];
        t.refit(&s, &m.points, &dx, &Sweep::new(&m.points, &dx), 1e-3);
        assert!(t.pairs().is_empty(), "{} pairs", t.pairs().len());
    }
}
