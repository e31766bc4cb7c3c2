//! The Crank–Nicolson viscous term of eq. (3.18): the face Laplacian of one
//! velocity component, and the Helmholtz solve (I − αL)δ = b for the change
//! δ = u* − uⁿ over a step, with α = νΔt/2.
//!
//! δ is the difference of two fields with the same side velocities, so its
//! ghosts follow the homogeneous sides (`Side::homogeneous`): the operator
//! is then symmetric and positive definite (a mirrored ghost adds to the
//! diagonal, a copied one cancels), and conjugate gradients solve it. Its
//! condition number is below 1 + 4α·Σ1/h²: a few where the cells are
//! coarse for the viscosity (air around a parachute, the cavity), so no
//! preconditioner is used; a very viscous flow on fine cells takes more
//! iterations.
//!
//! On a graded grid (`metric.rs`) L is the finite-volume Laplacian, whose
//! rows scaled by the faces' control volumes are symmetric: the solve's dot
//! products then weigh each face by its control volume, the inner product
//! in which I − αL is self-adjoint.
//!
//! On a rank's slab (`part.rs`) the dot products are summed over the ranks
//! (each face counted by the one rank that updates it).

use crate::incompressible::metric::{AlongAxis, Metric};
use crate::incompressible::padded::Padded;
use crate::incompressible::rows;
use crate::incompressible::side::Sides;
use crate::layout::Layout;

/// out = L u = Σ_a (u₊ − 2u + u₋)/h_a² on the unknown faces (ghosts
/// filled), its finite-volume form along a graded axis.
pub fn laplacian(u: &Padded, metric: &Metric, out: &mut [f64]) {
    let lay = u.lay;
    let axes = Axes::of(metric, &lay, 1.0);
    let d = &u.data;
    rows::each(&lay, lay.unknown_box(), [out], |row, [o]| {
        let at = axes.row_indices(&lay, row.first);
        for i in 0..row.len {
            o[row.offset + i] = axes.sum(d, row.at + i, at, i);
        }
    });
}

/// The axes a component's Laplacian runs along (those with ghosts), each
/// with its stride, lengths and the factor the terms are scaled by.
struct Axes<'a> {
    axes: Vec<(usize, usize, &'a AlongAxis, f64, f64)>,
}

impl<'a> Axes<'a> {
    fn of(metric: &'a Metric, lay: &Layout, scale: f64) -> Axes<'a> {
        let axes = (0..3)
            .filter(|&a| lay.g[a] > 0)
            .map(|a| {
                let m = &metric.axes[a];
                (a, lay.stride[a], m, scale * m.uniform, scale)
            })
            .collect();
        Axes { axes }
    }

    /// The padded index along each axis of a row's first entry.
    #[inline(always)]
    fn row_indices(&self, lay: &Layout, first: [isize; 3]) -> [usize; 3] {
        [0, 1, 2].map(|a| (first[a] + lay.g[a] as isize) as usize)
    }

    /// Σ_a scale·L_a at entry p, the i-th of a row starting at `at`.
    #[inline(always)]
    fn sum(&self, d: &[f64], p: usize, at: [usize; 3], i: usize) -> f64 {
        (0..self.axes.len())
            .map(|t| self.term(t, d, p, at, i))
            .sum()
    }

    /// The term of the t-th axis: the uniform stencil's own operations
    /// where the axis is uniform.
    #[inline(always)]
    fn term(&self, t: usize, d: &[f64], p: usize, at: [usize; 3], i: usize) -> f64 {
        let (a, s, m, scaled, scale) = self.axes[t];
        match &m.weights {
            None => scaled * (d[p + s] - 2.0 * d[p] + d[p - s]),
            Some([lo, hi]) => {
                let k = at[a] + if a == 0 { i } else { 0 };
                scale * (hi[k] * (d[p + s] - d[p]) + lo[k] * (d[p - s] - d[p]))
            }
        }
    }
}

/// Why the viscous solve stopped.
#[derive(Debug, thiserror::Error)]
#[error("the viscous (Crank–Nicolson) solve of velocity component {component} did not converge in {iterations} iterations (relative residual {reached:e})")]
pub struct ViscousError {
    pub component: usize,
    pub iterations: usize,
    pub reached: f64,
}

/// Most conjugate-gradient iterations of one viscous solve: CG needs about
/// √κ·ln(2/tolerance)/2, some 200 at νΔt/h² = 100 (κ ≈ 400 in 2-D).
const MAX_ITERATIONS: usize = 1000;

/// Scratch for the solve of one component.
#[derive(Debug, Clone)]
pub struct Helmholtz {
    p: Padded,
    r: Vec<f64>,
    q: Vec<f64>,
}

impl Helmholtz {
    pub fn new(like: &Padded) -> Helmholtz {
        Helmholtz {
            p: like.clone(),
            r: vec![0.0; like.data.len()],
            q: vec![0.0; like.data.len()],
        }
    }

