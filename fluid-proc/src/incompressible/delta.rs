//! Peskin's 4-point discrete delta function, the smoothed δ of the dissertation
//! eq. (3.25) that spreads a force at a point of a surface to the grid and
//! interpolates the grid velocity back to the point.
//!
//! φ(r) = (3 − 2|r| + √(1 + 4|r| − 4r²))/8      for |r| ≤ 1,
//!        (5 − 2|r| − √(−7 + 12|r| − 4r²))/8     for 1 ≤ |r| ≤ 2,
//!        0                                     beyond,
//! Peskin, "The immersed boundary method", Acta Numerica 11, 479–517
//! (2002), eq. (6.27). On a lattice of spacing h, δ_h(x) = Π_d φ(x_d/h_d)/h_d.
//! It is built to satisfy, for every shift r, Σ_j φ(r − j) = 1 (nothing
//! lost in spreading), Σ_j (r − j)φ(r − j) = 0 (no spurious torque), the
//! even and odd sums ½ each (no checkerboard), and Σ_j φ(r − j)² = 3/8
//! (interaction independent of the point's place on the lattice).

/// Lattice points a point's kernel touches along one axis.
pub const WIDTH: usize = 4;

/// φ(r) of eq. (6.27).
pub fn phi(r: f64) -> f64 {
    let r = r.abs();
    if r <= 1.0 {
        (3.0 - 2.0 * r + (1.0 + 4.0 * r - 4.0 * r * r).sqrt()) / 8.0
    } else if r <= 2.0 {
        (5.0 - 2.0 * r - (-7.0 + 12.0 * r - 4.0 * r * r).max(0.0).sqrt()) / 8.0
    } else {
        0.0
    }
}

/// The lattice points near `r` (a position in units of the spacing, the
/// lattice at the integers) and their weights: points `first + j` for
/// j < WIDTH, weights φ(r − first − j).
pub fn stencil(r: f64) -> (i64, [f64; WIDTH]) {
    let first = r.floor() as i64 - 1;
    let w = std::array::from_fn(|j| phi(r - (first + j as i64) as f64));
    (first, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Peskin (2002) §6: the moment conditions hold for every shift, to
    /// round-off; they are what makes spreading conserve force and torque.
    #[test]
    fn moment_conditions_hold_for_every_shift() {
        for k in 0..=100 {
            let r = 7.0 + k as f64 / 100.0;
            let (first, w) = stencil(r);
            let at = |j: usize| (first + j as i64) as f64;
            let sum: f64 = w.iter().sum();
            let first_moment: f64 = (0..WIDTH).map(|j| (r - at(j)) * w[j]).sum();
            let even: f64 = (0..WIDTH)
                .filter(|j| (first + *j as i64) % 2 == 0)
                .map(|j| w[j])
                .sum();
            let squares: f64 = w.iter().map(|w| w * w).sum();
            assert!((sum - 1.0).abs() < 1e-14, "Σφ = {sum} at r = {r}");
            assert!(first_moment.abs() < 1e-14, "Σ(r − j)φ = {first_moment}");
            assert!((even - 0.5).abs() < 1e-14, "even sum {even}");
            assert!((squares - 3.0 / 8.0).abs() < 1e-14, "Σφ² = {squares}");
        }
    }

    /// φ is continuous where its two pieces meet and at its support's end:
    /// φ(0) = 1/2, φ(1) = 1/4 from both sides, φ(2) = 0, so that the
    /// lattice sum at r = 0 is ½ + 2·¼ = 1.
    #[test]
    fn pieces_meet() {
        let e = 1e-12;
        assert!((phi(1.0 - e) - 0.25).abs() < 1e-6);
        assert!((phi(1.0 + e) - 0.25).abs() < 1e-6);
        assert!(phi(2.0 - e).abs() < 1e-6);
        assert!((phi(0.0) - 0.5).abs() < 1e-15);
    }
}
