//! Kang's fast approximated implicit method, thesis eqs. (52)–(57) (Kang, Choi,
//! Cho & Lee 2000). Backward Euler needs (M + Δt²K)⁻¹; Kang replaces it by one
//! Jacobi-like sweep over the spring graph:
//!   Δv_i = (F_i Δt + Δt² Σ_j k_ij F_j Δt/(m_j + Δt² K_j)) / (m_i + Δt² K_i),
//! with K_i = Σ_j k_ij (eq. 55 writes k·n_i for uniform k). Then v and x advance
//! as eqs. (56)–(57). First order and very dissipative, but stable at large steps.
//! Held nodes (1/m = 0) count as infinitely heavy and contribute nothing.

use super::*;

#[derive(Default)]
pub struct Kang(Work<3>);

impl Integrator for Kang {
    fn step(
        &mut self,
        sys: &dyn System,
        h: f64,
        x: &mut [f64],
        v: &mut [f64],
    ) -> Result<(), StepError> {
        // f; Σ_j k_ij per node (first n/3 entries); Σ_j k_ij F_j Δt/(m_j + Δt² K_j) per dof.
        let ([f, ksum, neighbour], reaction) = self.0.begin(x.len());
        ksum.fill(0.0);
        neighbour.fill(0.0);
        let inv_mass = sys.inv_mass();
        sys.force(x, v, f); // (52)–(54)
        for &(i, j, k) in sys.couplings() {
            ksum[i] += k;
            ksum[j] += k;
        }
        // F_j Δt/(m_j + Δt² K_j), zero for held nodes.
        let relaxed = |node: usize, c: usize| {
            let w = inv_mass[node];
            if w == 0.0 {
                0.0
            } else {
                f[3 * node + c] * h / (1.0 / w + h * h * ksum[node])
            }
        };
        for &(i, j, k) in sys.couplings() {
            for c in 0..3 {
                neighbour[3 * i + c] += k * relaxed(j, c);
                neighbour[3 * j + c] += k * relaxed(i, c);
            }
        }
        for (d, vd) in v.iter_mut().enumerate() {
            let w = inv_mass[d / 3];
            if w == 0.0 {
                reaction[d] = h * f[d];
                continue;
            }
            let dv = (f[d] * h + h * h * neighbour[d]) / (1.0 / w + h * h * ksum[d / 3]); // (55)
            *vd += dv; // (56)
        }
        drift(x, v, h); // (57)
        Ok(())
    }

    fn reaction(&self) -> &[f64] {
        &self.0.reaction
    }
}
