//! fluid-proc's compressible Euler model, on one rank or several (part of
//! the binary; `ranks.rs` says how they work together): every rank obeys
//! rank 0's orders together: stepping (with the halo exchanges and the
//! global Δt), the monitors (sums and minima over the box) and the output
//! (gathered to rank 0, which writes it).

use crate::comm::Comm;
use crate::compressible::{AdvanceReport, Compressible, GasCheckpoint, GasError};
use crate::driver::{declaration, Error};
use crate::gas::Primitive;
use crate::rank_checkpoint::{self, Place};
use crate::ranks::{Order, Stopped};
use crate::setup::gas_on;
use fluid_section::FluidSection;
use participant::vtu::{Image, Series};
use participant::{Command, Joining, Monitor, Participant};
use std::sync::Arc;

/// What obeying an order gave; only rank 0's is used.
enum Done {
    Monitors(Vec<Monitor>),
    /// The box's cells, on rank 0.
    Output(Option<Vec<Primitive>>),
    Advanced(Vec<Monitor>, u64),
    Checkpoint,
    Stop,
}

/// One rank's gas, the window's checkpoint (implicit coupling), and where
/// run checkpoints go.
struct Gas {
    gas: Compressible,
    saved: GasCheckpoint,
    comm: Arc<dyn Comm>,
    place: Place,
}

impl Gas {
    fn new(gas: Compressible, comm: Arc<dyn Comm>) -> Gas {
        Gas {
            gas,
            saved: GasCheckpoint::default(),
            comm,
            place: Place::default(),
        }
    }
}

/// Obeys `order` on this rank (every rank calls it with the same order);
/// a failure fails on every rank together, with this message.
fn obey(g: &mut Gas, order: Order) -> Result<Done, String> {
    let gas = &mut g.gas;
    Ok(match order {
        Order::Monitors => Done::Monitors(monitors(gas, AdvanceReport::default())),
        Order::Output { .. } => Done::Output(gas.gathered_primitives()),
        Order::Advance { dt, window_end, .. } => {
            let report = gas
                .advance(dt)
                .map_err(|e: GasError| format!("gas step: {e}"))?;
            let m = if window_end {
                monitors(gas, report)
            } else {
                Vec::new()
            };
            Done::Advanced(m, report.steps)
        }
        Order::Checkpoint { restore: false } => {
            gas.save(&mut g.saved);
            Done::Checkpoint
        }
        Order::Checkpoint { restore: true } => {
            gas.restore(&g.saved);
            Done::Checkpoint
        }
        Order::RunCheckpoint { window, resume } => {
            let (comm, place) = (g.comm.as_ref(), &g.place);
            match resume {
                false => {
                    gas.save(&mut g.saved);
                    rank_checkpoint::write_part(comm, place, window, &g.saved)?;
                }
                true => {
                    rank_checkpoint::read_part(comm, place, window, |c: GasCheckpoint| {
                        match gas.restore(&c) {
                            true => Ok(()),
                            false => Err("another part of the gas than this rank's".into()),
                        }
                    })?
                }
            }
            Done::Checkpoint
        }
        Order::Stop => Done::Stop,
    })
}

/// The gas's monitors, in the order [`monitors`] reports them.
const GAS_MONITORS: [&str; 5] = ["mass", "energy", "min_density", "min_pressure", "steps"];

/// Mass and energy (conserved but for what crosses the sides), the lowest
/// density and pressure (what fails first), and the steps of the last call.
/// Sums and minima over every rank: every rank calls it together.
fn monitors(gas: &Compressible, r: AdvanceReport) -> Vec<Monitor> {
    let totals = gas.totals();
    let [density, pressure] = gas.lowest();
    let values = [totals[0], totals[4], density, pressure, r.steps as f64];
    GAS_MONITORS
        .iter()
        .zip(values)
        .map(|(name, v)| Monitor::new(*name, v))
        .collect()
}

/// Rank 0 (or the only rank): as many stable steps per window as the
/// fastest wave allows (`cfl`), the gas written as `fluid.pvd`. The gas
/// exchanges no field yet.
pub fn lead(joining: Joining, section: &FluidSection, comm: Arc<dyn Comm>) -> Result<(), Stopped> {
    let c = comm.as_ref();
    let gas = gas_on(section, comm.clone()).ok_or_else(|| {
        Stopped::before_order(c, "[fluid] lacks the box or the regions of the euler model")
    })?;
    let names = GAS_MONITORS.iter().map(|n| n.to_string()).collect();
    let mut p = joining
        .declare(declaration(0, false, names).restarts())
        .map_err(|e| Stopped::before_order(c, e))?;
    let mut g = Gas::new(gas, comm.clone());
    g.place = Place::of(&p);
    let steps = p.reporting(|p| run(p, g, section, comm))?;
    p.finish(steps)?;
    Ok(())
}

/// The schedule's commands, turned into orders every rank obeys.
fn run(
    p: &mut Participant,
    mut g: Gas,
    section: &FluidSection,
    comm: Arc<dyn Comm>,
) -> Result<u64, Stopped> {
    let origin = section.flow_box.map_or([0.0; 3], |b| b.lower);
    let mut series = Series::new(p.run_dir(), "fluid");
    let mut steps = 0u64;
    loop {
        // A failure to hear the coupler stops the other ranks too.
        let command = p.next_command();
        let order = command.as_ref().map_or(Order::Stop, Order::of);
        order.share(comm.as_ref());
        match (command?, obey(&mut g, order)) {
            (_, Err(msg)) => {
                p.fail(msg.clone())?;
                return Err(Stopped {
                    error: msg.into(),
                    together: true,
                });
            }
            (_, Ok(Done::Stop)) => break,
            (_, Ok(Done::Monitors(m))) => p.done(m)?,
            (Command::WriteCheckpoint { window }, Ok(Done::Checkpoint)) => {
                rank_checkpoint::write_lead(p, window, &series, steps)?;
                p.done(Vec::new())?
            }
            (Command::Resume { window }, Ok(Done::Checkpoint)) => {
                steps = rank_checkpoint::read_lead(p, window, &mut series)?;
                p.done(Vec::new())?
            }
            (_, Ok(Done::Checkpoint)) => p.done(Vec::new())?,
            (Command::Output { index, time }, Ok(Done::Output(cells))) => {
                let cells = cells.ok_or("rank 0 gathers the cells")?;
                let density: Vec<f64> = cells.iter().map(|w| w.density).collect();
                let velocity: Vec<f64> = cells.iter().flat_map(|w| w.velocity).collect();
                let pressure: Vec<f64> = cells.iter().map(|w| w.pressure).collect();
                let image = Image {
                    origin,
                    spacing: g.gas.setup.h,
                    cells: g.gas.setup.n,
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
    let gas = gas_on(section, comm.clone()).ok_or("[fluid] lacks the box or the regions")?;
    let mut g = Gas::new(gas, comm.clone());
    loop {
        let order = Order::Stop.share(comm.as_ref());
        match obey(&mut g, order) {
            Ok(Done::Stop) | Err(_) => return Ok(()),
            Ok(_) => {}
        }
    }
}
