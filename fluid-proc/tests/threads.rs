//! The incompressible step on the pool's threads gives the same field to
//! the bit on any number of them (issue 43, item 5): every loop writes
//! disjoint rows, red–black Gauss–Seidel updates one colour from the other
//! only (across the wrap of an odd periodic axis, in seam phases), every sum is taken on one thread in the grid's order
//! (`rows.rs`), and the three components' predictions run side by side,
//! each writing its own arrays (`component.rs`, `by_component`: the
//! box's 8 640 cells are above the size from which they do). The field is also checked for what the projection
//! promises: discretely divergence-free (dissertation eq. 3.19) to the
//! pressure solve's tolerance.

use fluid_proc::incompressible::grid::Grid;
use fluid_proc::incompressible::side::{bcs, Side};
use fluid_proc::incompressible::{FlowSetup, Incompressible};

/// A lid-driven box of 24 × 20 × 18 cells (lid 1 m/s, ν = 0.01 m²/s).
fn lid_driven() -> ([usize; 3], [[Side; 2]; 3]) {
    let mut sides = [[Side::WALL; 2]; 3];
    sides[2][1] = Side::Velocity([1.0, 0.0, 0.0]);
    ([24, 20, 18], sides)
}

/// A periodic box of 16 × 15 × 37 cells: odd across y and z, where the
/// last line of each axis touches the first of the same colour across the
/// wrap, and 555 lines, enough for the smoother to share them out.
fn odd_periodic() -> ([usize; 3], [[Side; 2]; 3]) {
    ([16, 15, 37], [[Side::Periodic; 2]; 3])
}

/// The box `(n, sides)` (ν = 0.01 m²/s) from a swirl that fills it, after
/// five steps at Courant number 0.4 (of 1 m/s) on `threads` threads: the
/// velocity on every face and the pressure.
fn steps_on(
    threads: usize,
    (n, sides): ([usize; 3], [[Side; 2]; 3]),
) -> (Vec<Vec<f64>>, Vec<f64>, f64) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    pool.install(|| {
        let mut flow = Incompressible::new(FlowSetup {
            grid: Grid::uniform(n, n.map(|n| 1.0 / n as f64), bcs(&sides)),
            sides,
            density: 1.0,
            nu: 0.01,
        });
        for (d, u) in flow.u.u.iter_mut().enumerate() {
            for (f, v) in u.iter_mut().enumerate() {
                *v = 0.3 * ((f * (d + 3)) as f64 * 0.37).sin();
            }
        }
        flow.impose_sides();
        for _ in 0..5 {
            flow.step(0.4 / n[0] as f64).expect("a stable step");
        }
        (flow.u.u.to_vec(), flow.pressure(), flow.max_divergence())
    })
}

#[test]
fn a_step_is_the_same_to_the_bit_on_one_two_and_three_threads() {
    same_on_one_two_and_three_threads(lid_driven());
}

/// The same where the red–black smoother's colours meet across the wraps
/// of odd periodic axes (`laplacian.rs`, its seam phases).
#[test]
fn a_step_across_odd_periodic_wraps_is_the_same_to_the_bit_on_any_threads() {
    same_on_one_two_and_three_threads(odd_periodic());
}

fn same_on_one_two_and_three_threads(case: ([usize; 3], [[Side; 2]; 3])) {
    let (u1, p1, div1) = steps_on(1, case);
    // The projection's promise: ∇·u below 1e-10 of 1 m/s over a cell
    // (n_x s⁻¹); measured 2.9e-10 s⁻¹ in the lid-driven box.
    let scale = case.0[0] as f64;
    assert!(div1 < 1e-10 * scale, "max |∇·u| = {div1:e} s⁻¹");
    for threads in [2, 3] {
        let (u, p, _) = steps_on(threads, case);
        for d in 0..3 {
            let differ = u1[d]
                .iter()
                .zip(&u[d])
                .filter(|(a, b)| a.to_bits() != b.to_bits())
                .count();
            assert_eq!(
                differ, 0,
                "{differ} faces normal to axis {d} differ on {threads} threads"
            );
        }
        let differ = p1
            .iter()
            .zip(&p)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(
            differ, 0,
            "{differ} cells' pressures differ on {threads} threads"
        );
    }
}
