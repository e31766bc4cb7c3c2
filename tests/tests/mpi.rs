//! The flows split among MPI ranks (issue 6, item 6): the same run on 1, 2
//! and 4 ranks gives the same fields.
//!
//! - The compressible gas: each rank computes its cells from the same
//!   stencil values one rank alone reads (its halo holds the neighbours'
//!   cells) and all take the same global step, so the fields must agree to
//!   round-off; measured, they agree bit for bit. Only sums over cells (the
//!   mass monitor) change, by their order of addition.
//! - The incompressible flow: the same holds for every stencil, and the
//!   multigrid's smoothing gives the same values too (red–black sweeps with
//!   the halo swapped before each colour). The conjugate-gradient solves'
//!   dot products are sums over the ranks, whose order of addition changes
//!   their round-off; measured, the fields agree to 2·10⁻¹⁴ of their
//!   largest value (`fluid-proc/tests/split.rs` tests the same on thread
//!   ranks, a periodic slab axis and odd slab starts included).
//! - The canopy and bodies in the incompressible flow: rank 0 places them
//!   and shares their markers; every rank forces its own faces, the air's
//!   velocity at a marker being summed over the ranks (round-off where a
//!   kernel straddles two slabs). The bodies' loads are the forcing rank 0
//!   records; the canopy's pressure jump and the bodies' pressure force
//!   are read on rank 0 from the gathered pressure. They agree to
//!   round-off as well.

use canopy_tests::*;
use fluid_section::flow::SideSpec;
use fluid_section::gas::GasRegion;
use participant::vtu;
use std::path::{Path, PathBuf};

/// The scene run on `ranks` ranks of the MPI fluid-proc; its run directory.
fn run_on(
    name: &str,
    dir: &Path,
    ranks: u32,
    fluid: &Path,
    change: fn(&mut canopy_tests::Scenario),
) -> PathBuf {
    let scenario = variant(name, dir, |s| {
        change(s);
        let spec = s.participants.get_mut("fluid").unwrap();
        spec.program = fluid.display().to_string();
        spec.ranks = Some(ranks);
    });
    let out = dir.join(format!("run-{ranks}"));
    run_ok(&scenario, &out);
    out
}