    /// Solves (I − αL)δ = b on the unknown faces to a relative residual of
    /// `tolerance`, from the guess in `delta`. Returns the iterations.
    pub fn solve(
        &mut self,
        sides: &Sides,
        metric: &Metric,
        alpha: f64,
        b: &[f64],
        delta: &mut Padded,
        tolerance: f64,
    ) -> Result<usize, ViscousError> {
        let homogeneous = sides.map(|s| s.map(|s| s.homogeneous()));
        let lay = delta.lay;
        let range = lay.unknown_box();
        let part = delta.part().clone();
        let weights = metric.graded.then_some(metric);
        let dot = |x: &[f64], y: &[f64]| part.sum(dot(&lay, range, x, y, weights));
        let norm_b = dot(b, b).sqrt();
        delta.fill_ghosts(&homogeneous);
        self.first_residual(metric, alpha, b, delta);
        let mut rr = dot(&self.r, &self.r);
        let goal = tolerance * norm_b;
        if norm_b == 0.0 {
            // Nothing changes over the step: δ = 0 exactly, whatever the guess.
            lay.for_box(range, |_, i| delta.data[i] = 0.0);
            return Ok(0);
        }
        if rr.sqrt() <= goal {
            return Ok(0);
        }
        let axes = Axes::of(metric, &lay, alpha);
        for it in 1..=MAX_ITERATIONS {
            self.p.fill_ghosts(&homogeneous);
            self.apply(&axes, lay, range);
            let step = rr / dot(&self.p.data, &self.q);
            if !step.is_finite() {
                return Err(ViscousError {
                    component: delta.c,
                    iterations: it,
                    reached: f64::NAN,
                });
            }
            self.advance(step, delta);
            let rr_new = dot(&self.r, &self.r);
            if rr_new.sqrt() <= goal {
                return Ok(it);
            }
            self.next_direction(rr_new / rr, lay);
            rr = rr_new;
        }
        Err(ViscousError {
            component: delta.c,
            iterations: MAX_ITERATIONS,
            reached: rr.sqrt() / norm_b,
        })
    }

    /// r = b − (I − αL)δ (δ's ghosts filled), and the first direction p = r.
    fn first_residual(&mut self, metric: &Metric, alpha: f64, b: &[f64], delta: &Padded) {
        let lay = delta.lay;
        laplacian(delta, metric, &mut self.q);
        let (q, d) = (&self.q, &delta.data);
        rows::each(
            &lay,
            lay.unknown_box(),
            [&mut self.r, &mut self.p.data],
            |row, [r, p]| {
                for i in 0..row.len {
                    let (at, o) = (row.at + i, row.offset + i);
                    r[o] = b[at] - (d[at] - alpha * q[at]);
                    p[o] = r[o];
                }
            },
        );
    }

    /// δ ← δ + step·p and r ← r − step·q.
    fn advance(&mut self, step: f64, delta: &mut Padded) {
        let lay = delta.lay;
        let (p, q) = (&self.p.data, &self.q);
        rows::each(
            &lay,
            lay.unknown_box(),
            [&mut delta.data, &mut self.r],
            |row, [d, r]| {
                for i in 0..row.len {
                    let (at, o) = (row.at + i, row.offset + i);
                    d[o] += step * p[at];
                    r[o] -= step * q[at];
                }
            },
        );
    }

    /// p ← r + β·p.
    fn next_direction(&mut self, beta: f64, lay: Layout) {
        let r = &self.r;
        rows::each(&lay, lay.unknown_box(), [&mut self.p.data], |row, [p]| {
            for i in 0..row.len {
                let o = row.offset + i;
                p[o] = r[row.at + i] + beta * p[o];
            }
        });
    }

    /// q = (I − αL)p on this rank's unknowns (`axes`: the Laplacian's axes
    /// scaled by α).
    fn apply(&mut self, axes: &Axes, lay: Layout, range: [[isize; 2]; 3]) {
        let p = &self.p.data;
        rows::each(&lay, range, [&mut self.q], |row, [q]| {
            let first = axes.row_indices(&lay, row.first);
            for i in 0..row.len {
                let at = row.at + i;
                let mut v = p[at];
                for t in 0..axes.axes.len() {
                    v -= axes.term(t, p, at, first, i);
                }
                q[row.offset + i] = v;
            }
        })
    }
}

/// This rank's x·y over the box `range`, each entry weighed by its control
/// volume where `metric` is given (a graded grid): on one thread in the
/// grid's order (`rows.rs` says why).
fn dot(lay: &Layout, range: [[isize; 2]; 3], x: &[f64], y: &[f64], metric: Option<&Metric>) -> f64 {
    let mut s = 0.0;
    match metric {
        None => lay.for_box(range, |_, p| s += x[p] * y[p]),
        Some(m) => lay.for_box(range, |f, p| s += x[p] * y[p] * m.volume(lay, f)),
    }
    s
}
