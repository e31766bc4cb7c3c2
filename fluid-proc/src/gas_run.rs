//! fluid-proc's compressible Euler model, on one rank or several (part of
//! the binary). Rank 0 alone speaks to the coupler; it turns each command
//! into an [`Order`], broadcasts it, and every rank obeys it together:
//! stepping (with the halo exchanges and the global Δt), the monitors
//! (sums and minima over the box) and the output (gathered to rank 0, which
//! writes it). One rank is the same code with a [`Single`] communicator.

use crate::Error;
use coupler::scenario::FluidSection;
use coupler::vtu::{Image, Series};
use coupler::{Command, Monitor, Participant};
use fluid_proc::comm::Comm;
use fluid_proc::compressible::{AdvanceReport, Compressible, GasError};
use fluid_proc::gas::Primitive;
use fluid_proc::setup::gas_on;
use std::sync::Arc;

/// What every rank does next.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Order {
    Monitors,
    Output { index: u64, time: f64 },
    Advance { dt: f64, window_end: bool },
    Stop,
}

impl Order {
    /// As four numbers, for the broadcast.
    fn encode(self) -> [f64; 4] {
        match self {
            Order::Monitors => [0.0; 4],
            Order::Output { index, time } => [1.0, index as f64, time, 0.0],
            Order::Advance { dt, window_end } => [2.0, dt, window_end as u8 as f64, 0.0],
            Order::Stop => [3.0, 0.0, 0.0, 0.0],
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
            },
            _ => Order::Stop,
        }
    }

    fn share(self, comm: &dyn Comm) -> Order {
        let mut x = self.encode();
        comm.broadcast(&mut x);
        Order::decode(x)
    }
}

/// What obeying an order gave; only rank 0's is used.
enum Done {
    Monitors(Vec<Monitor>),
    /// The box's cells, on rank 0.
    Output(Option<Vec<Primitive>>),
    Advanced(Vec<Monitor>, u64),
    Stop,
}

/// Obeys `order` on this rank (every rank calls it with the same order).
fn obey(gas: &mut Compressible, order: Order) -> Result<Done, GasError> {
    Ok(match order {
        Order::Monitors => Done::Monitors(monitors(gas, AdvanceReport::default())),
        Order::Output { .. } => Done::Output(gas.gathered_primitives()),
        Order::Advance { dt, window_end } => {
            let report = gas.advance(dt)?;
            let m = if window_end {
                monitors(gas, report)
            } else {
                Vec::new()
            };
            Done::Advanced(m, report.steps)
        }
        Order::Stop => Done::Stop,
    })
}

/// Mass and energy (conserved but for what crosses the sides), the lowest
/// density and pressure (what fails first), and the steps of the last call.
fn monitors(gas: &Compressible, r: AdvanceReport) -> Vec<Monitor> {
    let totals = gas.totals();
    let [density, pressure] = gas.lowest();
    vec![
        Monitor::new("mass", totals[0]),
        Monitor::new("energy", totals[4]),
        Monitor::new("min_density", density),
        Monitor::new("min_pressure", pressure),
        Monitor::new("steps", r.steps as f64),
    ]
}

