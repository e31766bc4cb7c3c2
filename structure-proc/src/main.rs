//! structure-proc: the spring-mass library driven by the coupler, advanced by
//! the integrator the scenario names, on the CPU or the GPU it names.

use structure_proc::driver::{self, Error, Scheme, Stepper};
use structure_proc::Model;
use structure_section::{Device, StructureSection};

fn main() {
    driver::main(
        "structure-proc",
        |section, m| -> Result<Box<dyn Stepper>, Error> {
            Ok(match section.device {
                Device::Cpu => Box::new(Scheme::of(section)),
                Device::Gpu => on_device(section, m)?,
            })
        },
    );
}

#[cfg(feature = "gpu")]
fn on_device(section: &StructureSection, m: &Model) -> Result<Box<dyn Stepper>, Error> {
    Ok(Box::new(structure_proc::gpu::OnDevice::new(section, m)?))
}

/// Built without the `gpu` feature: `--check` puts this at the `device` key.
#[cfg(not(feature = "gpu"))]
fn on_device(_: &StructureSection, _: &Model) -> Result<Box<dyn Stepper>, Error> {
    Err("this structure-proc was built without its `gpu` feature (cargo build -p structure-proc --features gpu)".into())
}
