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
//! On a rank's slab (`part.rs`) the dot products are summed over the ranks
//! (each face counted by the one rank that updates it).

use crate::incompressible::padded::Padded;
use crate::incompressible::rows;
use crate::incompressible::side::Sides;
use crate::layout::Layout;

/// out = L u = Σ_a (u₊ − 2u + u₋)/h_a² on the unknown faces (ghosts filled).
pub fn laplacian(u: &Padded, h: [f64; 3], out: &mut [f64]) {
    let lay = u.lay;
    let w = h.map(|h| 1.0 / (h * h));
    let axes: Vec<(usize, f64)> = (0..3)
        .filter(|&a| lay.g[a] > 0)
        .map(|a| (lay.stride[a], w[a]))
        .collect();
    let d = &u.data;
    rows::each(&lay, lay.unknown_box(), [out], |row, [o]| {
        for i in 0..row.len {
            let p = row.at + i;
            o[row.offset + i] = axes
                .iter()
                .map(|&(s, w)| w * (d[p + s] - 2.0 * d[p] + d[p - s]))
                .sum();
        }
    });
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
        h: [f64; 3],
        alpha: f64,
        b: &[f64],
        delta: &mut Padded,
        tolerance: f64,
    ) -> Result<usize, ViscousError> {
        let homogeneous = sides.map(|s| s.map(|s| s.homogeneous()));
        let lay = delta.lay;
        let range = lay.unknown_box();
        let part = delta.part().clone();
        let dot = |x: &[f64], y: &[f64]| part.sum(dot(&lay, range, x, y));
        let norm_b = dot(b, b).sqrt();
        delta.fill_ghosts(&homogeneous);
        self.first_residual(h, alpha, b, delta);
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
        let w = h.map(|h| 1.0 / (h * h));
        let axes: Vec<(usize, f64)> = (0..3)
            .filter(|&a| lay.g[a] > 0)
            .map(|a| (lay.stride[a], alpha * w[a]))
            .collect();
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
    fn first_residual(&mut self, h: [f64; 3], alpha: f64, b: &[f64], delta: &Padded) {
        let lay = delta.lay;
        laplacian(delta, h, &mut self.q);
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

    /// q = (I − αL)p on this rank's unknowns (`axes`: each axis's stride and
    /// α/h²).
    fn apply(&mut self, axes: &[(usize, f64)], lay: Layout, range: [[isize; 2]; 3]) {
        let p = &self.p.data;
        rows::each(&lay, range, [&mut self.q], |row, [q]| {
            for i in 0..row.len {
                let at = row.at + i;
                let mut v = p[at];
                for &(s, aw) in axes {
                    v -= aw * (p[at + s] - 2.0 * p[at] + p[at - s]);
                }
                q[row.offset + i] = v;
            }
        })
    }
}

/// This rank's x·y over the box `range`, on one thread in the grid's order
/// (`rows.rs` says why).
fn dot(lay: &Layout, range: [[isize; 2]; 3], x: &[f64], y: &[f64]) -> f64 {
    let mut s = 0.0;
    lay.for_box(range, |_, p| s += x[p] * y[p]);
    s
}
