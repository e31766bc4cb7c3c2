//! `[structure] device = "gpu"` from the scenario to the run (issue 25):
//! a coupled scene on the GPU gives the CPU's monitors, and `check` refuses
//! what the device does not run, naming the key. CI runs these on Mesa's
//! CPU Vulkan adapter; `CANOPY_REQUIRE_GPU` makes a missing adapter a
//! failure there, elsewhere the scene test says so and passes.

use canopy_tests::*;
use structure_section::{Device, Integrator};

/// `coupler check` of `scenario`: exit code and stderr.
fn check(scenario: &std::path::Path, env: &[(&str, &str)]) -> (Option<i32>, String) {
    let mut command = std::process::Command::new(coupler_exe());
    command.args(["check", scenario.to_str().unwrap()]);
    command.envs(env.iter().copied());
    let o = command.output().expect("run coupler");
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// `canopy-porous` (the fluid's porous free stream loading the annulus,
/// velocity Verlet, thesis eq. 68's dampers) for 0.2 s on `device`.
fn canopy_porous(dir: &std::path::Path, device: Device) -> std::path::PathBuf {
    let sub = dir.join(format!("{device:?}"));
    std::fs::create_dir_all(&sub).unwrap();
    variant("canopy-porous", &sub, |s| {
        s.run.end_time = 0.2;
        s.run.output_interval = 0.0;
        s.structure.as_mut().unwrap().device = device;
    })
}

#[test]
fn a_coupled_scene_on_the_gpu_gives_the_cpus_monitors() {
    let dir = scratch("gpu-scene");
    let on_gpu = canopy_porous(&dir, Device::Gpu);
    let (code, err) = check(&on_gpu, &[]);
    if code != Some(0)
        && err.contains("no GPU adapter")
        && std::env::var_os("CANOPY_REQUIRE_GPU").is_none()
    {
        eprintln!("skipped: {err}");
        return;
    }
    assert_eq!(code, Some(0), "{err}");
    run_ok(&on_gpu, &dir.join("gpu"));
    run_ok(&canopy_porous(&dir, Device::Cpu), &dir.join("cpu"));
    let (gpu, cpu) = (
        Monitors::read(&dir.join("gpu")),
        Monitors::read(&dir.join("cpu")),
    );
    let deflection = cpu.column("structure.centre_deflection");
    assert!(
        deflection.last().unwrap().abs() > 0.05,
        "the stream bends the canopy: {deflection:?}"
    );
    // Both run the same passes in f64: round-off apart at most (fused
    // multiply–adds on a GPU), far below the 10⁻⁶ m the CSV prints.
    for name in [
        "structure.centre_deflection",
        "structure.kinetic_energy",
        "structure.potential_energy",
    ] {
        let (a, b) = (gpu.column(name), cpu.column(name));
        assert_eq!(a.len(), b.len(), "{name}: as many rows");
        for (t, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!(
                (x - y).abs() <= 1e-9 * (1.0 + y.abs()),
                "{name}, row {t}: GPU {x}, CPU {y}"
            );
        }
    }
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
