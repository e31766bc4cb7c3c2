//! The classical fourth-order Runge–Kutta step of dissertation eq. (3.1), which
//! advances both the translation and the rotation of a body.

/// u(t + h) for u′ = L(u).
pub fn rk4<const N: usize>(u: &[f64; N], h: f64, l: impl Fn(&[f64; N]) -> [f64; N]) -> [f64; N] {
    let along = |k: &[f64; N], s: f64| std::array::from_fn(|i| u[i] + s * k[i]);
    let k1 = l(u);
    let k2 = l(&along(&k1, h / 2.0));
    let k3 = l(&along(&k2, h / 2.0));
    let k4 = l(&along(&k3, h));
    std::array::from_fn(|i| u[i] + h * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) / 6.0)
}
