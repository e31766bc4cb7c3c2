//! The narrow phase's geometry: how far a point is from a triangle and an
//! edge from an edge, and the first moment in a step at which such a pair
//! touches (Bridson, Fedkiw & Anderson 2002, §§ 6–7; the dissertation §3.4's
//! two elementary tests of which a triangle pair's fifteen are made).
//!
//! A pair is a [`Stencil`] of four nodes with weights w, Σ wᵢ = 0, such that
//! Σ wᵢ xᵢ is the separation from the second feature's nearest point to the
//! first's: a point p against a triangle abc has w = [1, −α, −β, −γ] (α, β, γ
//! the barycentric coordinates of p's nearest point), an edge a₁a₂ against an
//! edge b₁b₂ has w = [1 − s, s, −(1 − t), −t]. Impulses use the same weights
//! (`impulse.rs`), which is why they keep momentum.

use nalgebra::Vector3;

pub type V3 = Vector3<f64>;

/// Which elementary test a stencil is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Kind {
    /// Nodes [p, a, b, c]: the point p against the triangle abc.
    PointTriangle,
    /// Nodes [a₁, a₂, b₁, b₂]: the edge a₁a₂ against the edge b₁b₂.
    EdgeEdge,
}

/// Four nodes of one point–triangle or edge–edge pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Stencil {
    pub kind: Kind,
    pub nodes: [usize; 4],
}

/// The nearest points of a pair at one moment.
#[derive(Debug, Clone, Copy)]
pub struct Closest {
    /// Weights of the four nodes, Σ wᵢ = 0.
    pub w: [f64; 4],
    /// Σ wᵢ xᵢ: from the second feature's nearest point to the first's.
    pub separation: V3,
}

impl Closest {
    pub fn distance(&self) -> f64 {
        self.separation.norm()
    }
}

impl Stencil {
    /// The four nodes' positions in `x` (xyz per node), moved by `s`·`dx`.
    #[inline]
    pub fn at(&self, x: &[f64], dx: &[f64], s: f64) -> [V3; 4] {
        // Written out: `nodes.map` was not inlined, and this runs for
        // every pair measured.
        let p = |n: usize| {
            V3::new(
                x[3 * n] + s * dx[3 * n],
                x[3 * n + 1] + s * dx[3 * n + 1],
                x[3 * n + 2] + s * dx[3 * n + 2],
            )
        };
        let [a, b, c, d] = self.nodes;
        [p(a), p(b), p(c), p(d)]
    }

    /// The pair's nearest points with the nodes at `p`.
    #[inline]
    pub fn closest(&self, p: &[V3; 4]) -> Closest {
        let w = match self.kind {
            Kind::PointTriangle => point_triangle_weights(p),
            Kind::EdgeEdge => edge_edge_weights(p),
        };
        let separation = (0..4).map(|i| p[i] * w[i]).sum();
        Closest { w, separation }
    }

    /// The plane's normal of the pair with the nodes at `p`, not normalised:
    /// the triangle's (b − a) × (c − a), or the edges' (a₂ − a₁) × (b₂ − b₁).
    pub fn plane_normal(&self, p: &[V3; 4]) -> V3 {
        let (e1, e2, _) = self.edges(p);
        e1.cross(&e2)
    }

    /// The three vectors whose triple product vanishes when the four nodes
    /// are coplanar: for a point–triangle pair b − a, c − a, p − a; for two
    /// edges a₂ − a₁, b₂ − b₁, b₁ − a₁.
    fn edges(&self, p: &[V3; 4]) -> (V3, V3, V3) {
        match self.kind {
            Kind::PointTriangle => (p[2] - p[1], p[3] - p[1], p[0] - p[1]),
            Kind::EdgeEdge => (p[1] - p[0], p[3] - p[2], p[2] - p[0]),
        }
    }

