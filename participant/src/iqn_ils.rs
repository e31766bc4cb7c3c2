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
//! the least-squares problem solved from the Gram matrix VᵀV, which is
//! kept up to date as columns come and go (a new column costs one dot
//! product with each kept one, n·m operations, where a QR decomposition
//! of V at every try costs 2n·m²): its Cholesky factor over the kept
//! columns is the R of V's QR decomposition (`joint.rs`,
//! [`Share::coefficients`]). Columns that are nearly dependent on newer
//! ones are dropped first (the QR2 filter of Haelterman et al. 2016: a
//! column whose part orthogonal to the newer kept ones is below
//! `filter`·its norm), since they would make R ill-conditioned. The
//! filter bounds how nearly dependent the kept columns are, which is what
//! keeps forming VᵀV (whose condition is R's squared) harmless here: the
//! tests check the step against a QR decomposition of V, and the shipped
//! implicit scenes take the tries they took with one (docs/src/parachutes-in-flow.md,
//! "At the original code's resolution").

use crate::joint::Share;

/// The columns kept, newest first, each with the window it came from, and
/// their Gram matrix in the inner product `scale`.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Columns {
    v: Vec<Vec<f64>>,
    w: Vec<Vec<f64>>,
    windows: Vec<u64>,
    /// gram[i][j] = v_i·S v_j, in step with `v` (empty in a checkpoint of
    /// an older version: computed again when first needed).
    #[serde(default)]
    gram: Vec<Vec<f64>>,
    #[serde(default)]
    scale: Scale,
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
        self.update_gram();
        let row: Vec<f64> = std::iter::once(self.scale.dot(&dr, &dr))
            .chain(self.v.iter().map(|v| self.scale.dot(&dr, v)))
            .collect();
        for (g, d) in self.gram.iter_mut().zip(&row[1..]) {
            g.insert(0, *d);
        }
        self.gram.insert(0, row);
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
        self.gram.truncate(keep);
        self.gram.iter_mut().for_each(|g| g.truncate(keep));
    }

    /// Forget columns of a value of another length (a mesh that changed),
    /// keeping the inner product.
    pub fn fit(&mut self, len: usize) {
        if self.v.first().is_some_and(|c| c.len() != len) {
            let scale = std::mem::take(&mut self.scale);
            *self = Columns {
                scale,
                ..Columns::default()
            };
        }
    }

    /// Measure the columns in the inner product `scale` from now on.
    pub fn rescale(&mut self, scale: &Scale) {
        if *scale != self.scale {
            self.scale = scale.clone();
            self.gram.clear();
        }
    }

    /// The Gram matrix computed afresh where it is not in step with the
    /// columns (a new scale, an older checkpoint). Each entry is the dot
    /// product of the newer column with the older, as a push computes it,
    /// so a matrix computed afresh has the same bits.
    fn update_gram(&mut self) {
        if self.gram.len() == self.v.len() {
            return;
        }
        let m = self.v.len();
        self.gram = vec![vec![0.0; m]; m];
        for i in 0..m {
            for j in i..m {
                let d = self.scale.dot(&self.v[i], &self.v[j]);
                (self.gram[i][j], self.gram[j][i]) = (d, d);
            }
        }
    }

    /// The quasi-Newton step for residual `r`, c = argmin ‖V c + r‖₂ over
    /// the columns the filter keeps ([`Columns::step_from`]); None when it
    /// keeps none. Also returns how many it used.
    pub fn step(&mut self, r: &[f64], filter: f64, complement: f64) -> Option<(Vec<f64>, usize)> {
        let m = self.count();
        let share = Share {
            columns: m,
            gram: self.gram(),
            against: self.against(r),
            ..Share::default()
        };
        let (kept, c) = share.coefficients(filter)?;
        Some((self.step_from(&kept, &c, r, complement), kept.len()))
    }

    /// The step added to the answer x_k, from the coefficients `c` of the
    /// columns `kept`: W c − (1 − ω)(r + V c), ω = `complement`.
    ///
    /// r + V c is the part of the residual the columns do not explain.
    /// Plain IQN-ILS (ω = 1, preCICE's) takes it whole: x̃_{k+1} = x̃_k +
    /// (r + V c) + (W − V) c, an inverse Jacobian of −I off the columns'
    /// span. A mode the columns have not learnt then iterates as plain
    /// fixed-point iteration, which strong added mass makes diverge: a
    /// fabric mode whose air weighs μ times its cloth answers H′ ≈ −μ
    /// (Causin, Gerbeau & Nobile 2005), amplified by 1 − ω(1 + μ) a try,
    /// so by μ at ω = 1, and damped only for ω < 2/(1 + μ). IQN-ILS is
    /// Anderson acceleration, and ω its mixing parameter β (Walker & Ni
    /// 2011, §1): the inverse Jacobian −ω·I off the columns' span, the
    /// same relaxation IQN-ILS starts a window with.
    pub fn step_from(&self, kept: &[usize], c: &[f64], r: &[f64], complement: f64) -> Vec<f64> {
        let mut step = self.combine(kept, c);
        if complement != 1.0 {
            let explained = weighted(&self.v, kept, c);
            for ((s, r), e) in step.iter_mut().zip(r).zip(&explained) {
                *s -= (1.0 - complement) * (r + e);
            }
        }
        step
    }

    /// How many columns are kept.
    pub fn count(&self) -> usize {
        self.v.len()
    }

    /// W c over the columns `kept` (indices, newest first), c[j] the
    /// weight of column kept[j].
    pub fn combine(&self, kept: &[usize], c: &[f64]) -> Vec<f64> {
        weighted(&self.w, kept, c)
    }

    /// The Gram matrix VᵀSV of the columns, row-major m×m.
    pub fn gram(&mut self) -> Vec<f64> {
        self.update_gram();
        self.gram.concat()
    }

    /// VᵀS r.
    pub fn against(&self, r: &[f64]) -> Vec<f64> {
        self.v.iter().map(|v| self.scale.dot(v, r)).collect()
    }
}

