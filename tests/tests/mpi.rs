//! The compressible flow split among MPI ranks (issue 6, item 6): the same
//! run on 1, 2 and 4 ranks gives the same fields. Each rank computes its
//! cells from the same stencil values one rank alone reads (its halo holds
//! the neighbours' cells) and all take the same global step, so the fields
//! must agree to round-off; measured, they agree bit for bit. Only sums over
//! cells (the mass monitor) change, by their order of addition.

use canopy_tests::*;
use coupler::scenario::flow::SideSpec;
use coupler::scenario::gas::GasRegion;
use coupler::vtu;
use std::path::{Path, PathBuf};

/// The scene run on `ranks` ranks of the MPI fluid-proc; its run directory.
fn run_on(
    name: &str,
    dir: &Path,
    ranks: u32,
    fluid: &Path,
    change: fn(&mut coupler::Scenario),
) -> PathBuf {
    let scenario = variant(name, dir, |s| {
        change(s);
        let spec = s.participants.fluid.as_mut().unwrap();
        spec.program = fluid.display().to_string();
        spec.ranks = Some(ranks);
    });
    let out = dir.join(format!("run-{ranks}"));
    run_ok(&scenario, &out);
    out
}

/// Every cell field of every output, from runs on each of `ranks`, against
/// the first.
fn assert_same_fields(runs: &[(u32, PathBuf)], fields: &[&str]) {
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
                        (a - b).abs() <= 1e-13 * scale,
                        "{field}[{i}] in {name:?}: {a} on one rank, {b} on {ranks}"
                    );
                }
            }
        }
    }
    // The mass is conserved on every rank count, to round-off of the sum.
    let mass0 = Monitors::read(first).column("fluid.mass");
    for (_, run) in runs {
        for (a, b) in Monitors::read(run).column("fluid.mass").iter().zip(&mass0) {
            assert!((a / b - 1.0).abs() < 1e-13, "mass {a} against {b}");
        }
    }
}

#[test]
fn sods_tube_gives_the_same_gas_on_1_2_and_4_ranks() {
    let Some(fluid) = mpi_fluid_proc() else {
        return;
    };
    let dir = scratch("mpi-sod");
    let runs: Vec<(u32, PathBuf)> = [1, 2, 4]
        .into_iter()
        .map(|r| (r, run_on("sod", &dir, r, &fluid, |_| {})))
        .collect();
    assert_same_fields(&runs, &["density", "velocity", "pressure"]);
}

#[test]
fn a_periodic_2d_gas_gives_the_same_fields_on_1_2_and_3_ranks() {
    // A square of high pressure in a periodic 2-D box with a diagonal
    // stream: its waves cross the rank boundaries and the periodic sides
    // (which the slabs wrap round) several times by t = 0.6. On 2 ranks
    // each rank's neighbours below and above are the same rank.
    let Some(fluid) = mpi_fluid_proc() else {
        return;
    };
    let dir = scratch("mpi-periodic");
    let change = |s: &mut coupler::Scenario| {
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
    let runs: Vec<(u32, PathBuf)> = [1, 2, 3]
        .into_iter()
        .map(|r| (r, run_on("sod", &dir, r, &fluid, change)))
        .collect();
    assert_same_fields(&runs, &["density", "velocity", "pressure"]);
}