    /// The first s in [0, 1] at which the nodes, moving from `x` by s·`dx`,
    /// come closer than `eta`, or None: the roots of the coplanarity cubic
    /// (Bridson et al. 2002, §6) in time order, then the step's end, each
    /// checked by the distance there.
    pub fn impact(&self, x: &[f64], dx: &[f64], eta: f64) -> Option<f64> {
        let p0 = self.at(x, dx, 0.0);
        let p1 = self.at(x, dx, 1.0);
        let (a0, b0, c0) = self.edges(&p0);
        let (a1, b1, c1) = self.edges(&p1);
        let cubic = triple_product_cubic([a0, b0, c0], [a1 - a0, b1 - b0, c1 - c0]);
        let mut times = cubic_roots_in_unit(&cubic);
        times.push(1.0);
        times
            .as_slice()
            .iter()
            .copied()
            .find(|&s| self.closest(&self.at(x, dx, s)).distance() < eta)
    }
}

/// p's nearest point on the triangle abc, as w = [1, −α, −β, −γ].
#[inline]
fn point_triangle_weights(p: &[V3; 4]) -> [f64; 4] {
    let [a, b, c] = super::nearest::point_triangle(&p[0], &p[1], &p[2], &p[3]);
    [1.0, -a, -b, -c]
}

/// The nearest points of the edges a₁a₂ and b₁b₂, as w = [1 − s, s, −(1 − t), −t].
#[inline]
fn edge_edge_weights(p: &[V3; 4]) -> [f64; 4] {
    let (s, t) = super::nearest::segment_segment(&p[0], &p[1], &p[2], &p[3]);
    [1.0 - s, s, t - 1.0, -t]
}

/// The triangle of `triangles` (over the nodes at `x`) with the smallest
/// altitude, and that altitude [m]: twice its area over its longest edge.
pub fn smallest_altitude(x: &[f64], triangles: &[[usize; 3]]) -> Option<(usize, f64)> {
    let at = |n: usize| V3::new(x[3 * n], x[3 * n + 1], x[3 * n + 2]);
    triangles
        .iter()
        .enumerate()
        .map(|(k, t)| {
            let [a, b, c] = t.map(at);
            let longest = [(b - a).norm(), (c - b).norm(), (a - c).norm()]
                .into_iter()
                .fold(0.0, f64::max);
            let twice_area = (b - a).cross(&(c - a)).norm();
            (
                k,
                if longest > 0.0 {
                    twice_area / longest
                } else {
                    0.0
                },
            )
        })
        .min_by(|p, q| p.1.total_cmp(&q.1))
}

/// The coefficients c₀ … c₃ of (a(s) × b(s)) · c(s) for vectors moving as
/// v(s) = v₀ + s·dv.
fn triple_product_cubic(v0: [V3; 3], dv: [V3; 3]) -> [f64; 4] {
    let t = |a: &V3, b: &V3, c: &V3| a.cross(b).dot(c);
    let ([a, b, c], [da, db, dc]) = (v0, dv);
    [
        t(&a, &b, &c),
        t(&da, &b, &c) + t(&a, &db, &c) + t(&a, &b, &dc),
        t(&da, &db, &c) + t(&da, &b, &dc) + t(&a, &db, &dc),
        t(&da, &db, &dc),
    ]
}

/// Bisections that bring a root's bracket below 2⁻⁵² of the step.
const BISECTIONS: usize = 52;

/// A few times in [0, 1], ascending: a cubic's roots and the step's end
/// (at most five), kept on the stack, as this runs for every candidate pair.
#[derive(Debug, Clone, Copy, Default)]
pub struct Times {
    at: [f64; 6],
    len: usize,
}

impl Times {
    fn push(&mut self, s: f64) {
        if self.len < self.at.len() && (self.len == 0 || self.at[self.len - 1] != s) {
            self.at[self.len] = s;
            self.len += 1;
        }
    }

    pub fn as_slice(&self) -> &[f64] {
        &self.at[..self.len]
    }
}

