//! How fluid-proc's ranks work together (part of the binary). Rank 0 alone
//! speaks to the coupler; it turns each command into an [`Order`],
//! broadcasts it, and every rank obeys it together (the run loop,
//! `run.rs`). One rank is the same code with a `Single` communicator.

use crate::comm::Comm;
use crate::driver::Error;

/// What every rank does next.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Order {
    Monitors,
    Output {
        index: u64,
        time: f64,
    },
    /// A window of `dt`, in `substeps` equal steps where the model takes
    /// the coupler's (the euler model picks its own).
    Advance {
        dt: f64,
        substeps: u32,
        window_end: bool,
    },
    /// Save the window's start (implicit coupling), or return to it.
    Checkpoint {
        restore: bool,
    },
    /// Write a run checkpoint at the end of `window`, or read it back
    /// (`resume`), each rank its part.
    RunCheckpoint {
        window: u64,
        resume: bool,
    },
    Stop,
}

impl Order {
    /// What the ranks do for the schedule's `command`.
    pub fn of(command: &participant::Command) -> Order {
        use participant::Command;
        match *command {
            Command::Initialize => Order::Monitors,
            Command::Output { index, time } => Order::Output { index, time },
            Command::Advance(a) => Order::Advance {
                dt: a.dt,
                substeps: a.substeps,
                window_end: a.window_end,
            },
            Command::SaveCheckpoint => Order::Checkpoint { restore: false },
            Command::RestoreCheckpoint => Order::Checkpoint { restore: true },
            Command::WriteCheckpoint { window } => Order::RunCheckpoint {
                window,
                resume: false,
            },
            Command::Resume { window } => Order::RunCheckpoint {
                window,
                resume: true,
            },
            Command::Stop => Order::Stop,
        }
    }

    /// As four numbers, for the broadcast.
    fn encode(self) -> [f64; 4] {
        match self {
            Order::Monitors => [0.0; 4],
            Order::Output { index, time } => [1.0, index as f64, time, 0.0],
            Order::Advance {
                dt,
                substeps,
                window_end,
            } => [2.0, dt, window_end as u8 as f64, substeps as f64],
            Order::Stop => [3.0, 0.0, 0.0, 0.0],
            Order::Checkpoint { restore } => [4.0, restore as u8 as f64, 0.0, 0.0],
            // Exact for windows below 2⁵³.
            Order::RunCheckpoint { window, resume } => {
                [5.0, window as f64, resume as u8 as f64, 0.0]
            }
        }
    }

    fn decode(x: [f64; 4]) -> Order {
        match x[0] as u8 {
            0 => Order::Monitors,
            1 => Order::Output {
                index: x[1] as u64,
                time: x[2],
            },
            2 => Order::Advance {
                dt: x[1],
                window_end: x[2] != 0.0,
                substeps: x[3] as u32,
            },
            4 => Order::Checkpoint {
                restore: x[1] != 0.0,
            },
            5 => Order::RunCheckpoint {
                window: x[1] as u64,
                resume: x[2] != 0.0,
            },
            _ => Order::Stop,
        }
    }

    /// Rank 0's order on every rank (the others pass anything).
    pub fn share(self, comm: &dyn Comm) -> Order {
        let mut x = self.encode();
        comm.broadcast(&mut x);
        Order::decode(x)
    }
}

/// Why a lead stopped early.
#[derive(Debug)]
pub struct Stopped {
    pub error: Error,
    /// Whether every rank stopped with it (a failed step, which all ranks
    /// meet together, or a Stop order shared before leaving), or rank 0
    /// alone (the others must then be aborted).
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    pub together: bool,
}

impl<E: Into<Error>> From<E> for Stopped {
    fn from(e: E) -> Stopped {
        Stopped {
            error: e.into(),
            together: false,
        }
    }
}

impl std::fmt::Display for Stopped {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        self.error.fmt(f)
    }
}

impl Stopped {
    /// Rank 0 stops alone before an order: it tells the others to stop too.
    pub fn before_order(comm: &dyn Comm, error: impl Into<Error>) -> Stopped {
        Order::Stop.share(comm);
        Stopped {
            error: error.into(),
            together: true,
        }
    }
}

/// fluid-proc started under `mpirun` (`[participants.fluid] ranks = N`).
#[cfg(feature = "mpi")]
pub fn ranks() -> Result<(), Error> {
    use crate::euler::run::Gas;
    use crate::incompressible::run::Flow;
    use crate::mpi_comm::MpiComm;
    use crate::run::follow;
    use fluid_section::FluidModel;
    use fluid_section::Scene;
    use std::sync::Arc;
    let universe = mpi::initialize().ok_or("MPI was initialised twice")?;
    let mpi = Arc::new(MpiComm::new(&universe));
    let comm: Arc<dyn Comm> = mpi.clone();
    let (mut path, mut text) = (String::new(), String::new());
    let result = if comm.rank() == 0 {
        (|| -> Result<(), Stopped> {
            let (joining, scenario, section) = crate::driver::connect()?;
            path = joining.scenario_path().display().to_string();
            text = joining.scenario().to_string();
            comm.broadcast_text(&mut path);
            comm.broadcast_text(&mut text);
            if section.model == FluidModel::PorousFreeStream {
                let msg = format!("model = \"{}\" runs on one rank only", section.model.name());
                return Err(msg.into());
            }
            crate::driver::lead(joining, &scenario, comm.clone())
        })()
    } else {
        comm.broadcast_text(&mut path);
        comm.broadcast_text(&mut text);
        (|| -> Result<(), Stopped> {
            let scene = Scene::load(std::path::Path::new(&path), &text)?;
            match scene.fluid.model {
                FluidModel::Euler => follow::<Gas>(&scene, comm.clone())?,
                FluidModel::Incompressible => follow::<Flow>(&scene, comm.clone())?,
                FluidModel::PorousFreeStream => {}
            }
            Ok(())
        })()
    };
    match result {
        Ok(()) => Ok(()),
        // Every rank has left its loop: MPI finalises as the universe drops.
        Err(Stopped {
            error,
            together: true,
        }) => Err(error),
        // One rank alone cannot finish the others' collectives: stop them all.
        Err(Stopped { error, .. }) => {
            eprintln!("fluid-proc (rank {}): {error}", comm.rank());
            mpi.abort(1)
        }
    }
}

/// fluid-proc built without MPI, started under `mpirun` all the same.
#[cfg(not(feature = "mpi"))]
pub fn ranks() -> Result<(), Error> {
    Err(
        "the scenario asks for several ranks, but this fluid-proc was built without MPI: \
         build it with `cargo build --release -p fluid-proc --features mpi` (needs OpenMPI: \
         apt-get install libopenmpi-dev openmpi-bin libclang1-14 libclang-common-14-dev)"
            .into(),
    )
}
