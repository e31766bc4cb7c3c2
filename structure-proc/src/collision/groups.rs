//! The layered model's groups (`layered.rs`): two patches of the surface
//! whose boxes come near, with the candidate pairs their primitives bring
//! that were within a cutoff when the group was formed and a bound on all
//! the others; lowered at each step by the patches' relative motion,
//! formed anew when that bound wears down to the layer, let go when the
//! patches part. A sweep and prune over the patches' boxes finds the
//! patch pairs near each other.

use super::candidates::{Pair, ROUNDING};
use super::patches::{approach, Patches};
use super::sweep::{overlap, Aabb};
use super::Contacts;
use rayon::prelude::*;

/// Two patches whose swept boxes come within the layer and this many
/// layers more make a group ...
pub const SLACK: f64 = 1.0;

/// ... which holds the pairs within the layer and twice the slack when
/// it is formed, and is let go when its patches' boxes are more than the
/// layer and this many layers apart.
pub const PART: f64 = 4.0;

/// The groups are brought up to date for a step's motion with room for
/// each node's motion to change by this many layers more (the pushes and
/// impulses of the step), so that they are looked at again only when it
/// changes by more.
pub const CHANGE: f64 = 0.25;

/// Two patches (`a` ≤ `b`) near each other and the pairs their primitives
/// bring that were within the cutoff when the group was formed, each with
/// a stored distance that less `eroded` is a lower bound: those the
/// repulsion pushes, then the others, each in stencil order.
#[derive(Debug, Clone)]
pub(super) struct Group {
    pub(super) a: u32,
    pub(super) b: u32,
    pub(super) pushed: Vec<Pair>,
    pub(super) others: Vec<Pair>,
    /// Every pair the group does not hold is at least this far apart,
    /// less `eroded`.
    pub(super) cutoff: f64,
    /// The least stored distance of the pairs the repulsion pushes ...
    pub(super) pushed_least: f64,
    /// ... and of the others.
    pub(super) others_least: f64,
    /// How far the nodes of one patch can have come closer to those of
    /// the other since the stored distances were measured [m].
    pub(super) eroded: f64,
}

impl Group {
    fn key(&self) -> (u32, u32) {
        (self.a, self.b)
    }

    pub(super) fn least(&self) -> f64 {
        self.pushed_least.min(self.others_least)
    }
}

impl Contacts {
    /// The layered model's groups for a step from x^n moving by `dx`:
    /// their bounds lowered by the motion since the last step, then
    /// brought up to date ([`Contacts::layered_follow`]).
    pub(super) fn layered_begin(&mut self, dx: &[f64]) {
        let mut layers = self.layers.take().expect("the layered model");
        if layers.at.len() == self.start.len() {
            let moved: Vec<f64> = self
                .start
                .iter()
                .zip(&layers.at)
                .map(|(a, b)| a - b)
                .collect();
            let boxes = layers.patches.boxes(&moved);
            let rounding = ROUNDING * self.repulsion.thickness;
            for g in &mut layers.groups {
                g.eroded += approach(&boxes[g.a as usize], &boxes[g.b as usize]) + rounding;
            }
        } else {
            layers.groups.clear();
        }
        layers.at = self.start.clone();
        self.layers = Some(layers);
        self.layered_follow(dx);
    }

    /// Bring the groups up to date for the step's motion changed to `dx`,
    /// if it changed by more than the room they were brought up to date
    /// with ([`CHANGE`]).
    pub(super) fn layered_refollow(&mut self, dx: &[f64]) {
        let followed = &self.layers.as_ref().expect("the layered model").followed;
        let room = CHANGE * self.repulsion.thickness;
        let changed = |(a, b): (&[f64], &[f64])| {
            (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2) > room * room
        };
        let moved = dx.len() != followed.len()
            || dx
                .chunks_exact(3)
                .zip(followed.chunks_exact(3))
                .any(changed);
        if moved {
            self.layered_follow(dx);
        }
    }