/// Why [`lead`] stopped early.
pub struct Stopped {
    pub error: Error,
    /// Whether every rank stopped with it (a failed step, which all ranks
    /// meet together), or rank 0 alone (the others must then be aborted).
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

/// Rank 0 (or the only rank): as many stable steps per window as the
/// fastest wave allows (`cfl`), the gas written as `fluid.pvd`.
pub fn lead(
    p: &mut Participant,
    section: &FluidSection,
    comm: Arc<dyn Comm>,
) -> Result<u64, Stopped> {
    let mut gas = gas_on(section, comm.clone())
        .ok_or("[fluid] lacks the box or the regions of the euler model")?;
    let origin = section.flow_box.map_or([0.0; 3], |b| b.lower);
    let mut series = Series::new(p.run_dir(), "fluid");
    let mut steps = 0u64;
    loop {
        // A failure to hear the coupler stops the other ranks too.
        let command = p.next_command();
        let order = match &command {
            Ok(Command::Initialize) => Order::Monitors,
            Ok(Command::Output { index, time }) => Order::Output {
                index: *index,
                time: *time,
            },
            Ok(Command::Advance(a)) => Order::Advance {
                dt: a.dt,
                window_end: a.window_end,
            },
            _ => Order::Stop,
        };
        order.share(comm.as_ref());
        match (command?, obey(&mut gas, order)) {
            (_, Err(e)) => {
                let msg = format!("gas step: {e}");
                p.fail(msg.clone())?;
                return Err(Stopped {
                    error: msg.into(),
                    together: true,
                });
            }
            (Command::Setup(_), _) => return Err("unexpected second setup".into()),
            (_, Ok(Done::Stop)) => break,
            (_, Ok(Done::Monitors(m))) => p.done(m)?,
            (Command::Output { index, time }, Ok(Done::Output(cells))) => {
                let cells = cells.ok_or("rank 0 gathers the cells")?;
                let density: Vec<f64> = cells.iter().map(|w| w.density).collect();
                let velocity: Vec<f64> = cells.iter().flat_map(|w| w.velocity).collect();
                let pressure: Vec<f64> = cells.iter().map(|w| w.pressure).collect();
                let image = Image {
                    origin,
                    spacing: gas.setup.h,
                    cells: gas.setup.n,
                    cell_data: vec![
                        ("density", 1, &density),
                        ("velocity", 3, &velocity),
                        ("pressure", 1, &pressure),
                    ],
                };
                series.write_image(index, time, &image)?;
                p.done(Vec::new())?
            }
            (_, Ok(Done::Advanced(m, n))) => {
                steps += n;
                p.done(m)?
            }
            (_, Ok(Done::Output(_))) => {
                unreachable!("an output order comes from an output command")
            }
        }
    }
    Ok(steps)
}

/// A rank other than 0: obeys rank 0's orders until it stops, or until a
/// step fails (rank 0 meets the same failure and reports it).
#[cfg_attr(not(feature = "mpi"), allow(dead_code))]
pub fn follow(section: &FluidSection, comm: Arc<dyn Comm>) -> Result<(), Error> {
    let mut gas = gas_on(section, comm.clone()).ok_or("[fluid] lacks the box or the regions")?;
    loop {
        let order = Order::Stop.share(comm.as_ref());
        match obey(&mut gas, order) {
            Ok(Done::Stop) | Err(_) => return Ok(()),
            Ok(_) => {}
        }
    }
}

/// fluid-proc started under `mpirun` (`[participants.fluid] ranks = N`).
#[cfg(feature = "mpi")]
pub fn ranks() -> Result<(), Error> {
    use coupler::scenario::fluid::FluidModel;
    use coupler::{Role, Scenario};
    use fluid_proc::mpi_comm::MpiComm;
    let universe = mpi::initialize().ok_or("MPI was initialised twice")?;
    let mpi = Arc::new(MpiComm::new(&universe));
    let comm: Arc<dyn Comm> = mpi.clone();
    let mut text = String::new();
    let result = if comm.rank() == 0 {
        (|| -> Result<(), Stopped> {
            let mut p = Participant::connect(Role::Fluid)?;
            text = p.scenario().to_toml();
            comm.broadcast_text(&mut text);
            let section = p
                .scenario()
                .fluid
                .clone()
                .ok_or("the scenario has no [fluid] section")?;
            if section.model != FluidModel::Euler {
                let msg = format!("model = \"{}\" runs on one rank only", section.model.name());
                return Err(msg.into());
            }
            let steps = lead(&mut p, &section, comm.clone())?;
            p.finish(steps)?;
            Ok(())
        })()
    } else {
        comm.broadcast_text(&mut text);
        (|| -> Result<(), Stopped> {
            let scenario = Scenario::from_resolved(&text)?;
            let section = scenario
                .fluid
                .ok_or("the scenario has no [fluid] section")?;
            Ok(follow(&section, comm.clone())?)
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
