//! xpbd-proc: the structure participant advanced by XPBD. A scenario selects it
//! with `[participants.structure] program = "xpbd-proc"`; nothing else changes.

use structure_proc::driver;
use xpbd_proc::Xpbd;

fn main() {
    driver::main("xpbd-proc", |_, model| Ok(Xpbd::new(model)?));
}
