//! The numerical flux of the Euler equations along one line of cells,
//! reconstructed characteristic-wise by WENO5 (dissertation §3.2.1, eqs.
//! 3.15–3.17; Jiang & Shu, J. Comput. Phys. 126, 202–228, 1996, §2.4).
//!
//! At each face the states and fluxes of the six cells around it are
//! projected onto the characteristic fields of the Roe-averaged state
//! (w = LU, eq. 3.17), where the system is nearly three independent
//! advection equations. Each field's flux is split by Lax–Friedrichs into a
//! right-going part ½(g + αw) and a left-going part ½(g − αw), α being the
//! field's largest wave speed |λ| over those cells; each part is WENO5
//! reconstructed from its upwind side and the sum is taken back with R.
//! Reconstructing the fields instead of the conserved components is what
//! keeps a shock free of the oscillations a component-wise scheme leaves.

use crate::euler::gas::{Gas, State};
use crate::weno5::reconstruct;

/// Cells of a line's stencil beyond its ends (the ghosts the flux needs).
pub const REACH: usize = 3;

/// The fluxes at the faces of a line of rotated states (normal momentum
/// first, [`Gas::rotated`]): `line` holds the n cells with REACH ghosts at
/// each end, and `faces` receives the n + 1 face fluxes, face f lying
/// between cells f − 1 and f.
pub fn line_fluxes(gas: &Gas, line: &[State], faces: &mut [State]) {
    let n = line.len() - 2 * REACH;
    debug_assert_eq!(faces.len(), n + 1);
    let flux: Vec<State> = line.iter().map(|s| gas.flux(s)).collect();
    let speed: Vec<[f64; 5]> = line.iter().map(|s| gas.eigenvalues(s)).collect();
    for (f, out) in faces.iter_mut().enumerate() {
        // Cells f − 3 … f + 2 of the line, at f … f + 5 with the ghosts.
        let e = gas.roe_average(&line[f + 2], &line[f + 3]);
        let mut w = [[0.0; 5]; 6];
        let mut g = [[0.0; 5]; 6];
        let mut alpha = [0.0f64; 5];
        for k in 0..6 {
            w[k] = e.to_characteristic(&line[f + k]);
            g[k] = e.to_characteristic(&flux[f + k]);
            for (a, l) in alpha.iter_mut().zip(speed[f + k]) {
                *a = a.max(l.abs());
            }
        }
        let mut face = [0.0; 5];
        for s in 0..5 {
            let plus = |k: usize| 0.5 * (g[k][s] + alpha[s] * w[k][s]);
            let minus = |k: usize| 0.5 * (g[k][s] - alpha[s] * w[k][s]);
            face[s] =
                reconstruct([0, 1, 2, 3, 4].map(plus)) + reconstruct([5, 4, 3, 2, 1].map(minus));
        }
        *out = e.from_characteristic(&face);
    }
}