/// The roots of c₀ + c₁s + c₂s² + c₃s³ in [0, 1], ascending. The interval
/// is cut at the derivative's roots into pieces where the cubic is
/// monotone; a piece whose ends differ in sign (or touch zero) holds one
/// root, found by bisection, which cannot fail on round-off the way a
/// closed formula can. A local extremum that nearly touches zero (a
/// grazing contact, within round-off of the coefficients' size) counts as
/// a root too: the distance test that follows decides.
pub fn cubic_roots_in_unit(c: &[f64; 4]) -> Times {
    let f = |s: f64| ((c[3] * s + c[2]) * s + c[1]) * s + c[0];
    let mut roots = Times::default();
    let scale = c.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if scale == 0.0 {
        // Coplanar all through the step: only the distance can tell.
        roots.push(0.0);
        roots.push(0.5);
        return roots;
    }
    let graze = 1e-12 * scale;
    let mut cuts = Times::default();
    cuts.push(0.0);
    for s in quadratic_roots_in_unit(3.0 * c[3], 2.0 * c[2], c[1]).as_slice() {
        cuts.push(*s);
    }
    cuts.push(1.0);
    for w in cuts.as_slice().windows(2) {
        let (mut lo, mut hi) = (w[0], w[1]);
        let (flo, fhi) = (f(lo), f(hi));
        if flo.abs() <= graze {
            roots.push(lo);
            continue;
        }
        if flo.signum() == fhi.signum() {
            continue;
        }
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if f(mid).signum() == flo.signum() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        roots.push(lo);
    }
    if f(1.0).abs() <= graze {
        roots.push(1.0);
    }
    roots
}

/// The roots of a·s² + b·s + c = 0 in (0, 1), ascending.
fn quadratic_roots_in_unit(a: f64, b: f64, c: f64) -> Times {
    let mut r = [f64::NAN; 2];
    if a == 0.0 {
        if b != 0.0 {
            r[0] = -c / b;
        }
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            // The stable pair of formulas: no cancellation in either root.
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            if q != 0.0 {
                r = [q / a, c / q];
            } else {
                r[0] = 0.0;
            }
        }
    }
    if r[1] < r[0] {
        r.swap(0, 1);
    }
    let mut out = Times::default();
    for s in r {
        if s > 0.0 && s < 1.0 {
            out.push(s);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_smallest_altitude_is_twice_the_area_over_the_longest_edge() {
        // A 3-4-5 right triangle: altitude to the hypotenuse 3·4/5 = 2.4;
        // a 1 × 0.1 sliver: 0.1 (its long edge is √1.01, so 0.1/√1.01).
        let x = [
            0., 0., 0., 3., 0., 0., 0., 4., 0., 10., 0., 0., 11., 0., 0., 10., 0.1, 0.,
        ];
        let (k, h) = smallest_altitude(&x, &[[0, 1, 2]]).unwrap();
        assert_eq!(k, 0);
        assert!((h - 2.4).abs() < 1e-15, "{h}");
        let (k, h) = smallest_altitude(&x, &[[0, 1, 2], [3, 4, 5]]).unwrap();
        assert_eq!(k, 1);
        assert!((h - 0.1 / 1.01f64.sqrt()).abs() < 1e-15, "{h}");
    }

    #[test]
    fn cubic_roots_are_found_to_round_off() {
        // (s − 0.2)(s − 0.5)(s − 0.9) = s³ − 1.6 s² + 0.73 s − 0.09.
        let r = cubic_roots_in_unit(&[-0.09, 0.73, -1.6, 1.0]);
        let r = r.as_slice();
        assert_eq!(r.len(), 3);
        for (got, want) in r.iter().zip([0.2, 0.5, 0.9]) {
            assert!((got - want).abs() < 1e-14, "{got} against {want}");
        }
        // A double root (a grazing touch) at 0.25: (s − 0.25)² (s + 1).
        let r = cubic_roots_in_unit(&[0.0625, -0.4375, 0.5, 1.0]);
        assert!(
            r.as_slice().iter().any(|s| (s - 0.25).abs() < 1e-7),
            "{r:?}"
        );
    }
}
