//! Delingette's triangular springs (dissertation §2.3, eqs. 2.29–2.37): each triangle
//! resists the change of its three edge lengths dl with the energy
//! W = Σ ½ k_ij dl_ij² + Σ γ_i dl_ij dl_ik (eq. 2.29). With the stiffnesses of
//! eqs. (2.30)–(2.31) and the Lamé relations (2.32), W equals the small-strain
//! energy of an isotropic membrane of Young's modulus E, Poisson ratio ν and
//! thickness t on that triangle, so the mesh stretches as the fabric would.

use super::spring::{length_hessian, point};
use nalgebra::{Matrix3, Vector3};

/// Edge e joins vertices `EDGES[e].0` and `EDGES[e].1` and lies opposite vertex `(e + 2) % 3`.
const EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleSprings {
    pub nodes: [usize; 3],
    /// Rest lengths l⁰ of the edges [m].
    pub rest: [f64; 3],
    /// Q_ee = k_e (eq. 2.30); Q_ef = γ_i for the two edges e, f that meet at vertex i (eq. 2.31).
    pub q: Matrix3<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("triangle ({0}, {1}, {2}) is degenerate: area {3:.3e} m² for longest edge {4:.3e} m")]
pub struct Degenerate(pub usize, pub usize, pub usize, pub f64, pub f64);

/// Lamé coefficients of dissertation eq. (2.32) per unit area of a membrane of
/// thickness t: λ = E t ν/(1 − ν²), μ = E t (1 − ν)/(1 − ν²).
pub fn lame(young: f64, poisson: f64, thickness: f64) -> (f64, f64) {
    let et = young * thickness / (1.0 - poisson * poisson);
    (et * poisson, et * (1.0 - poisson))
}

impl TriangleSprings {
    /// The springs of the rest triangle `nodes` at positions `x`.
    pub fn new(x: &[f64], nodes: [usize; 3], lambda: f64, mu: f64) -> Result<Self, Degenerate> {
        let p = nodes.map(|n| point(x, n));
        let rest = EDGES.map(|(a, b)| (p[b] - p[a]).norm());
        let area = 0.5 * (p[1] - p[0]).cross(&(p[2] - p[0])).norm();
        let longest = rest.iter().cloned().fold(0.0, f64::max);
        // A sliver with area below 1e-8 of its edge squared has no usable angles.
        if !(area > 1e-8 * longest * longest) {
            return Err(Degenerate(nodes[0], nodes[1], nodes[2], area, longest));
        }
        // cot α at vertex v from the two edges leaving it.
        let cot = |v: usize| {
            let a = p[(v + 1) % 3] - p[v];
            let b = p[(v + 2) % 3] - p[v];
            a.dot(&b) / a.cross(&b).norm()
        };
        let mut q = Matrix3::zeros();
        for (e, _) in EDGES.iter().enumerate() {
            let k = (e + 2) % 3;
            q[(e, e)] =
                rest[e].powi(2) * (2.0 * cot(k).powi(2) * (lambda + mu) + mu) / (8.0 * area);
        }
        for i in 0..3 {
            // Vertex i joins edge i (to i+1) and edge i+2 (from i+2); eq. (2.31)
            // uses the angles at the other two vertices j = i+1, k = i+2.
            let (e, f) = (i, (i + 2) % 3);
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let g = rest[e] * rest[f] * (2.0 * cot(j) * cot(k) * (lambda + mu) - mu) / (8.0 * area);
            q[(e, f)] = g;
            q[(f, e)] = g;
        }
        Ok(TriangleSprings { nodes, rest, q })
    }

    /// Edge vectors, lengths and length changes dl at `x`.
    #[inline]
    fn edges(&self, x: &[f64]) -> ([Vector3<f64>; 3], [f64; 3], Vector3<f64>) {
        let d = EDGES.map(|(a, b)| point(x, self.nodes[b]) - point(x, self.nodes[a]));
        let l = d.map(|d| d.norm());
        let dl = Vector3::new(
            l[0] - self.rest[0],
            l[1] - self.rest[1],
            l[2] - self.rest[2],
        );
        (d, l, dl)
    }

    /// W of eq. (2.29) = ½ dlᵀ Q dl.
    pub fn energy(&self, x: &[f64]) -> f64 {
        let (_, _, dl) = self.edges(x);
        0.5 * dl.dot(&(self.q * dl))
    }

    /// −∂W/∂x (eq. 2.33) per edge e, on its first vertex `EDGES[e].0` (the
    /// second gets the opposite): every edge pulls its ends with the tension
    /// T_e = ∂W/∂dl_e = k_e dl_e + Σ γ dl_f, as in eqs. (2.35)–(2.36).
    #[inline]
    pub fn edge_forces(&self, x: &[f64]) -> [Vector3<f64>; 3] {
        let (d, l, dl) = self.edges(x);
        let t = self.q * dl;
        [0, 1, 2].map(|e| d[e] * (t[e] / l[e]))
    }

    /// −(s·H·p) per edge, on its first vertex (the second gets the opposite),
    /// H = ∂²W/∂x² = Σ Q_ef ∇l_e ∇l_fᵀ + Σ T_e ∇²l_e, the second sum kept only
    /// for edges under tension so that H stays positive semi-definite.
    #[inline]
    pub fn stiffness_product(&self, x: &[f64], s: f64, p: &[f64]) -> [Vector3<f64>; 3] {
        let (d, l, dl) = self.edges(x);
        let t = self.q * dl;
        let e = [d[0] / l[0], d[1] / l[1], d[2] / l[2]];
        let q = EDGES.map(|(a, b)| point(p, self.nodes[b]) - point(p, self.nodes[a]));
        let rate = Vector3::new(e[0].dot(&q[0]), e[1].dot(&q[1]), e[2].dot(&q[2]));
        let material = self.q * rate;
        [0, 1, 2]
            .map(|k| -(e[k] * material[k] + length_hessian(&e[k], l[k]) * q[k] * t[k].max(0.0)) * s)
    }

    /// The blocks G_ef = s·(Q_ef e_e e_fᵀ + δ_ef T_e⁺ ∇²l_e) of s·H between
    /// edges e and f: H couples edge e's ends (a_e, b_e) with edge f's as
    /// [G −G; −G G] ([`TriangleSprings::stiffness_product`] per edge is
    /// −Σ_f G_ef·(p_{b_f} − p_{a_f}) at a_e).
    pub fn stiffness_blocks(&self, x: &[f64], s: f64) -> [[Matrix3<f64>; 3]; 3] {
        let (d, l, dl) = self.edges(x);
        let t = self.q * dl;
        let e = [d[0] / l[0], d[1] / l[1], d[2] / l[2]];
        std::array::from_fn(|k| {
            std::array::from_fn(|f| {
                let mut g = e[k] * e[f].transpose() * self.q[(k, f)];
                if k == f {
                    g += length_hessian(&e[k], l[k]) * t[k].max(0.0);
                }
                g * s
            })
        })
    }

    /// The ends of edge e.
    pub fn edge(&self, e: usize) -> (usize, usize) {
        (self.nodes[EDGES[e].0], self.nodes[EDGES[e].1])
    }

    /// The tensile stiffness k_e of each edge, summed over triangles into k̃ of eq. (2.37).
    pub fn edge_stiffness(&self) -> [(usize, usize, f64); 3] {
        let mut out = [(0, 0, 0.0); 3];
        for (e, &(a, b)) in EDGES.iter().enumerate() {
            out[e] = (self.nodes[a], self.nodes[b], self.q[(e, e)]);
        }
        out
    }
}