/// Σⱼ c[j]·columns[kept[j]].
fn weighted(columns: &[Vec<f64>], kept: &[usize], c: &[f64]) -> Vec<f64> {
    let mut sum = vec![0.0; columns.first().map_or(0, Vec::len)];
    for (&col, c) in kept.iter().zip(c) {
        for (s, w) in sum.iter_mut().zip(&columns[col]) {
            *s += c * w;
        }
    }
    sum
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
            sent = match cols.step(&r, LIMITS.filter, 1.0) {
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
        let kept = |filter: f64| {
            let share = Share {
                columns: 3,
                gram: cols.clone().gram(),
                against: vec![1.0; 3],
                ..Share::default()
            };
            share.coefficients(filter).unwrap().0
        };
        assert_eq!(kept(1e-2), vec![0, 1]);
        assert_eq!(kept(1e-6), vec![0, 1, 2]);
    }

    /// The Gram matrix kept up to date through pushes and truncations has
    /// the bits of one computed afresh, in a scaled product too.
    #[test]
    fn the_gram_matrix_kept_in_step_is_the_one_computed_afresh() {
        let limits = Limits {
            max_columns: 3,
            ..LIMITS
        };
        let mut cols = Columns::default();
        cols.rescale(&Scale {
            parts: vec![(2, 0.5), (2, 4.0)],
        });
        for k in 0..5 {
            let c: Vec<f64> = (0..4).map(|i| ((k * 7 + i * 3) % 5) as f64 - 1.7).collect();
            cols.push(c.clone(), c, 0, limits);
        }
        let kept = cols.gram();
        cols.gram.clear();
        assert_eq!(cols.gram(), kept);
        assert_eq!(cols.count(), 3);
    }
}