    /// Bring the groups up to date for the step moving by `dx`: two
    /// patches whose boxes over the step come within the layer and the
    /// slack form a group; a group whose bound on the pairs it does not
    /// hold, less what its patches move relative to each other in the
    /// step, is under the layer is formed anew; a group whose patches'
    /// boxes are farther apart than the layer and [`PART`] is let go.
    pub(super) fn layered_follow(&mut self, dx: &[f64]) {
        let mut layers = self.layers.take().expect("the layered model");
        let layer = self.repulsion.thickness;
        let end: Vec<f64> = self.start.iter().zip(dx).map(|(a, d)| a + d).collect();
        let swept: Vec<Aabb> = (layers.patches.boxes(&self.start).into_iter())
            .zip(layers.patches.boxes(&end))
            .map(|(s, e)| union(&s, &e))
            .collect();
        let motion = layers.patches.boxes(dx);
        // Room for each node's motion to change by CHANGE layers.
        let room = CHANGE * layer;
        let near = touching_pairs(&swept, 0.5 * (1.0 + SLACK) * layer + room);
        let apart = |a: u32, b: u32| {
            let grow = |bx: &Aabb| grown(bx, 0.5 * (1.0 + PART) * layer);
            !overlap(&grow(&swept[a as usize]), &grow(&swept[b as usize]))
        };
        let worn = |g: &Group| {
            let moving = approach(&motion[g.a as usize], &motion[g.b as usize]) + 2.0 * room;
            g.cutoff - g.eroded - moving < layer
        };
        // The groups kept as they are, and the patch pairs to form.
        let mut kept: Vec<Group> = Vec::with_capacity(layers.groups.len());
        let mut form: Vec<(u32, u32, f64)> = Vec::new();
        let cutoff = |a: u32, b: u32| {
            let moving = approach(&motion[a as usize], &motion[b as usize]) + 2.0 * room;
            (1.0 + 2.0 * SLACK) * layer + moving
        };
        let mut old = std::mem::take(&mut layers.groups).into_iter().peekable();
        let mut new = near.into_iter().peekable();
        loop {
            let (g, pair) = match (old.peek(), new.peek()) {
                (None, None) => break,
                (Some(g), Some(&p)) if g.key() == p => (old.next(), new.next()),
                (Some(g), Some(&p)) if g.key() < p => (old.next(), None),
                (Some(_), Some(_)) | (None, Some(_)) => (None, new.next()),
                (Some(_), None) => (old.next(), None),
            };
            match (g, pair) {
                (Some(g), None) if apart(g.a, g.b) => {}
                (Some(g), _) if worn(&g) => form.push((g.a, g.b, cutoff(g.a, g.b))),
                (Some(g), _) => kept.push(g),
                (None, Some((a, b))) => form.push((a, b, cutoff(a, b))),
                (None, None) => unreachable!("one of the two lists gave a key"),
            }
        }
        let formed: Vec<Group> = if form.len() < 64 {
            form.iter()
                .map(|&(a, b, c)| self.formed(&layers.patches, a, b, c))
                .collect()
        } else {
            form.par_iter()
                .map(|&(a, b, c)| self.formed(&layers.patches, a, b, c))
                .collect()
        };
        if !formed.is_empty() {
            kept.extend(formed);
            kept.sort_unstable_by_key(Group::key);
        }
        layers.groups = kept;
        layers.followed = dx.to_vec();
        self.layers = Some(layers);
    }

