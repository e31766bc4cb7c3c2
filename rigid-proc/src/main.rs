//! rigid-proc: the rigid-body library taking part in a coupled run.

fn main() {
    if let Err(e) = rigid_proc::driver::run() {
        eprintln!("rigid-proc: {e}");
        std::process::exit(1);
    }
}
