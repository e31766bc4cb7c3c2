//! The interface quasi-Newton method with an inverse Jacobian from a least
//! squares model, IQN-ILS (Degroote, Bathe & Vierendeels 2009, §3.2), as
//! preCICE runs it.
//!
//! Each try k of a window gives the solvers' answer x_k = H(x̃_k) to the
//! value x̃_k sent, and its residual r_k = x_k − x̃_k. From two tries on,
//! the differences of residuals ΔR and of answers ΔX are kept as columns
//! of V and W, those of the last few windows too. The next value sent is
//!
//!   x̃_{k+1} = x_k + W c,  c = argmin ‖V c + r_k‖₂,
//!
//! the least-squares problem solved by a QR decomposition of V (nalgebra).
//! Columns that are nearly dependent on newer ones are dropped first (the
//! QR2 filter of Haelterman et al. 2016: a column whose part orthogonal to
//! the newer kept ones is below `filter`·its norm), since they would make
//! R ill-conditioned.

use nalgebra::{DMatrix, DVector};

/// The columns kept, newest first, each with the window it came from.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Columns {
    v: Vec<Vec<f64>>,
    w: Vec<Vec<f64>>,
    windows: Vec<u64>,
}

/// The settings of [`Columns::update`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Windows whose columns are kept besides the current one.
    pub reused_windows: u32,
    /// Most columns kept.
    pub max_columns: u32,
    /// The QR2 filter's limit.
    pub filter: f64,
}

impl Columns {
    /// Keep the column (ΔR, ΔX) of `window`, newest first, and forget those
    /// older than the windows reused and beyond the most columns.
    pub fn push(&mut self, dr: Vec<f64>, dx: Vec<f64>, window: u64, limits: Limits) {
        self.v.insert(0, dr);
        self.w.insert(0, dx);
        self.windows.insert(0, window);
        let oldest = window.saturating_sub(limits.reused_windows as u64);
        let keep = self
            .windows
            .iter()
            .take_while(|&&w| w >= oldest)
            .count()
            .min(limits.max_columns as usize);
        self.v.truncate(keep);
        self.w.truncate(keep);
        self.windows.truncate(keep);
    }

    /// Forget columns of a value of another length (a mesh that changed).
    pub fn fit(&mut self, len: usize) {
        if self.v.first().is_some_and(|c| c.len() != len) {
            *self = Columns::default();
        }
    }

    /// The quasi-Newton step W c for residual `r`, c = argmin ‖V c + r‖₂ over
    /// the columns the filter keeps; None when it keeps none. Also returns
    /// how many it used.
    pub fn step(&self, r: &[f64], filter: f64) -> Option<(Vec<f64>, usize)> {
        let kept = self.filtered(filter);
        if kept.is_empty() {
            return None;
        }
        let n = r.len();
        let v = DMatrix::from_fn(n, kept.len(), |i, j| self.v[kept[j]][i]);
        let qr = v.qr();
        let rhs = qr.q().transpose() * DVector::from_iterator(n, r.iter().map(|x| -x));
        let c = qr.r().solve_upper_triangular(&rhs)?;
        Some((self.combine(&kept, c.as_slice()), kept.len()))
    }

    /// How many columns are kept.
    pub fn count(&self) -> usize {
        self.v.len()
    }

    /// W c over the columns `kept` (indices, newest first), c[j] the
    /// weight of column kept[j].
    pub fn combine(&self, kept: &[usize], c: &[f64]) -> Vec<f64> {
        let mut step = vec![0.0; self.w.first().map_or(0, Vec::len)];
        for (&col, c) in kept.iter().zip(c) {
            for (s, w) in step.iter_mut().zip(&self.w[col]) {
                *s += c * w;
            }
        }
        step
    }

    /// The Gram matrix VᵀSV of the first `m` columns in the scaled inner
    /// product `scale` (`Scale`), row-major m×m.
    pub fn gram(&self, m: usize, scale: &Scale) -> Vec<f64> {
        let mut g = vec![0.0; m * m];
        for i in 0..m {
            for j in 0..=i {
                let d = scale.dot(&self.v[i], &self.v[j]);
                (g[i * m + j], g[j * m + i]) = (d, d);
            }
        }
        g
    }

    /// VᵀS r over the first `m` columns.
    pub fn against(&self, m: usize, r: &[f64], scale: &Scale) -> Vec<f64> {
        self.v[..m].iter().map(|v| scale.dot(v, r)).collect()
    }

