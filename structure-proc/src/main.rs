//! structure-proc: the spring-mass library driven by the coupler, advanced by
//! the integrator the scenario names, on the CPU or the GPU it names.

use structure_proc::driver::{self, Error, Scheme, Stepper};
use structure_proc::gpu::OnDevice;
use structure_section::Device;

fn main() {
    driver::main(
        "structure-proc",
        |section, m| -> Result<Box<dyn Stepper>, Error> {
            Ok(match section.device {
                Device::Cpu => Box::new(Scheme::of(section)),
                Device::Gpu => Box::new(OnDevice::new(section, m)?),
            })
        },
    );
}
