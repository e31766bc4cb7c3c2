//! The time integrators of thesis §2.4 plus backward Euler, each implemented
//! once against [`Integrator`] and used by every scene.
//!
//! An integrator advances the flat state (x, v) of a [`System`]. Nodes with
//! 1/m = 0 are not accelerated: fixed nodes keep v = 0 and attached nodes keep
//! the constant velocity of their rigid body, so every scheme carries them
//! exactly. The force on those nodes is what the structure exerts on whatever
//! holds them; integrated over the step with the scheme's own velocity weights it
//! is the step's [`Integrator::reaction`], the impulse sent to rigid-proc.

mod backward_euler;
mod block_sparse;
mod cg;
mod cholesky;
mod dormand_prince;
mod euler_cromer;
mod euler_richardson;
mod explicit_euler;
mod improved_euler;
mod kang;
mod multigrid;
mod newmark;
mod newton;
mod rk4;
mod velocity_verlet;

use crate::forces::assembly::GRAIN;
pub use crate::system::System;
pub use newton::extent;
use rayon::prelude::*;
pub use structure_section::{NewtonParams, Scheme};

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    #[error("Newton iterations did not converge in {iterations} iterations (last correction {correction:.3e} m)")]
    NoConvergence { iterations: u32, correction: f64 },
    #[error("a non-finite value appeared in the Newton iterations")]
    NonFinite,
    #[error("the adaptive step fell to {step:.3e} s, {time:.3e} s into the step: the error tolerance cannot be met")]
    StepTooSmall { step: f64, time: f64 },
    #[error("the GPU failed: {0}")]
    Device(String),
}

pub trait Integrator: Send {
    /// Advance `x`, `v` of `sys` by one step `h`.
    fn step(
        &mut self,
        sys: &dyn System,
        h: f64,
        x: &mut [f64],
        v: &mut [f64],
    ) -> Result<(), StepError>;

    /// Impulse ∫F dt [N·s] of the last step on the nodes with 1/m = 0 (3 per node, 0 elsewhere).
    fn reaction(&self) -> &[f64];

    /// Internal steps taken so far, for schemes that choose their own (adaptive ones).
    fn internal_steps(&self) -> Option<u64> {
        None
    }

    /// The Newton iterations' linear solves so far and the seconds they
    /// took (each with its correction's bookkeeping), for implicit schemes.
    fn linear_solves(&self) -> Option<(u64, f64)> {
        None
    }

    /// Append to `into` what the next step reads beyond (x, v): the
    /// history a repeated window must start from (see `checkpoint.rs`).
    /// Nothing for one-step schemes whose buffers are only scratch.
    fn save_history(&self, into: &mut Vec<f64>) {
        let _ = into;
    }

    /// Take back the history [`save_history`](Self::save_history) wrote.
    fn restore_history(&mut self, from: &[f64]) {
        let _ = from;
    }
}

/// The integrator for `scheme`.
pub fn integrator(scheme: Scheme) -> Box<dyn Integrator> {
    match scheme {
        Scheme::ExplicitEuler => Box::<explicit_euler::ExplicitEuler>::default(),
        Scheme::EulerCromer => Box::<euler_cromer::EulerCromer>::default(),
        Scheme::EulerRichardson => Box::<euler_richardson::EulerRichardson>::default(),
        Scheme::ImprovedEuler => Box::<improved_euler::ImprovedEuler>::default(),
        Scheme::VelocityVerlet => Box::<velocity_verlet::VelocityVerlet>::default(),
        Scheme::Rk4 => Box::<rk4::Rk4>::default(),
        Scheme::Kang => Box::<kang::Kang>::default(),
        Scheme::Newmark {
            beta,
            gamma,
            alpha,
            newton,
        } => Box::new(newmark::Newmark::new(beta, gamma, alpha, newton)),
        Scheme::BackwardEuler { newton } => Box::new(backward_euler::BackwardEuler::new(newton)),
        Scheme::DormandPrince { tolerance } => {
            Box::new(dormand_prince::DormandPrince::new(tolerance))
        }
    }
}

