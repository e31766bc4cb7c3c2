//! `[structure] device = "gpu"` (issue 25) and `[fluid] device = "gpu"`
//! (issue 47) from the scenario to the run: a scene on the GPU gives the
//! CPU's monitors, and `check` refuses what the device does not run,
//! naming the key. CI runs these on Mesa's
//! CPU Vulkan adapter; `CANOPY_REQUIRE_GPU` makes a missing adapter a
//! failure there, elsewhere the scene test says so and passes.

use canopy_tests::*;
use scenario::section::Device;
use std::path::{Path, PathBuf};
use structure_section::Integrator;

/// `coupler check` of `scenario`: exit code and stderr.
fn check(scenario: &Path, env: &[(&str, &str)]) -> (Option<i32>, String) {
    let mut command = std::process::Command::new(coupler_exe());
    command.args(["check", scenario.to_str().unwrap()]);
    command.envs(env.iter().copied());
    let o = command.output().expect("run coupler");
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Which section's steps go to the GPU.
#[derive(Clone, Copy)]
enum Part {
    Structure,
    Fluid,
}

/// `name` cut to `end_time` [s], its `part` on the GPU or not, written under `dir`.
fn on(dir: &Path, name: &str, end_time: f64, part: Part, gpu: bool) -> PathBuf {
    let sub = dir.join(if gpu { "Gpu" } else { "Cpu" });
    std::fs::create_dir_all(&sub).unwrap();
    variant(name, &sub, |s| {
        s.run.end_time = end_time;
        s.run.output_interval = 0.0;
        let device = if gpu { Device::Gpu } else { Device::Cpu };
        match part {
            Part::Structure => s.structure.as_mut().unwrap().device = device,
            Part::Fluid => s.fluid.as_mut().unwrap().device = device,
        }
    })
}

/// `name` to `end_time` on the GPU and on the CPU: every monitor the same
/// to round-off (both run the same passes in f64; a GPU may fuse multiplies
/// and adds), far below the 10⁻⁶ the CSV resolves. Returns the CPU's
/// monitors, or `None` where no adapter is found and CI does not require one.
fn same_on_both(name: &str, end_time: f64) -> Option<Monitors> {
    same_on_both_within(name, end_time, Part::Structure, 1e-9, &[])
}

/// [`same_on_both`] with `part` on the GPU, each monitor but those `left`
/// within `tolerance` relative (plus as much absolute).
fn same_on_both_within(
    name: &str,
    end_time: f64,
    part: Part,
    tolerance: f64,
    left: &[&str],
) -> Option<Monitors> {
    let dir = scratch(&format!("gpu-{name}"));
    let on_gpu = on(&dir, name, end_time, part, true);
    if !gpu_check_passes(&on_gpu) {
        return None;
    }
    run_ok(&on_gpu, &dir.join("gpu"));
    run_ok(&on(&dir, name, end_time, part, false), &dir.join("cpu"));
    let (gpu, cpu) = (
        Monitors::read(&dir.join("gpu")),
        Monitors::read(&dir.join("cpu")),
    );
    assert_eq!(gpu.header, cpu.header, "{name}: the same monitors");
    for column in cpu.header.iter().filter(|c| !left.contains(&c.as_str())) {
        let (a, b) = (gpu.column(column), cpu.column(column));
        assert_eq!(a.len(), b.len(), "{name}, {column}: as many rows");
        for (t, (x, y)) in a.iter().zip(&b).enumerate() {
            // A monitor not yet reported reads NaN on both.
            let same = (x.is_nan() && y.is_nan()) || (x - y).abs() <= tolerance * (1.0 + y.abs());
            assert!(same, "{name}, {column}, row {t}: GPU {x}, CPU {y}");
        }
    }
    Some(cpu)
}

/// `canopy-porous`: the fluid's porous free stream loads the annulus every
/// window (velocity Verlet, thesis eq. 68's dampers); a window's sub-steps
/// stay on the device.
#[test]
fn the_porous_canopy_on_the_gpu_gives_the_cpus_monitors() {
    let Some(cpu) = same_on_both("canopy-porous", 0.2) else {
        return;
    };
    let deflection = cpu.column("structure.centre_deflection");
    assert!(
        deflection.last().unwrap().abs() > 0.05,
        "the stream bends the canopy: {deflection:?}"
    );
}

/// `c9-drop-body`: the C-9 on a rigid payload (rigid-proc), its lines
/// exchanging impulses every sub-step, so the state crosses every sub-step.
#[test]
fn the_c9_on_its_body_on_the_gpu_gives_the_cpus_monitors() {
    let Some(cpu) = same_on_both("c9-drop-body", 0.1) else {
        return;
    };
    assert!(cpu.column("time").len() > 50, "windows ran");
}

/// `cavity` (Re = 100, 128² cells) for its first 0.5 s (160 flow steps)
/// with `[fluid] device = "gpu"`: every monitor (the kinetic energy, the
/// momentum, the divergence, the iterations) the CPU's within 10⁻⁸
/// relative (both solves stop at a relative residual of 10⁻⁸ and agree to
/// round-off here; the CSV holds 10 digits).
#[test]
fn the_cavity_with_its_flow_on_the_gpu_gives_the_cpus_monitors() {
    let Some(cpu) = same_on_both_within("cavity", 0.5, Part::Fluid, 1e-8, &[]) else {
        return;
    };
    // ½ρΣ|u|²V over a slab 1/128 m thick: 1.4·10⁻⁴ J at 0.5 s.
    let energy = cpu.column("fluid.kinetic_energy");
    assert!(
        *energy.last().unwrap() > 5e-5,
        "the lid drives the flow: {:?}",
        energy.last()
    );
}

/// `canopy-flow` (the annulus, a porous sheet, in a stream of 50 m/s on
/// 30 × 30 × 40 cells) for its first 0.03 s (50 windows) with its flow on
/// the GPU: the canopy's markers spread the fabric's drag on the device,
/// and every monitor is the CPU run's within 10⁻⁸ relative.
#[test]
fn the_canopy_in_the_flow_on_the_gpu_gives_the_cpus_monitors() {
    let Some(cpu) = same_on_both_within("canopy-flow", 0.03, Part::Fluid, 1e-8, &[]) else {
        return;
    };
    let jump = cpu.column("fluid.mean_pressure_jump");
    assert!(
        *jump.last().unwrap() > 1.0,
        "the stream loads the canopy: {:?}",
        jump.last()
    );
}

/// `c9-inflation` (the C-9 in a box of 32 × 32 × 72 cells that follows it,
/// implicit coupling) for its first 0.03 s with its flow on the GPU: every
/// monitor the CPU run's within 10⁻⁸ relative (seen: 1.5·10⁻¹⁰), the same
/// tries a window and the same iterations, as a window's later tries take
/// the first one's prediction and start the pressure solve from the last
/// try's correction on the device as on the CPU (fluid-gpu's window.rs).
#[test]
fn the_c9_opening_with_its_flow_on_the_gpu_gives_the_cpus_monitors() {
    let Some(cpu) = same_on_both_within("c9-inflation", 0.03, Part::Fluid, 1e-8, &[]) else {
        return;
    };
    assert_eq!(cpu.column("time").len(), 4, "three windows and the start");
}

/// What the flow's device path does not cover yet: a graded box
/// (`c9-graded`), refused by `check` with the key named (exit 2).
#[test]
fn check_refuses_a_graded_box_on_the_gpu() {
    let dir = scratch("gpu-fluid-graded");
    let path = variant("c9-graded", &dir, |s| {
        s.fluid.as_mut().unwrap().device = Device::Gpu;
    });
    let (code, err) = check(&path, &[]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("key `fluid.device`") && err.contains("a graded box"),
        "{err}"
    );
}

#[test]
fn check_refuses_an_integrator_the_gpu_does_not_run() {
    let dir = scratch("gpu-integrator");
    let path = variant("spring-pendulum", &dir, |s| {
        let st = s.structure.as_mut().unwrap();
        st.device = Device::Gpu;
        st.integrator = Integrator::BackwardEuler;
    });
    let (code, err) = check(&path, &[]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("key `structure.device`") && err.contains("not \"backward-euler\""),
        "{err}"
    );
}

/// No Vulkan driver to be found: what a machine without a GPU or Mesa gives.
#[test]
fn check_refuses_the_gpu_without_an_adapter() {
    let dir = scratch("gpu-none");
    let path = variant("spring-pendulum", &dir, |s| {
        s.structure.as_mut().unwrap().device = Device::Gpu;
    });
    let (code, err) = check(
        &path,
        &[
            ("VK_ICD_FILENAMES", "/nonexistent"),
            ("VK_DRIVER_FILES", "/nonexistent"),
        ],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("key `structure.device`") && err.contains("no GPU adapter found"),
        "{err}"
    );
    assert!(
        err.contains("mesa-vulkan-drivers"),
        "says how to get one: {err}"
    );
}

/// The flow's `device = "gpu"` without a Vulkan driver: refused by `check`
/// with the key named (exit 2), saying how to get an adapter.
#[test]
fn check_refuses_the_flow_on_the_gpu_without_an_adapter() {
    let dir = scratch("gpu-fluid-none");
    let path = variant("cavity", &dir, |s| {
        s.fluid.as_mut().unwrap().device = Device::Gpu;
    });
    let (code, err) = check(
        &path,
        &[
            ("VK_ICD_FILENAMES", "/nonexistent"),
            ("VK_DRIVER_FILES", "/nonexistent"),
        ],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("key `fluid.device`") && err.contains("mesa-vulkan-drivers"),
        "{err}"
    );
}
