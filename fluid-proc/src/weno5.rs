//! Fifth-order WENO reconstruction (Jiang & Shu, J. Comput. Phys. 126,
//! 202–228, 1996), the reconstruction of dissertation §3.2.1: the value at the
//! interface i+½ from the five cell values i−2…i+2, upwind from the left.
//! Three third-order candidates are blended with weights that tend to the
//! optimal (1/10, 6/10, 3/10) where the data are smooth, giving fifth order,
//! and drop a candidate whose stencil holds a jump, so no oscillation grows.

/// Keeps the weights finite on flat data (Jiang & Shu's value).
const EPSILON: f64 = 1e-6;

/// The left-biased value at i+½ from `f = [f_{i−2}, f_{i−1}, f_i, f_{i+1}, f_{i+2}]`.
/// For the right-biased value at i−½, pass the five values in reverse order.
pub fn reconstruct(f: [f64; 5]) -> f64 {
    let [a, b, c, d, e] = f;
    // Candidates on {i−2, i−1, i}, {i−1, i, i+1}, {i, i+1, i+2}.
    let q0 = (2.0 * a - 7.0 * b + 11.0 * c) / 6.0;
    let q1 = (-b + 5.0 * c + 2.0 * d) / 6.0;
    let q2 = (2.0 * c + 5.0 * d - e) / 6.0;
    // Smoothness indicators (Jiang & Shu eq. 3.2).
    let s0 = 13.0 / 12.0 * (a - 2.0 * b + c).powi(2) + 0.25 * (a - 4.0 * b + 3.0 * c).powi(2);
    let s1 = 13.0 / 12.0 * (b - 2.0 * c + d).powi(2) + 0.25 * (b - d).powi(2);
    let s2 = 13.0 / 12.0 * (c - 2.0 * d + e).powi(2) + 0.25 * (3.0 * c - 4.0 * d + e).powi(2);
    let w0 = 0.1 / (EPSILON + s0).powi(2);
    let w1 = 0.6 / (EPSILON + s1).powi(2);
    let w2 = 0.3 / (EPSILON + s2).powi(2);
    (w0 * q0 + w1 * q1 + w2 * q2) / (w0 + w1 + w2)
}
