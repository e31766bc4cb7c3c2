//! xpbd-proc: the structure participant advanced by XPBD. A scenario selects it
//! with `[participants.structure] program = "xpbd-proc"`; nothing else changes.

use structure_proc::driver;
use structure_section::Device;
use xpbd_proc::Xpbd;

fn main() {
    driver::main("xpbd-proc", |section, model| {
        if section.device == Device::Gpu {
            return Err("xpbd-proc runs on the CPU only; structure-proc runs the GPU".into());
        }
        Ok(Xpbd::new(model)?)
    });
}
