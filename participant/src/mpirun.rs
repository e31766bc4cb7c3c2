//! How a program is started on MPI ranks under `mpirun`: by the coupler
//! for `ranks = N`, and by fluid-proc's benchmark for its ranks column.

/// `mpirun`'s arguments to start `program args` on `ranks` ranks. More
/// ranks than cores are allowed (`--oversubscribe`): a run asks for ranks
/// for its decomposition, not for its speed alone.
pub fn args(ranks: u32, program: &std::path::Path, args: &[String]) -> Vec<String> {
    let mut all = vec![
        "-n".to_string(),
        ranks.to_string(),
        "--oversubscribe".to_string(),
        program.display().to_string(),
    ];
    all.extend(args.iter().cloned());
    all
}

/// What the ranks need in their environment: their count, and OpenMPI's
/// consent to run as root (containers and CI run as root; mpirun refuses
/// it otherwise).
pub fn env(ranks: u32) -> [(&'static str, String); 3] {
    [
        (crate::names::ENV_RANKS, ranks.to_string()),
        ("OMPI_ALLOW_RUN_AS_ROOT", "1".to_string()),
        ("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1".to_string()),
    ]
}
