//! How large a step a spring-mass model allows: the highest eigenfrequency
//! bound of dissertation eq. (3.7), computed from the model. The schemes'
//! stability intervals and the sub-step estimate built on it are the
//! coupler's (`scenario::stability`), re-exported here.

pub use scenario::stability::*;

/// Upper bound on the highest angular eigenfrequency [rad/s] of the spring
/// network, dissertation eq. (3.7) taken node by node: ω_max² ≤ max_i 2·Σ_j k_ij/m_i
/// over free nodes i (Gershgorin's theorem on M⁻¹K with axial stiffnesses).
/// With M neighbours of stiffness k and equal masses m this is eq. (3.7),
/// √(2Mk/m); node by node it stays tight when masses or stiffnesses vary.
/// Held nodes (1/m = 0) do not oscillate; 0 if no node is free and coupled.
pub fn omega_max(inv_mass: &[f64], couplings: &[(usize, usize, f64)]) -> f64 {
    let mut ksum = vec![0.0; inv_mass.len()];
    for &(i, j, k) in couplings {
        ksum[i] += k;
        ksum[j] += k;
    }
    ksum.iter()
        .zip(inv_mass)
        .map(|(k, w)| 2.0 * k * w)
        .fold(0.0, f64::max)
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bound_of_eq_3_7_holds_and_is_tight_on_a_uniform_chain() {
        // Fixed–fixed chain of n equal masses m and springs k: the exact
        // highest frequency is 2√(k/m)·sin(nπ/(2(n+1))) (e.g. Strang, Linear
        // Algebra and its Applications, §1.5), below eq. (3.7)'s √(2·2k/m).
        let (n, k, m) = (9usize, 50.0, 0.2);
        let mut inv_mass = vec![1.0 / m; n + 2];
        inv_mass[0] = 0.0;
        inv_mass[n + 1] = 0.0;
        let couplings: Vec<_> = (0..=n).map(|i| (i, i + 1, k)).collect();
        let bound = omega_max(&inv_mass, &couplings);
        let exact = 2.0
            * (k / m).sqrt()
            * (n as f64 * std::f64::consts::PI / (2.0 * (n as f64 + 1.0))).sin();
        assert!((bound - (4.0 * k / m).sqrt()).abs() < 1e-12 * bound);
        assert!(bound >= exact && bound < 1.02 * exact);
    }
}
