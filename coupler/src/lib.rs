//! The `coupler` executable's library half: check a scenario, launch and
//! supervise its participants, write the run directory, run the benches.
//! Solvers link the `participant` library instead; the protocol both sides
//! speak is described in `docs/PROTOCOL.md`.

pub mod launcher;
