//! Run checkpoints and restart (issue 22): a run killed with SIGKILL
//! mid-run and restarted with `coupler run --restart` ends with the same
//! monitors and output files as a run never interrupted, bit for bit.

use canopy_tests::*;
use participant::restart;
use std::path::Path;
use std::time::{Duration, Instant};

/// Every file a run leaves that holds results: `monitors.csv`, the
/// implicit run's `iterations.csv`, the `.pvd` series and the outputs in
/// `vtk/`, by name.
fn results(run: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files = Vec::new();
    let mut add = |dir: &Path, keep: &dyn Fn(&str) -> bool| {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| e.ok()?.file_name().into_string().ok())
            .filter(|n| keep(n))
            .collect();
        names.sort();
        for n in names {
            let bytes = std::fs::read(dir.join(&n)).unwrap();
            files.push((n, bytes));
        }
    };
    add(run, &|n| n.ends_with(".csv") || n.ends_with(".pvd"));
    add(&run.join("vtk"), &|_| true);
    files
}

/// Whether a run checkpoint in `out` is complete for every one of
/// `names`; if one is, `monitors.csv` holds the rows up to its window (a
/// row at the start and one per window): a participant completes its part
/// only once the coupler has them on disk.
fn usable_checkpoint(out: &Path, names: &[String]) -> bool {
    let Some(&w) = restart::complete(out, names).first() else {
        return false;
    };
    let rows = std::fs::read(out.join("monitors.csv"))
        .map_or(0, |t| t.iter().filter(|&&b| b == b'\n').count() as u64);
    assert!(
        rows >= w + 3,
        "checkpoint {w} is complete with {rows} lines of monitors.csv"
    );
    true
}

/// How a run is stopped mid-run.
#[derive(Clone, Copy, PartialEq)]
enum Stop {
    /// SIGKILL to the coupler: its participants die with it.
    Kill,
    /// SIGINT, as Ctrl-C: the coupler stops everything cleanly and says
    /// how to go on.
    Interrupt,
}

/// Start `scenario` into `out`, stop the coupler as `stop` says once its
/// first run checkpoint of `names` can be gone on from, and check that it
/// was stopped mid-run.
fn stop_after_first_checkpoint(scenario: &Path, out: &Path, names: &[&str], stop: Stop) {
    let names: Vec<String> = names.iter().map(|n| n.to_string()).collect();
    let mut coupler = run_command(scenario, out)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start coupler");
    let since = Instant::now();
    while !usable_checkpoint(out, &names) {
        assert!(
            since.elapsed() < Duration::from_secs(120),
            "no checkpoint came"
        );
        assert!(coupler.try_wait().unwrap().is_none(), "the run ended first");
        std::thread::sleep(Duration::from_millis(2));
    }
    match stop {
        Stop::Kill => coupler.kill().expect("SIGKILL the coupler"),
        // SAFETY: kill(2) on our own child's pid, which it has not reaped.
        Stop::Interrupt => assert_eq!(unsafe { libc::kill(coupler.id() as i32, libc::SIGINT) }, 0),
    }
    let o = coupler.wait_with_output().unwrap();
    let (status, err) = match stop {
        Stop::Kill => ("running", String::new()),
        Stop::Interrupt => (
            "interrupted",
            String::from_utf8_lossy(&o.stderr).to_string(),
        ),
    };
    assert_eq!(manifest(out)["status"], status, "stopped before its end");
    if stop == Stop::Interrupt {
        assert_eq!(o.status.code(), Some(130), "{err}");
        assert!(err.contains("coupler run --restart"), "{err}");
    }
}

/// The whole run and a killed and restarted one of `scenario` leave the
/// same results, bit for bit.
fn restart_matches_whole_run(name: &str, scenario: &Path, dir: &Path, names: &[&str]) {
    restart_after(Stop::Kill, name, scenario, dir, names);
}

