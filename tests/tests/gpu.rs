//! `[structure] device = "gpu"` from the scenario to the run (issue 25):
//! a coupled scene on the GPU gives the CPU's monitors, and `check` refuses
//! what the device does not run, naming the key. CI runs these on Mesa's
//! CPU Vulkan adapter; `CANOPY_REQUIRE_GPU` makes a missing adapter a
//! failure there, elsewhere the scene test says so and passes.

use canopy_tests::*;
use std::path::{Path, PathBuf};
use structure_section::{Device, Integrator};

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

/// `name` cut to `end_time` [s] on `device`, written under `dir`.
fn on(dir: &Path, name: &str, end_time: f64, device: Device) -> PathBuf {
    let sub = dir.join(format!("{device:?}"));
    std::fs::create_dir_all(&sub).unwrap();
    variant(name, &sub, |s| {
        s.run.end_time = end_time;
        s.run.output_interval = 0.0;
        s.structure.as_mut().unwrap().device = device;
    })
}

/// `name` to `end_time` on the GPU and on the CPU: every monitor the same
/// to round-off (both run the same passes in f64; a GPU may fuse multiplies
/// and adds), far below the 10⁻⁶ the CSV resolves. Returns the CPU's
/// monitors, or `None` where no adapter is found and CI does not require one.
fn same_on_both(name: &str, end_time: f64) -> Option<Monitors> {
    let dir = scratch(&format!("gpu-{name}"));
    let on_gpu = on(&dir, name, end_time, Device::Gpu);
    let (code, err) = check(&on_gpu, &[]);
    if code != Some(0)
        && err.contains("no GPU adapter")
        && std::env::var_os("CANOPY_REQUIRE_GPU").is_none()
    {
        eprintln!("skipped: {err}");
        return None;
    }
    assert_eq!(code, Some(0), "{err}");
    run_ok(&on_gpu, &dir.join("gpu"));
    run_ok(&on(&dir, name, end_time, Device::Cpu), &dir.join("cpu"));
    let (gpu, cpu) = (
        Monitors::read(&dir.join("gpu")),
        Monitors::read(&dir.join("cpu")),
    );
    assert_eq!(gpu.header, cpu.header, "{name}: the same monitors");
    for column in &cpu.header {
        let (a, b) = (gpu.column(column), cpu.column(column));
        assert_eq!(a.len(), b.len(), "{name}, {column}: as many rows");
        for (t, (x, y)) in a.iter().zip(&b).enumerate() {
            // A monitor not yet reported reads NaN on both.
            let same = (x.is_nan() && y.is_nan()) || (x - y).abs() <= 1e-9 * (1.0 + y.abs());
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
