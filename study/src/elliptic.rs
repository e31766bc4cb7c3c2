//! Jacobi elliptic functions and the complete elliptic integral of the first
//! kind, by the arithmetic–geometric mean (Abramowitz & Stegun 1964, §16.4 and
//! §17.6). They give the undamped simple pendulum its exact motion.

/// The AGM sequence for parameter m = k²: the a_n and c_n of A&S 16.4.
fn agm(m: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut a, mut b, mut c) = (1.0, (1.0 - m).sqrt(), m.sqrt());
    let (mut aa, mut cc) = (vec![a], vec![c]);
    // Converges quadratically: a handful of rounds reach round-off.
    while c.abs() > f64::EPSILON * a && aa.len() < 64 {
        (a, b, c) = ((a + b) / 2.0, (a * b).sqrt(), (a - b) / 2.0);
        aa.push(a);
        cc.push(c);
    }
    (aa, cc)
}

/// K(m) = ∫₀^{π/2} dφ / √(1 − m sin²φ) = π / (2·AGM(1, √(1 − m))), A&S 17.6.
pub fn complete_k(m: f64) -> f64 {
    let (a, _) = agm(m);
    std::f64::consts::PI / (2.0 * a[a.len() - 1])
}

/// (sn, cn, dn)(u | m) by descending Landen transformation, A&S 16.4.3:
/// φ_N = 2ᴺ·a_N·u, then φ_{n−1} = (φ_n + asin(c_n/a_n · sin φ_n)) / 2, and
/// sn = sin φ₀, cn = cos φ₀.
pub fn sn_cn_dn(u: f64, m: f64) -> (f64, f64, f64) {
    let (a, c) = agm(m);
    let n = a.len() - 1;
    let mut phi = 2f64.powi(n as i32) * a[n] * u;
    for i in (1..=n).rev() {
        phi = (phi + (c[i] / a[i] * phi.sin()).asin()) / 2.0;
    }
    let (sn, cn) = phi.sin_cos();
    // dn > 0 for real u and m < 1 (A&S 16.9), and this form stays accurate
    // where A&S 16.4.3's cos φ₀ / cos(φ₁ − φ₀) is 0/0 (at u = K).
    (sn, cn, (1.0 - m * sn * sn).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn k_matches_tabulated_values() {
        // K(0) = π/2; K(1/2) = 1.854074677301372 (A&S table 17.1, m = 0.5).
        assert!((complete_k(0.0) - PI / 2.0).abs() < 1e-15);
        assert!((complete_k(0.5) - 1.854_074_677_301_372).abs() < 1e-14);
    }

    #[test]
    fn sn_cn_dn_obey_their_identities() {
        for m in [0.0, 0.1, 0.5, 0.9] {
            let k = complete_k(m);
            // sn(K) = 1, cn(K) = 0, dn(K) = √(1 − m) (A&S 16.5).
            let (s, c, d) = sn_cn_dn(k, m);
            assert!(
                (s - 1.0).abs() < 1e-14 && c.abs() < 1e-7 && (d - (1.0 - m).sqrt()).abs() < 1e-12
            );
            for u in [0.1, 0.7, 1.3, 2.9] {
                let (s, c, d) = sn_cn_dn(u, m);
                assert!((s * s + c * c - 1.0).abs() < 1e-14);
                assert!((d * d + m * s * s - 1.0).abs() < 1e-14);
            }
        }
        // m = 0: the circular functions.
        let (s, c, _) = sn_cn_dn(0.8, 0.0);
        assert!((s - 0.8f64.sin()).abs() < 1e-15 && (c - 0.8f64.cos()).abs() < 1e-15);
    }
}