/// The same, stopped as `stop` says.
fn restart_after(stop: Stop, name: &str, scenario: &Path, dir: &Path, names: &[&str]) {
    let (whole, killed) = (dir.join("whole"), dir.join("killed"));
    run_ok(scenario, &whole);
    stop_after_first_checkpoint(scenario, &killed, names, stop);
    let o = coupler(&["run", "--restart", killed.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "restart of {name} failed:\n{err}");
    assert!(err.contains("restarting"), "{err}");
    assert_eq!(manifest(&killed)["status"], "completed");
    let kept = std::fs::read_dir(whole.join(restart::DIR)).unwrap().count();
    assert!(kept <= restart::KEEP, "{name}: {kept} run checkpoints kept");
    assert_same_results(name, &results(&whole), &killed);
}

/// The results a restarted run left in `run` are `expected`, file by
/// file, bit for bit; `name` says which run in a failure.
fn assert_same_results(name: &str, expected: &[(String, Vec<u8>)], run: &Path) {
    let got = results(run);
    assert!(expected.len() > 3, "{name}: the run left its results");
    let names = |r: &[(String, Vec<u8>)]| r.iter().map(|f| f.0.clone()).collect::<Vec<_>>();
    assert_eq!(names(expected), names(&got), "{name}: the same files");
    for ((file, x), (_, y)) in expected.iter().zip(&got) {
        assert!(x == y, "{name}: {file} differs after the restart");
    }
}

/// The pendulum under implicit coupling with velocity Verlet: the
/// structure's and the ball's state, the outputs written so far, and the
/// IQN-ILS columns of the windows before go into each checkpoint.
#[test]
fn a_killed_implicit_pendulum_restarts_to_the_same_results() {
    let dir = scratch("restart-pendulum");
    let scenario = variant("pendulum", &dir, |s| {
        s.run.end_time = 60.0;
        s.run.output_interval = 5.0;
        s.run.checkpoint_interval = Some(5.0);
        s.coupling.impulse_substeps = 1;
        s.coupling.scheme = scenario::SchemeName::Implicit;
        let structure = s.structure.as_mut().unwrap();
        structure.integrator = structure_section::Integrator::VelocityVerlet;
    });
    restart_matches_whole_run("pendulum", &scenario, &dir, &["structure", "rigid"]);
}

/// The closed sheet under the parallel implicit scheme (issue 43, item 2):
/// the fluid computes its pressure only at window ends, so a restarted run
/// sends the structure the pressure of the checkpoint's window again from
/// the acceleration state kept in the checkpoint, and the run goes on as
/// the whole one did, to the bit.
#[test]
fn a_killed_parallel_implicit_run_restarts_to_the_same_results() {
    let dir = scratch("restart-parallel");
    let scenario = variant("sheet-closed", &dir, |s| {
        // The sheet rises 1.8 m of its box's 2.5 m above it.
        s.run.end_time = 1.0;
        s.run.output_interval = 0.25;
        s.run.checkpoint_interval = Some(0.1);
        s.coupling.scheme = scenario::SchemeName::ParallelImplicit;
    });
    restart_matches_whole_run("sheet-closed", &scenario, &dir, &["fluid", "structure"]);
}

/// The pendulum with a finite body whose shape is a mesh file beside the
/// scenario, named by a relative path: the restart reads the scenario the
/// run was started from, unchanged, so the mesh is found as it was.
#[test]
fn a_restart_finds_a_mesh_named_relative_to_the_scenario() {
    let dir = scratch("restart-mesh");
    // A cube of side 0.2 m about its centre, outward triangles.
    let mut obj = String::new();
    for i in 0..8 {
        let c = |bit: usize| if i >> bit & 1 == 1 { 0.1 } else { -0.1 };
        obj.push_str(&format!("v {} {} {}\n", c(0), c(1), c(2)));
    }
    for f in [
        [1, 3, 4, 2],
        [5, 6, 8, 7],
        [1, 2, 6, 5],
        [3, 7, 8, 4],
        [1, 5, 7, 3],
        [2, 4, 8, 6],
    ] {
        obj.push_str(&format!(
            "f {} {} {}\nf {} {} {}\n",
            f[0], f[1], f[2], f[0], f[2], f[3]
        ));
    }
    std::fs::write(dir.join("cube.obj"), obj).unwrap();
    let scenario = variant("pendulum-body", &dir, |s| {
        s.run.end_time = 60.0;
        s.run.output_interval = 5.0;
        s.run.checkpoint_interval = Some(5.0);
        let body = &mut s.rigid.as_mut().unwrap().bodies[0];
        body.shape = Some(rigid_section::ShapeSpec::Mesh {
            file: "cube.obj".into(),
        });
    });
    restart_matches_whole_run("pendulum-body", &scenario, &dir, &["structure", "rigid"]);
}

/// A canopy in the porous free stream, interrupted as with Ctrl-C: the
/// fluid keeps no state, and takes the canopy's triangles again when the
/// run resumes; the interrupted coupler says how to go on.
#[test]
fn an_interrupted_canopy_in_the_stream_restarts_to_the_same_results() {
    let dir = scratch("restart-canopy");
    let scenario = variant("canopy-porous", &dir, |s| {
        // 20 000 windows: seconds, so that the interrupt comes mid-run
        // although the coupler writes monitor rows only every 0.2 s.
        s.run.end_time = 40.0;
        s.run.output_interval = 0.5;
        s.run.checkpoint_interval = Some(1.0);
    });
    let names = ["fluid", "structure"];
    restart_after(Stop::Interrupt, "canopy-porous", &scenario, &dir, &names);
}

/// A porous annulus in the incompressible flow under implicit coupling,
/// the fluid on two MPI ranks where MPI is installed (one otherwise): each
/// rank writes and reads back its part of the flow (faces, pressure,
/// Adams–Bashforth history, the solvers' first guesses, the canopy's
/// markers), rank 0 its outputs.
#[test]
fn a_killed_canopy_in_the_flow_restarts_to_the_same_results() {
    let dir = scratch("restart-flow");
    let fluid = mpi_fluid_proc();
    let scenario = short_canopy_flow(&dir, &fluid, |s| {
        s.coupling.scheme = scenario::SchemeName::Implicit;
    });
    restart_matches_whole_run("canopy-flow", &scenario, &dir, &["fluid", "structure"]);
    rank_1_wrote_its_part(&dir, &fluid);
}

/// The same with the box following the canopy (`[fluid.frame]`), graded
/// along z from a core of 0.15 m round the canopy (`[fluid.box.core]`,
/// issue 45): the box's place and motion go into each rank's run
/// checkpoint, and the window it resumes aims the box as the whole run did.
#[test]
fn a_killed_graded_box_that_follows_the_canopy_restarts_to_the_same_results() {
    let dir = scratch("restart-frame");
    let fluid = mpi_fluid_proc();
    let scenario = short_canopy_flow(&dir, &fluid, |s| {
        let f = s.fluid.as_mut().unwrap();
        f.frame = Some(fluid_section::frame::FrameSpec {
            follow: "canopy".into(),
            velocity: None,
            altitude: None,
        });
        let core = fluid_section::grading::Core {
            lower: [-1.5, -1.5, -0.6],
            upper: [1.5, 1.5, 0.9],
            spacing: 0.15,
            growth: 1.2,
        };
        let b = f.flow_box.as_mut().unwrap();
        *b = b.with_core(core);
        assert_eq!(b.cells, [20, 20, 20], "the graded box's cells");
    });
    restart_matches_whole_run("canopy-flow", &scenario, &dir, &["fluid", "structure"]);
    let m = Monitors::read(&dir.join("whole"));
    let moved = m.column("fluid.frame_descent_speed");
    assert!(
        moved.iter().any(|v| v.abs() > 1e-3),
        "the box never moved: {moved:?}"
    );
}

/// Two balls in a cloth (`ball-cloth`) with the structure's contact pass:
/// the candidates it holds from step to step are not in the checkpoint
/// (the restarted run finds them anew), and the impulses act in the order
/// of the pairs' kinds and node numbers, so the restart gives the same
/// impulses.
#[test]
fn a_killed_cloth_in_contact_with_balls_restarts_to_the_same_results() {
    let dir = scratch("restart-contact");
    let scenario = variant("ball-cloth", &dir, |s| {
        s.run.end_time = 0.8;
        s.run.output_interval = 0.1;
        s.run.checkpoint_interval = Some(0.2);
    });
    restart_matches_whole_run("ball-cloth", &scenario, &dir, &["structure", "rigid"]);
}

/// The cloth falling on strings (`cloth-strings`, on the coarse mesh of
/// its scene test) killed at 0.2 s, as it lies on the strings, and gone
/// on with to 0.5 s, through the strings' first contacts with each other
/// (from 0.32 s): held candidates, lower bounds on their distances and the
/// tree's skipped regions are not in the checkpoint, and the restart gives
/// the same impulses.
#[test]
fn a_killed_cloth_on_strings_restarts_to_the_same_results() {
    let dir = scratch("restart-strings");
    let scenario = variant("cloth-strings", &dir, |s| {
        s.run.end_time = 0.5;
        s.run.output_interval = 0.1;
        s.run.checkpoint_interval = Some(0.2);
        coarse_cloth_strings(s);
    });
    restart_matches_whole_run("cloth-strings", &scenario, &dir, &["structure"]);
    let m = Monitors::read(&dir.join("whole"));
    let strings = m.column("structure.contact.string_string");
    assert!(
        strings.last().is_some_and(|&n| n > 0.0),
        "the strings never met"
    );
}

/// The Sod shock tube of the euler model, on 2 000 cells so that it runs
/// long enough to be killed, on two MPI ranks where MPI is installed:
/// each rank's conserved cells and the time.
#[test]
fn a_killed_shock_tube_restarts_to_the_same_results() {
    let dir = scratch("restart-sod");
    let fluid = mpi_fluid_proc();
    let scenario = variant("sod", &dir, |s| {
        s.run.checkpoint_interval = Some(0.02);
        let b = s.fluid.as_mut().unwrap().flow_box.as_mut().unwrap();
        b.cells = [2000, 1, 1];
        on_two_ranks(s, &fluid);
    });
    restart_matches_whole_run("sod", &scenario, &dir, &["fluid"]);
    rank_1_wrote_its_part(&dir, &fluid);
}

/// `canopy-flow.toml` for 0.06 s on 20 × 20 × 27 cells, a run checkpoint
/// every 0.01 s, the fluid on two ranks of `fluid` if any, changed by
/// `change`.
fn short_canopy_flow(
    dir: &Path,
    fluid: &Option<std::path::PathBuf>,
    change: impl FnOnce(&mut Scenario),
) -> std::path::PathBuf {
    variant("canopy-flow", dir, |s| {
        s.run.end_time = 0.06;
        s.run.output_interval = 0.02;
        s.run.checkpoint_interval = Some(0.01);
        s.coupling.window = 9e-4;
        s.fluid.as_mut().unwrap().flow_box.as_mut().unwrap().cells = [20, 20, 27];
        change(s);
        on_two_ranks(s, fluid);
    })
}

/// The fluid of `s` on two ranks of `fluid` (built with MPI), if any.
fn on_two_ranks(s: &mut Scenario, fluid: &Option<std::path::PathBuf>) {
    if let Some(fluid) = fluid {
        let spec = s.participants.get_mut("fluid").unwrap();
        spec.program = fluid.display().to_string();
        spec.ranks = Some(2);
    }
}

/// On two ranks, rank 1 wrote its part of the killed run's newest checkpoint.
fn rank_1_wrote_its_part(dir: &Path, fluid: &Option<std::path::PathBuf>) {
    if fluid.is_some() {
        let kept = dir.join("killed").join(restart::DIR);
        let newest = std::fs::read_dir(&kept)
            .unwrap()
            .flatten()
            .map(|e| e.path())
            .max();
        let rank_1 = newest.unwrap().join("fluid.1.state");
        assert!(rank_1.is_file(), "rank 1 wrote its part");
    }
}

/// Issue 42: the coupler killed with SIGKILL at many moments after its
/// first run checkpoint is complete, through the checkpoints that follow
/// (one every 25 windows): every restart goes on, and ends with the
/// results of the run never interrupted, bit for bit. Before the
/// participants waited for their rows to be on disk, restarts that came
/// while `monitors.csv` lagged behind the checkpoints were refused.
#[test]
fn a_coupler_killed_anywhere_around_its_checkpoints_always_restarts() {
    let dir = scratch("restart-anywhere");
    let scenario = variant("canopy-porous", &dir, |s| {
        s.run.end_time = 4.0;
        s.run.output_interval = 0.5;
        s.run.checkpoint_interval = Some(0.05);
    });
    let names = ["fluid", "structure"].map(String::from);
    let whole = dir.join("whole");
    run_ok(&scenario, &whole);
    let expected = results(&whole);
    for (k, delay_ms) in [0u64, 0, 1, 2, 3, 5, 8, 13, 21, 34, 55, 89]
        .into_iter()
        .enumerate()
    {
        let out = dir.join(format!("killed-{k}"));
        let mut running = run_command(&scenario, &out)
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("start coupler");
        let since = Instant::now();
        while restart::complete(&out, &names).is_empty() {
            assert!(
                since.elapsed() < Duration::from_secs(120),
                "no checkpoint came"
            );
            assert!(
                running.try_wait().unwrap().is_none(),
                "kill {k}: the run ended first"
            );
            std::thread::sleep(Duration::from_micros(500));
        }
        std::thread::sleep(Duration::from_millis(delay_ms));
        running.kill().expect("SIGKILL the coupler");
        running.wait().unwrap();
        assert_eq!(
            manifest(&out)["status"],
            "running",
            "kill {k} came after the end"
        );
        let o = coupler(&["run", "--restart", out.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&o.stderr);
        let name = format!("kill {k}, {delay_ms} ms after the first checkpoint");
        assert!(o.status.success(), "{name}: restart failed:\n{err}");
        assert_same_results(&name, &expected, &out);
        std::fs::remove_dir_all(&out).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// What cannot be restarted says why and exits 2: a completed run, and a
/// run whose scenario writes no run checkpoints.
#[test]
fn a_run_with_nothing_to_go_on_from_is_refused() {
    let dir = scratch("restart-refused");
    let scenario = variant("pendulum", &dir, |s| s.run.end_time = 0.5);
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let o = coupler(&["run", "--restart", out.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("completed: there is nothing to go on with"),
        "{err}"
    );

    // Killed before it ended, with no checkpoint_interval.
    let m = std::fs::read_to_string(out.join("manifest.json")).unwrap();
    std::fs::write(out.join("manifest.json"), m.replace("completed", "running")).unwrap();
    let o = coupler(&["run", "--restart", out.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("sets no [run] checkpoint_interval"), "{err}");
}
