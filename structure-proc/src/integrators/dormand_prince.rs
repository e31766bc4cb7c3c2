//! Adaptive Dormand–Prince 5(4), beyond the dissertation and the thesis: the embedded Runge–Kutta
//! pair of Dormand & Prince (J. Comput. Appl. Math. 6, 19–26, 1980), as in
//! Hairer, Nørsett & Wanner, Solving ODEs I, §II.5 (table 5.2) and §II.4
//! (step control). Each call covers the step h with as many internal steps
//! as the error control needs: the fifth-order solution advances, the
//! fourth-order one estimates the local error, and the step size follows
//!   h_new = h·min(5, max(0.2, 0.9·err^(−1/5))),
//! err the largest |error| / (tol·(1 + |y|)) over positions and velocities.
//! The last accepted size is carried to the next call.

use super::*;

/// The Runge–Kutta matrix a_ij, row i. The stage times c_i are not needed:
/// the forces do not depend on t explicitly.
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    // The last stage sits at the fifth-order solution (first same as last).
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// Weights of the fifth-order solution: the last row of A, and 0.
const B: [f64; 7] = [A[6][0], A[6][1], A[6][2], A[6][3], A[6][4], A[6][5], 0.0];
/// Fifth- minus fourth-order weights: the local error estimate.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
/// Step-size factor limits and safety factor (Hairer et al. §II.4).
const GROW_MAX: f64 = 5.0;
const SHRINK_MAX: f64 = 0.2;
const SAFETY: f64 = 0.9;
/// An internal step below this fraction of the outer step gives up.
const SMALLEST: f64 = 1e-12;

pub struct DormandPrince {
    tolerance: f64,
    /// Internal step size to try next; 0 before the first call.
    h_next: f64,
    /// Internal steps accepted so far.
    accepted: u64,
    /// Stage velocities and forces, 7 each; stage state; trial state.
    vs: [Vec<f64>; 7],
    fs: [Vec<f64>; 7],
    xs: Vec<f64>,
    vt: Vec<f64>,
    reaction: Vec<f64>,
}

impl DormandPrince {
    pub fn new(tolerance: f64) -> DormandPrince {
        DormandPrince {
            tolerance,
            h_next: 0.0,
            accepted: 0,
            vs: Default::default(),
            fs: Default::default(),
            xs: Vec::new(),
            vt: Vec::new(),
            reaction: Vec::new(),
        }
    }

    /// One trial step of size h from (x, v), whose force is in fs[0]: the
    /// stages, the fifth-order state in (xs, vt) and the error norm.
    fn trial(&mut self, sys: &dyn System, h: f64, x: &[f64], v: &[f64]) -> f64 {
        let inv_mass = sys.inv_mass();
        let n = x.len();
        self.vs[0].copy_from_slice(v);
        for s in 1..7 {
            for d in 0..n {
                let w = inv_mass[d / 3];
                let (mut dx, mut dv) = (0.0, 0.0);
                for j in 0..s {
                    dx += A[s][j] * self.vs[j][d];
                    dv += A[s][j] * self.fs[j][d];
                }
                self.xs[d] = x[d] + h * dx;
                self.vt[d] = v[d] + h * dv * w;
            }
            sys.force(&self.xs, &self.vt, &mut self.fs[s]);
            self.vs[s].copy_from_slice(&self.vt);
        }
        // After stage 7, (xs, vt) is the fifth-order solution (row 7 of A = B).
        let tol = self.tolerance;
        let mut err: f64 = 0.0;
        for d in 0..n {
            let w = inv_mass[d / 3];
            let (mut ex, mut ev) = (0.0, 0.0);
            for j in 0..7 {
                ex += E[j] * self.vs[j][d];
                ev += E[j] * self.fs[j][d];
            }
            let sx = tol * (1.0 + x[d].abs().max(self.xs[d].abs()));
            let sv = tol * (1.0 + v[d].abs().max(self.vt[d].abs()));
            err = err.max((h * ex).abs() / sx).max((h * ev * w).abs() / sv);
        }
        if err.is_finite() {
            err
        } else {
            f64::INFINITY
        }
    }
}

impl Integrator for DormandPrince {
    /// The internal step size to try next, and the steps accepted so far
    /// (exact in an f64 below 2⁵³).
    fn save_history(&self, into: &mut Vec<f64>) {
        into.extend([self.h_next, self.accepted as f64]);
    }

    fn restore_history(&mut self, from: &[f64]) {
        if let [h_next, accepted] = *from {
            self.h_next = h_next;
            self.accepted = accepted as u64;
        }
    }

    fn step(
        &mut self,
        sys: &dyn System,
        h: f64,
        x: &mut [f64],
        v: &mut [f64],
    ) -> Result<(), StepError> {
        let n = x.len();
        for b in self.vs.iter_mut().chain(self.fs.iter_mut()) {
            b.resize(n, 0.0);
        }
        self.xs.resize(n, 0.0);
        self.vt.resize(n, 0.0);
        self.reaction.clear();
        self.reaction.resize(n, 0.0);
        if !(self.h_next > 0.0) {
            self.h_next = h;
        }
        sys.force(x, v, &mut self.fs[0]);
        let mut done = 0.0;
        while done < h {
            let remaining = h - done;
            let last = self.h_next >= remaining * (1.0 - 1e-12);
            let step = if last { remaining } else { self.h_next };
            // The last step may be a sliver left by the one before; only a
            // step the controller chose can be too small.
            if (!last && step < SMALLEST * h) || !step.is_finite() {
                return Err(StepError::StepTooSmall { step, time: done });
            }
            let err = self.trial(sys, step, x, v);
            let factor = if err == 0.0 {
                GROW_MAX
            } else {
                (SAFETY * err.powf(-0.2)).clamp(SHRINK_MAX, GROW_MAX)
            };
            if err > 1.0 {
                self.h_next = step * factor.min(1.0);
                continue;
            }
            // Accepted: held nodes take the impulse h·Σ bᵢfᵢ.
            let inv_mass = sys.inv_mass();
            for d in 0..n {
                if inv_mass[d / 3] == 0.0 {
                    self.reaction[d] += step * (0..7).map(|j| B[j] * self.fs[j][d]).sum::<f64>();
                }
            }
            x.copy_from_slice(&self.xs);
            v.copy_from_slice(&self.vt);
            let (first, rest) = self.fs.split_at_mut(1);
            first[0].copy_from_slice(&rest[5]); // first same as last
            self.accepted += 1;
            done += step;
            if last {
                done = h;
            }
            // Keep the controller's size, not the one cut to end the step.
            if !last || factor < 1.0 {
                self.h_next = step * factor;
            }
        }
        Ok(())
    }

    fn reaction(&self) -> &[f64] {
        &self.reaction
    }

    fn internal_steps(&self) -> Option<u64> {
        Some(self.accepted)
    }
}