    /// The columns the QR2 filter keeps, newest first: modified Gram–Schmidt
    /// against the kept ones, dropping a column whose remainder is below
    /// `filter` times its norm.
    fn filtered(&self, filter: f64) -> Vec<usize> {
        let mut basis: Vec<Vec<f64>> = Vec::new();
        let mut kept = Vec::new();
        for (i, col) in self.v.iter().enumerate() {
            let norm = dot(col, col).sqrt();
            let mut rest = col.clone();
            for q in &basis {
                let p = dot(q, &rest);
                rest.iter_mut().zip(q).for_each(|(x, q)| *x -= p * q);
            }
            let left = dot(&rest, &rest).sqrt();
            if norm > 0.0 && left > filter * norm {
                rest.iter_mut().for_each(|x| *x /= left);
                basis.push(rest);
                kept.push(i);
            }
        }
        kept
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// A scaled inner product over fields laid end to end: each field's part
/// of a dot product weighed by its own factor, so that fields in other
/// units (pressures in Pa, positions in m) count alike in one
/// least-squares problem (preCICE's pre-scaling of a parallel scheme).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Scale {
    /// Each field's length and weight, in order.
    pub parts: Vec<(usize, f64)>,
}

impl Scale {
    /// Weights 1/‖x_f‖² from `values`' fields (1 for a zero field), so
    /// that each field of the value has unit norm.
    pub fn of(values: &[&mut [f64]]) -> Scale {
        let parts = values
            .iter()
            .map(|v| {
                let x2 = dot(v, v);
                (v.len(), if x2 > 0.0 { 1.0 / x2 } else { 1.0 })
            })
            .collect();
        Scale { parts }
    }

    /// Σ_f weight_f · a_f·b_f; a plain dot product where the lengths do
    /// not cover `a` (a value of another layout).
    pub fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        if self.parts.iter().map(|p| p.0).sum::<usize>() != a.len() {
            return dot(a, b);
        }
        let mut at = 0;
        let mut sum = 0.0;
        for &(len, w) in &self.parts {
            sum += w * dot(&a[at..at + len], &b[at..at + len]);
            at += len;
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: Limits = Limits {
        reused_windows: 0,
        max_columns: 10,
        filter: 1e-2,
    };

    /// On a linear H(x) = A x + b in n unknowns, IQN-ILS is a secant method
    /// that has the exact inverse Jacobian of the residual on the span of
    /// its columns: after n + 1 tries it sends the fixed point itself
    /// (Degroote et al. 2009, §3.2: the Broyden-like update is exact on
    /// the differences it has seen).
    #[test]
    fn iqn_ils_reaches_a_linear_fixed_point_in_n_plus_one_tries() {
        let a = [[-3.0, 1.0, 0.5], [0.2, -2.0, 0.3], [0.1, 0.4, -4.0]];
        let b = [1.0, 2.0, 3.0];
        let h = |x: &[f64]| -> Vec<f64> {
            (0..3)
                .map(|i| (0..3).map(|j| a[i][j] * x[j]).sum::<f64>() + b[i])
                .collect()
        };
        let mut cols = Columns::default();
        let mut sent = vec![0.0; 3];
        let (mut last_r, mut last_x): (Vec<f64>, Vec<f64>) = (vec![], vec![]);
        for k in 0..4 {
            let x = h(&sent);
            let r: Vec<f64> = x.iter().zip(&sent).map(|(x, s)| x - s).collect();
            if k > 0 {
                let dr = r.iter().zip(&last_r).map(|(a, b)| a - b).collect();
                let dx = x.iter().zip(&last_x).map(|(a, b)| a - b).collect();
                cols.push(dr, dx, 0, LIMITS);
            }
            sent = match cols.step(&r, LIMITS.filter) {
                Some((step, _)) => x.iter().zip(&step).map(|(x, s)| x + s).collect(),
                None => sent.iter().zip(&r).map(|(s, r)| s + 0.1 * r).collect(),
            };
            (last_r, last_x) = (r, x);
        }
        let residual: f64 = h(&sent)
            .iter()
            .zip(&sent)
            .map(|(x, s)| (x - s).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(residual < 1e-12, "‖H(x) − x‖ = {residual}");
    }

    /// A column parallel to a newer one is dropped; an independent one kept.
    #[test]
    fn the_filter_drops_a_column_dependent_on_newer_ones() {
        let mut cols = Columns::default();
        cols.push(vec![1.0, 0.0, 0.0], vec![0.0; 3], 0, LIMITS);
        cols.push(vec![0.0, 1.0, 0.0], vec![0.0; 3], 0, LIMITS);
        cols.push(vec![1.0, 1.0, 1e-4], vec![0.0; 3], 0, LIMITS);
        // Newest first: [1, 1, 1e-4] and [0, 1, 0] stay; [1, 0, 0] lies in
        // their span but for 1e-4 of its norm.
        assert_eq!(cols.filtered(1e-2), vec![0, 1]);
        assert_eq!(cols.filtered(1e-6), vec![0, 1, 2]);
    }
}
