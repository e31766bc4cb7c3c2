//! WENO5 reconstruction (dissertation §3.2.1; Jiang & Shu 1996): fifth order on
//! smooth data, and no new extremum at a jump.

use fluid_proc::weno5::reconstruct;
use std::f64::consts::PI;

/// L1 error of the interface values of sin(2πx + 1) reconstructed from its
/// exact cell averages on n periodic cells of [0, 1).
fn l1_error(n: usize) -> f64 {
    let h = 1.0 / n as f64;
    let k = 2.0 * PI;
    let avg = |i: isize| {
        let (a, b) = (i as f64 * h, (i + 1) as f64 * h);
        ((k * a + 1.0).cos() - (k * b + 1.0).cos()) / (k * h)
    };
    (0..n as isize)
        .map(|i| {
            let f = [avg(i - 2), avg(i - 1), avg(i), avg(i + 1), avg(i + 2)];
            let exact = (k * (i + 1) as f64 * h + 1.0).sin();
            (reconstruct(f) - exact).abs() * h
        })
        .sum()
}

#[test]
fn smooth_data_are_reconstructed_at_fifth_order() {
    // Halving h divides the error by 2⁵ = 32 once the weights are near
    // their optimal values; the observed order is above 4.7.
    let errors: Vec<f64> = [40, 80, 160, 320].iter().map(|&n| l1_error(n)).collect();
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(order > 4.7, "order {order:.2} from errors {errors:?}");
    }
}

#[test]
fn a_jump_makes_no_new_extremum() {
    // A step from 0 to 1 at every position in the stencil: the interface
    // value stays within [0, 1] to round-off (the essentially
    // non-oscillatory property), and next to the jump it takes the smooth
    // side's value to within 1e-4 (the candidate across the jump is
    // dropped).
    for at in 0..=5 {
        let f: [f64; 5] = std::array::from_fn(|i| if i < at { 0.0 } else { 1.0 });
        let q = reconstruct(f);
        assert!((-1e-12..=1.0 + 1e-12).contains(&q), "step at {at}: {q}");
    }
    // Flat on the left up to i, jump after: the value at i+½ is f_i's side.
    let q = reconstruct([0.0, 0.0, 0.0, 1.0, 1.0]);
    assert!(q.abs() < 1e-4, "left of the jump: {q}");
    let q = reconstruct([0.0, 0.0, 1.0, 1.0, 1.0]);
    assert!((q - 1.0).abs() < 1e-4, "right of the jump: {q}");
}
