//! The incompressible flow model through the coupler: the C-9 set-up of
//! seed 000 §4.2.1 (inflow below, outflow at p = 0 above, periodic sides)
//! carries a uniform stream through the box unchanged — uniform flow at
//! p = 0 solves the Navier–Stokes equations with these sides exactly, so
//! anything else is an error of the sides — and writes its fields as
//! readable `.vti` files.

use canopy_tests::*;
use coupler::vtu;

#[test]
fn the_c9_set_up_passes_a_uniform_stream_through_unchanged() {
    let dir = scratch("c9-tunnel");
    let scenario = variant("c9-tunnel", &dir, |s| s.run.end_time = 0.4);
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let last = std::fs::read_dir(out.join("vtk"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vti"))
        .max()
        .expect("fluid outputs");
    let velocity = vtu::read_cell_data(&last, "velocity").unwrap();
    let pressure = vtu::read_cell_data(&last, "pressure").unwrap();
    assert_eq!(velocity.len(), 3 * 32 * 32 * 48);
    assert_eq!(pressure.len(), 32 * 32 * 48);
    for (i, v) in velocity.iter().enumerate() {
        let exact = if i % 3 == 2 { 6.0 } else { 0.0 };
        assert!((v - exact).abs() < 1e-12, "velocity component {i}: {v}");
    }
    assert!(pressure.iter().all(|p| p.abs() < 1e-9), "pressure not 0");
    let m = Monitors::read(&out);
    let energy = m.column("fluid.kinetic_energy");
    // ½ρV²·volume with ISA air: ½·1.225·36·(16·16·24).
    let exact = 0.5 * 1.225 * 36.0 * 16.0 * 16.0 * 24.0;
    assert!(
        energy.iter().all(|e| (e / exact - 1.0).abs() < 1e-12),
        "{energy:?}"
    );
}