    /// The group of patches a and b formed at x^n: every pair their
    /// primitives bring that is within `cutoff`, measured.
    fn formed(&self, patches: &Patches, a: u32, b: u32, cutoff: f64) -> Group {
        let x = &self.start;
        let (a, b) = (a as usize, b as usize);
        let boxes = |k: usize| -> Vec<(usize, Aabb)> {
            patches
                .primitives(k)
                .map(|p| (p, primitive_box(self.surface.vertices(p), x)))
                .collect()
        };
        let (first, second) = (boxes(a), boxes(b));
        let (mut pushed, mut others) = (Vec::new(), Vec::new());
        for &(p, bp) in &first {
            let reach = grown(&bp, cutoff);
            for &(q, bq) in &second {
                let skip = (a == b && q <= p)
                    || (self.surface.is_body(p) && self.surface.is_body(q))
                    || !overlap(&reach, &bq);
                if skip {
                    continue;
                }
                self.surface.each_stencil(p.min(q), p.max(q), |st| {
                    let (fa, fb) = st.features();
                    // The features' boxes farther apart than the cutoff
                    // along an axis: no need of their nearest points.
                    if !overlap(&grown(&primitive_box(fa, x), cutoff), &primitive_box(fb, x)) {
                        return;
                    }
                    let d = st.closest(&st.at(x, x, 0.0)).distance();
                    if d <= cutoff {
                        let list = if self.pushed(&st) {
                            &mut pushed
                        } else {
                            &mut others
                        };
                        list.push(Pair::new(&st, d));
                    }
                });
            }
        }
        pushed.sort_unstable_by_key(Pair::key);
        others.sort_unstable_by_key(Pair::key);
        let mut g = Group {
            a: a as u32,
            b: b as u32,
            pushed,
            others,
            cutoff,
            pushed_least: f64::INFINITY,
            others_least: f64::INFINITY,
            eroded: 0.0,
        };
        self.set_least(&mut g);
        g
    }

    /// Set `g`'s least stored distances from its pairs.
    pub(super) fn set_least(&self, g: &mut Group) {
        let least = |pairs: &[Pair]| pairs.iter().fold(f64::INFINITY, |m, p| m.min(p.distance));
        (g.pushed_least, g.others_least) = (least(&g.pushed), least(&g.others));
    }
}

/// The pairs (a ≤ b) of `boxes` that overlap once each is grown by
/// `grow`, every box with itself included, in order: sweep and prune
/// along the axis the boxes' centres spread most along.
fn touching_pairs(boxes: &[Aabb], grow: f64) -> Vec<(u32, u32)> {
    let grown: Vec<Aabb> = boxes.iter().map(|b| grown(b, grow)).collect();
    let spread = |c: usize| {
        let centres = grown.iter().map(|b| b.0[c] + b.1[c]);
        let (lo, hi) = centres.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
        hi - lo
    };
    let axis = (0..3)
        .max_by(|&i, &j| spread(i).total_cmp(&spread(j)))
        .unwrap_or(0);
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_unstable_by(|&i, &j| grown[i].0[axis].total_cmp(&grown[j].0[axis]));
    let mut pairs: Vec<(u32, u32)> = (0..boxes.len() as u32).map(|k| (k, k)).collect();
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if grown[j].0[axis] > grown[i].1[axis] {
                break;
            }
            if overlap(&grown[i], &grown[j]) {
                pairs.push((i.min(j) as u32, i.max(j) as u32));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// `b` grown by `grow` on every side.
fn grown(b: &Aabb, grow: f64) -> Aabb {
    (b.0.map(|v| v - grow), b.1.map(|v| v + grow))
}

/// The box holding both `a` and `b`.
fn union(a: &Aabb, b: &Aabb) -> Aabb {
    (
        std::array::from_fn(|c| a.0[c].min(b.0[c])),
        std::array::from_fn(|c| a.1[c].max(b.1[c])),
    )
}

/// The box of `nodes` at `x`.
fn primitive_box(nodes: &[usize], x: &[f64]) -> Aabb {
    let mut b = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for &n in nodes {
        for c in 0..3 {
            b.0[c] = b.0[c].min(x[3 * n + c]);
            b.1[c] = b.1[c].max(x[3 * n + c]);
        }
    }
    b
}
