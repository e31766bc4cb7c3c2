//! Each node's path over a step, summarised once per motion so that the
//! broad and narrow phases test boxes and bounds by lookup: the box of the
//! node at x and x + dx, and how far it moves, |dx|.
//!
//! A feature's swept box (a point's, an edge's, a triangle's) is the union
//! of its nodes' boxes; the features of a pair can come no closer over the
//! step than their distance at the start less the largest motion of a node
//! of each (the bound the narrow phase uses to skip the cubic). A node's
//! box holds its path; |dx| is the box's diagonal, so it also bounds how
//! far apart any two points of the box are.

use super::geometry::{Kind, Stencil, V3};
use rayon::prelude::*;

/// A box as its lower and upper corners.
pub type Aabb = ([f64; 3], [f64; 3]);

#[derive(Debug, Clone, Default)]
pub struct Sweep {
    boxes: Vec<Aabb>,
    moved: Vec<f64>,
}

impl Sweep {
    /// The paths of the nodes of `x` moving by `dx` (xyz per node).
    pub fn new(x: &[f64], dx: &[f64]) -> Sweep {
        let path = |n: usize| {
            let mut b = ([0.0; 3], [0.0; 3]);
            for c in 0..3 {
                let (a, e) = (x[3 * n + c], x[3 * n + c] + dx[3 * n + c]);
                b.0[c] = a.min(e);
                b.1[c] = a.max(e);
            }
            let d = &dx[3 * n..3 * n + 3];
            (b, (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
        };
        let nodes = x.len() / 3;
        let (boxes, moved) = if nodes < super::PARALLEL_ITEMS {
            (0..nodes).map(path).unzip()
        } else {
            (0..nodes).into_par_iter().map(path).unzip()
        };
        Sweep { boxes, moved }
    }

    /// The box swept by `nodes`, grown by `grow` on every side.
    #[inline]
    pub fn feature_box(&self, nodes: &[usize], grow: f64) -> Aabb {
        let (mut lo, mut hi) = self.boxes[nodes[0]];
        for &n in &nodes[1..] {
            let (l, h) = &self.boxes[n];
            for c in 0..3 {
                lo[c] = lo[c].min(l[c]);
                hi[c] = hi[c].max(h[c]);
            }
        }
        for c in 0..3 {
            lo[c] -= grow;
            hi[c] += grow;
        }
        (lo, hi)
    }

    /// Whether the boxes swept by `a` and by `b`, each grown by `grow`,
    /// overlap (their gap is at most 2·`grow` along every axis).
    #[inline]
    pub fn near(&self, a: &[usize], b: &[usize], grow: f64) -> bool {
        overlap(&self.feature_box(a, grow), &self.feature_box(b, grow))
    }

    /// How far the two features of `st` can come closer over the step: the
    /// largest motion of a node of each, summed.
    #[inline]
    pub fn reach(&self, st: &Stencil) -> f64 {
        let (a, b) = st.features();
        let most = |nodes: &[usize]| nodes.iter().map(|&n| self.moved[n]).fold(0.0, f64::max);
        most(a) + most(b)
    }

    /// Whether node n's path in `now` lies within its path here grown by
    /// `slack` [m] along every axis.
    #[inline]
    pub fn holds(&self, now: &Sweep, n: usize, slack: f64) -> bool {
        let ((lo, hi), (l, h)) = (&self.boxes[n], &now.boxes[n]);
        (0..3).all(|c| l[c] >= lo[c] - slack && h[c] <= hi[c] + slack)
    }

    /// Take node n's path from `other`.
    pub fn take(&mut self, other: &Sweep, n: usize) {
        self.boxes[n] = other.boxes[n];
        self.moved[n] = other.moved[n];
    }

    /// The nodes' boxes as nalgebra vectors, for the tree.
    pub fn feature_box_v3(&self, nodes: &[usize], grow: f64) -> (V3, V3) {
        let (lo, hi) = self.feature_box(nodes, grow);
        (V3::from(lo), V3::from(hi))
    }
}

/// Whether two boxes overlap (touching counts).
#[inline]
pub fn overlap(a: &Aabb, b: &Aabb) -> bool {
    (0..3).all(|c| a.0[c] <= b.1[c] && b.0[c] <= a.1[c])
}

impl Stencil {
    /// The nodes of the pair's first feature (a point or an edge) and of
    /// its second (a triangle or an edge).
    #[inline]
    pub fn features(&self) -> (&[usize], &[usize]) {
        let split = match self.kind {
            Kind::PointTriangle => 1,
            Kind::EdgeEdge => 2,
        };
        self.nodes.split_at(split)
    }

    /// How far the pair's two features can come closer over a step moving
    /// by `dx`: the largest motion of a node of one relative to a node of
    /// the other. Each feature's points are weighted means of its nodes,
    /// so the relative motion of any two of them is a weighted mean of
    /// these; a pair that moves together (a falling layer) comes no closer.
    #[inline]
    pub fn approach(&self, dx: &[f64]) -> f64 {
        let (a, b) = self.features();
        let mut most: f64 = 0.0;
        for &i in a {
            for &j in b {
                let d = (0..3)
                    .map(|c| (dx[3 * i + c] - dx[3 * j + c]).powi(2))
                    .sum::<f64>();
                most = most.max(d);
            }
        }
        most.sqrt()
    }
}
