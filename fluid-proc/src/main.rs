//! fluid-proc: the flow models taking part in a coupled run.

fn main() {
    if let Err(e) = fluid_proc::driver::run() {
        eprintln!("fluid-proc: {e}");
        std::process::exit(1);
    }
}