/// The global order of accuracy a scheme should show on smooth problems.
pub fn theoretical_order(scheme: Scheme) -> u32 {
    match scheme {
        Scheme::ExplicitEuler
        | Scheme::EulerCromer
        | Scheme::Kang
        | Scheme::BackwardEuler { .. } => 1,
        Scheme::EulerRichardson | Scheme::ImprovedEuler | Scheme::VelocityVerlet => 2,
        // γ = 1/2 gives second order; any other γ, first (thesis §2.4.5).
        Scheme::Newmark { gamma, alpha, .. } => {
            if (gamma - 0.5 + alpha).abs() < 1e-12 {
                2
            } else {
                1
            }
        }
        Scheme::Rk4 => 4,
        Scheme::DormandPrince { .. } => 5,
    }
}

/// Work arrays of a scheme and the reaction of its last step.
pub struct Work<const K: usize> {
    bufs: [Vec<f64>; K],
    reaction: Vec<f64>,
}

impl<const K: usize> Default for Work<K> {
    fn default() -> Self {
        Work {
            bufs: std::array::from_fn(|_| Vec::new()),
            reaction: Vec::new(),
        }
    }
}

impl<const K: usize> Work<K> {
    /// Start a step on `len` values: K work arrays (contents unspecified) and a zero reaction.
    fn begin(&mut self, len: usize) -> (&mut [Vec<f64>; K], &mut [f64]) {
        for b in &mut self.bufs {
            b.resize(len, 0.0);
        }
        self.reaction.clear();
        self.reaction.resize(len, 0.0);
        (&mut self.bufs, &mut self.reaction)
    }
}

// The vector updates below run in parallel over nodes; each value is computed
// alone, so the result does not depend on the number of threads.

/// v ← v + h·f/m; where 1/m = 0, the impulse h·f goes to `reaction` instead.
fn kick(v: &mut [f64], f: &[f64], inv_mass: &[f64], h: f64, reaction: &mut [f64]) {
    v.par_chunks_exact_mut(3)
        .zip(reaction.par_chunks_exact_mut(3))
        .enumerate()
        .with_min_len(GRAIN)
        .for_each(|(n, (vn, rn))| {
            let w = inv_mass[n];
            for c in 0..3 {
                if w == 0.0 {
                    rn[c] += h * f[3 * n + c];
                } else {
                    vn[c] += h * f[3 * n + c] * w;
                }
            }
        });
}

/// A kick of `hk` and then a drift of `hd` in one pass over the nodes: the
/// same values as [`kick`] and then [`drift`], without a second pass over v.
fn kick_drift(
    x: &mut [f64],
    v: &mut [f64],
    f: &[f64],
    inv_mass: &[f64],
    (hk, hd): (f64, f64),
    reaction: &mut [f64],
) {
    let chunk = 3 * GRAIN;
    x.par_chunks_mut(chunk)
        .zip(v.par_chunks_mut(chunk))
        .zip(reaction.par_chunks_mut(chunk))
        .zip(f.par_chunks(chunk).zip(inv_mass.par_chunks(GRAIN)))
        .for_each(|(((x, v), r), (f, w))| {
            let nodes = x.chunks_exact_mut(3).zip(v.chunks_exact_mut(3));
            let loads = r.chunks_exact_mut(3).zip(f.chunks_exact(3)).zip(w);
            for ((xn, vn), ((rn, fn_), &w)) in nodes.zip(loads) {
                if w == 0.0 {
                    for c in 0..3 {
                        rn[c] += hk * fn_[c];
                    }
                } else {
                    for c in 0..3 {
                        vn[c] += hk * fn_[c] * w;
                    }
                }
                for c in 0..3 {
                    xn[c] += hd * vn[c];
                }
            }
        });
}

/// out ← v + h·f/m (velocity after a trial kick; held nodes keep theirs).
fn kicked(out: &mut [f64], v: &[f64], f: &[f64], inv_mass: &[f64], h: f64) {
    out.par_chunks_exact_mut(3)
        .enumerate()
        .with_min_len(GRAIN)
        .for_each(|(n, o)| {
            for c in 0..3 {
                o[c] = v[3 * n + c] + h * f[3 * n + c] * inv_mass[n];
            }
        });
}

/// out ← x + h·v.
fn advanced(out: &mut [f64], x: &[f64], v: &[f64], h: f64) {
    out.par_iter_mut()
        .zip(x.par_iter().zip(v))
        .with_min_len(3 * GRAIN)
        .for_each(|(o, (xi, vi))| *o = xi + h * vi);
}

/// x ← x + h·v.
fn drift(x: &mut [f64], v: &[f64], h: f64) {
    x.par_iter_mut()
        .zip(v.par_iter())
        .with_min_len(3 * GRAIN)
        .for_each(|(xi, vi)| *xi += h * vi);
}