/// Every cell field of every output, from runs on each of `ranks`, against
/// the first, to `tolerance` of the field's largest value; and the
/// `monitors` (sums over the box, loads) to `tolerance` relative.
fn assert_same_fields(runs: &[(u32, PathBuf)], fields: &[&str], monitors: &[&str], tolerance: f64) {
    let (_, first) = &runs[0];
    let outputs: Vec<PathBuf> = std::fs::read_dir(first.join("vtk"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vti"))
        .collect();
    assert!(outputs.len() >= 2, "{outputs:?}");
    for output in &outputs {
        let name = output.file_name().unwrap();
        for field in fields {
            let one = vtu::read_cell_data(output, field).unwrap();
            for (ranks, run) in &runs[1..] {
                let many = vtu::read_cell_data(&run.join("vtk").join(name), field).unwrap();
                assert_eq!(one.len(), many.len());
                let scale = one.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1.0);
                for (i, (a, b)) in one.iter().zip(&many).enumerate() {
                    assert!(
                        (a - b).abs() <= tolerance * scale,
                        "{field}[{i}] in {name:?}: {a} on one rank, {b} on {ranks}"
                    );
                }
            }
        }
    }
    for monitor in monitors {
        let one = Monitors::read(first).column(monitor);
        for (ranks, run) in runs {
            let many = Monitors::read(run).column(monitor);
            assert_eq!(many.len(), one.len());
            for (a, b) in many.iter().zip(&one) {
                // NaN where there is nothing to report yet (a load before the first window).
                let same = (a.is_nan() && b.is_nan()) || (a - b).abs() <= tolerance * b.abs();
                assert!(same, "{monitor} {a} on {ranks} ranks against {b} on one");
            }
        }
    }
}

/// The shipped scene `name`, changed by `change`, run on each of `ranks`
/// (in a scratch folder named for `test`): its fields as in
/// [`assert_same_fields`].
fn assert_same_on(
    test: &str,
    name: &str,
    ranks: &[u32],
    change: fn(&mut canopy_tests::Scenario),
    (fields, monitors, tolerance): (&[&str], &[&str], f64),
) {
    let Some(fluid) = mpi_fluid_proc() else {
        return;
    };
    let dir = scratch(test);
    let runs: Vec<(u32, PathBuf)> = ranks
        .iter()
        .map(|&r| (r, run_on(name, &dir, r, &fluid, change)))
        .collect();
    assert_same_fields(&runs, fields, monitors, tolerance);
}

/// The gas's fields, and its mass, to round-off.
const GAS: (&[&str], &[&str], f64) = (&["density", "velocity", "pressure"], &["fluid.mass"], 1e-13);

#[test]
fn sods_tube_gives_the_same_gas_on_1_2_and_4_ranks() {
    assert_same_on("mpi-sod", "sod", &[1, 2, 4], |_| {}, GAS);
}

#[test]
fn a_periodic_2d_gas_gives_the_same_fields_on_1_2_and_3_ranks() {
    // A square of high pressure in a periodic 2-D box with a diagonal
    // stream: its waves cross the rank boundaries and the periodic sides
    // (which the slabs wrap round) several times by t = 0.6. On 2 ranks
    // each rank's neighbours below and above are the same rank.
    let change = |s: &mut canopy_tests::Scenario| {
        s.run.end_time = 0.6;
        s.run.output_interval = 0.3;
        let f = s.fluid.as_mut().unwrap();
        let b = f.flow_box.as_mut().unwrap();
        b.upper = [1.0, 1.5, 0.05];
        b.cells = [32, 48, 1];
        let mut sides = f.sides.unwrap();
        sides.x_low = Some(SideSpec::Periodic);
        sides.x_high = Some(SideSpec::Periodic);
        sides.y_low = Some(SideSpec::Periodic);
        sides.y_high = Some(SideSpec::Periodic);
        f.sides = Some(sides);
        let stream = GasRegion {
            lower: None,
            upper: None,
            density: 1.0,
            velocity: [1.0, 0.5, 0.0],
            pressure: 1.0,
            density_wave: None,
        };
        let square = GasRegion {
            lower: Some([0.3, 0.5, 0.0]),
            upper: Some([0.6, 0.9, 1.0]),
            pressure: 5.0,
            ..stream
        };
        f.regions = Some(vec![stream, square]);
    };
    assert_same_on("mpi-periodic", "sod", &[1, 2, 3], change, GAS);
}

/// The flow's fields, and its kinetic energy, to the round-off of the
/// order of a dot product's terms: 2·10⁻¹⁴ measured; the solves'
/// tolerance is 10⁻⁸.
const FLOW: (&[&str], &[&str], f64) = (&["velocity", "pressure"], &["fluid.kinetic_energy"], 1e-12);

#[test]
fn the_cavity_gives_the_same_flow_on_1_2_and_4_ranks() {
    // The Re = 100 cavity (2-D, split along y): walls on the ranks at the
    // bottom and the sides, the lid on the top rank's side.
    let change = |s: &mut canopy_tests::Scenario| {
        s.run.end_time = 0.25;
        s.run.output_interval = 0.125;
        s.coupling.window = 1.25e-2;
        s.fluid.as_mut().unwrap().flow_box.as_mut().unwrap().cells = [32, 32, 1];
    };
    assert_same_on("mpi-cavity", "cavity", &[1, 2, 4], change, FLOW);
}

#[test]
fn a_3d_channel_gives_the_same_flow_on_1_2_and_4_ranks() {
    // A 3-D channel split along z, the flow's direction: a parabolic inflow
    // (its profile across x, between walls; y periodic) on the first rank's
    // side, an outflow at p = 0 on the last's, so the jet front and the
    // pressure cross every slab boundary.
    let change = |s: &mut canopy_tests::Scenario| {
        s.run.end_time = 0.3;
        s.run.output_interval = 0.15;
        s.coupling.window = 0.03;
        let f = s.fluid.as_mut().unwrap();
        f.density = Some(1.0);
        f.viscosity = Some(0.01);
        f.initial_velocity = None;
        let b = f.flow_box.as_mut().unwrap();
        b.lower = [0.0; 3];
        b.upper = [1.0, 1.0, 2.0];
        b.cells = [8, 8, 16];
        let mut sides = f.sides.unwrap();
        sides.x_low = Some(SideSpec::Wall);
        sides.x_high = Some(SideSpec::Wall);
        sides.z_low = Some(SideSpec::Parabolic([0.0, 0.0, 1.0]));
        f.sides = Some(sides);
    };
    assert_same_on("mpi-channel", "c9-tunnel", &[1, 2, 4], change, FLOW);
}

#[test]
fn a_porous_sheet_in_the_flow_moves_the_same_on_1_2_and_4_ranks() {
    // `sheet-updraft` with the sheet started at z = 2 m, the boundary
    // between the slabs of 2 ranks (the middle one of 4), so its kernel
    // straddles it. rank 0 reads the pressure jump through the coating
    // from the gathered pressure and the structure moves the sheet with
    // it: measured, the fields agree to 1.2·10⁻¹⁴, the jump and the
    // structure's energy to 6·10⁻¹⁴. (Before the markers' cut took a
    // slack, round-off in the cloth's edges of exactly one cell cut them
    // differently on 2 ranks: 10⁻³ off.)
    let change = |s: &mut canopy_tests::Scenario| {
        s.run.end_time = 0.3;
        s.run.output_interval = 0.1;
        let cloth = s.structure.as_mut().unwrap().cloth.as_mut().unwrap();
        cloth.origin = [0.0, 0.0, 2.0];
    };
    let monitors = &[
        "fluid.kinetic_energy",
        "fluid.mean_pressure_jump",
        "structure.kinetic_energy",
        "structure.momentum.z",
    ];
    let checks = (FLOW.0, &monitors[..], FLOW.2);
    assert_same_on("mpi-sheet", "sheet-updraft", &[1, 2, 4], change, checks);
}

#[test]
fn a_parachutist_in_the_flow_leaves_the_same_wake_on_1_2_and_4_ranks() {
    // `wake` with the parachutist 0.5 m higher: its section spans z from
    // −1.4 m to 0.4 m, cells 41.6 to 70.4 of 128, across the slab boundary
    // at cell 64 (z = 0) on 2 and 4 ranks. The fluid's load on it
    // (the forcing rank 0 records, and eq. 2.40's pressure integral over
    // the gathered pressure): measured, to 5·10⁻¹⁴.
    let change = |s: &mut canopy_tests::Scenario| {
        s.run.end_time = 0.15;
        s.run.output_interval = 0.075;
        s.rigid.as_mut().unwrap().bodies[0].position = [0.0, 0.0, -0.5];
    };
    let monitors = &[
        "fluid.kinetic_energy",
        "fluid.jumper_fluid_force_z",
        "fluid.jumper_pressure_force_z",
    ];
    let checks = (FLOW.0, &monitors[..], FLOW.2);
    assert_same_on("mpi-wake", "wake", &[1, 2, 4], change, checks);
}

/// The gas's fields with bodies in it, its mass, and each body's load.
fn with_bodies<'a>(loads: &'a [&'a str]) -> (&'a [&'a str], &'a [&'a str], f64) {
    (GAS.0, loads, 1e-12)
}

#[test]
fn the_piston_and_the_wedge_give_the_same_gas_on_1_and_2_ranks() {
    // Both boxes are split along x at 0.5 m: the piston's face reaches the
    // boundary at the end, the wedge lies across it. A ghost's image point
    // may lie up to 7 cells away, in the other rank's slab: the halo is
    // that wide with bodies in the gas.
    let piston = |s: &mut canopy_tests::Scenario| s.run.output_interval = 0.2;
    let loads = ["fluid.mass", "fluid.piston_fluid_force_x"];
    assert_same_on("mpi-piston", "piston", &[1, 2], piston, with_bodies(&loads));
    let wedge = |s: &mut canopy_tests::Scenario| {
        s.run.end_time = 0.5;
        s.run.output_interval = 0.25;
    };
    let loads = [
        "fluid.mass",
        "fluid.wedge_fluid_force_x",
        "fluid.wedge_fluid_force_y",
    ];
    assert_same_on("mpi-wedge", "wedge", &[1, 2], wedge, with_bodies(&loads));
}

#[test]
fn the_lifted_cylinder_moves_the_same_on_1_2_and_3_ranks() {
    // The free cylinder crosses the slab boundary at x = 1/3 m on 3 ranks
    // (by t = 0.14 s), and reaches the one at 0.5 m on 2; rigid-proc moves
    // it by the load the ranks sum.
    let change = |s: &mut canopy_tests::Scenario| s.run.output_interval = 0.085;
    let loads = [
        "fluid.mass",
        "fluid.cylinder_fluid_force_x",
        "fluid.cylinder_fluid_force_y",
        "rigid.cylinder.x",
        "rigid.cylinder.y",
    ];
    assert_same_on(
        "mpi-liftoff",
        "cylinder-liftoff",
        &[1, 2, 3],
        change,
        with_bodies(&loads),
    );
}
