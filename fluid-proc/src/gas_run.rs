//! fluid-proc's compressible Euler model, on one rank or several (part of
//! the binary; `ranks.rs` says how they work together): every rank obeys
//! rank 0's orders together: stepping (with the halo exchanges and the
//! global Δt), the monitors (sums and minima over the box) and the output
//! (gathered to rank 0, which writes it).
//!
//! Rigid bodies with a shape are walls of the gas (`gas_bodies.rs`): rank
//! 0 reads their states from rigid-proc at each window's start and shares
//! them; every rank moves them on through the window and adds the load on
//! its part of their surfaces; the sum goes back to rigid-proc.

use crate::comm::Comm;
use crate::compressible::{AdvanceReport, Compressible, GasCheckpoint, GasError};
use crate::driver::{declaration, Error};
use crate::gas::Primitive;
use crate::gas_bodies::Kinematics;
use crate::rank_checkpoint::{self, Place};
use crate::ranks::{Order, Stopped};
use crate::setup::gas_scene;
use exchange::body::read_states;
use exchange::fields::{BODY_LOADS, BODY_STATES, LOAD_LEN};
use exchange::Body;
use fluid_section::Scene;
use participant::vtu::{Image, Series};
use participant::{Command, Joining, Monitor, Participant};
use std::sync::Arc;

/// What obeying an order gave; only rank 0's is used.
enum Done {
    Monitors(Vec<Monitor>),
    /// The box's cells, on rank 0.
    Output(Option<(Vec<Primitive>, Vec<f64>)>),
    /// Monitors, steps taken, and the mean load on each body in the gas
    /// over the window (6 each: force [N], torque [N·m]), summed over ranks.
    Advanced(Vec<Monitor>, u64, Vec<f64>),
    Checkpoint,
    Stop,
}

/// One rank's gas, the window's checkpoint (implicit coupling), where run
/// checkpoints go, and the scenario's rigid bodies.
struct Gas {
    gas: Compressible,
    saved: GasCheckpoint,
    comm: Arc<dyn Comm>,
    place: Place,
    /// Every `[[rigid.bodies]]` entry (rigid-proc sends all of their
    /// states), and the index among them of each body in the gas.
    rigid: Vec<Body>,
    shaped: Vec<usize>,
    /// The box's low corner in the world [m].
    origin: [f64; 3],
    /// The states rank 0 read for the next window (13 per body).
    states: Vec<f64>,
}

impl Gas {
    /// The scene's gas on this rank, its bodies placed.
    fn new(scene: &Scene, comm: Arc<dyn Comm>) -> Result<Gas, String> {
        let s = gas_scene(scene, comm.clone())?;
        Ok(Gas {
            gas: s.gas,
            saved: GasCheckpoint::default(),
            comm,
            place: Place::default(),
            rigid: s.rigid,
            shaped: s.shaped,
            origin: s.origin,
            states: Vec::new(),
        })
    }

    /// On rank 0, before an advance: the states rigid-proc sent, for
    /// [`Gas::move_bodies`] to share.
    fn read_states(&mut self, p: &mut Participant) -> Result<(), participant::ExchangeError> {
        if p.is_connected(BODY_STATES) {
            self.states = p.read_field(BODY_STATES)?.to_vec();
        }
        Ok(())
    }

    /// The bodies where the states rank 0 read put them (every rank calls
    /// it together), moving on from the gas's present time.
    fn move_bodies(&mut self) -> Result<(), String> {
        let mut states = std::mem::take(&mut self.states);
        let mut len = [states.len() as f64];
        self.comm.broadcast(&mut len);
        states.resize(len[0] as usize, 0.0);
        self.comm.broadcast(&mut states);
        if states.is_empty() {
            return Ok(());
        }
        read_states(&mut self.rigid, &states)?;
        let t = self.gas.time;
        let kinematics: Vec<Kinematics> = self
            .shaped
            .iter()
            .map(|&i| Kinematics::of(&self.rigid[i], self.origin, t))
            .collect();
        if let Some(k) = kinematics.iter().position(|k| !k.is_finite()) {
            let name = &self.rigid[self.shaped[k]].name;
            return Err(format!("body `{name}` has a state that is not finite"));
        }
        self.gas.move_bodies(&kinematics);
        Ok(())
    }

    /// The mean load on every body of the scenario since the last call,
    /// summed over the ranks (every rank calls it together): 6 per body,
    /// zero on a mass point.
    fn loads(&mut self) -> Vec<f64> {
        let mut out = vec![0.0; LOAD_LEN * self.rigid.len()];
        for (body, &i) in self.gas.bodies.iter_mut().zip(&self.shaped) {
            let (f, t) = body.take_load();
            out[LOAD_LEN * i..LOAD_LEN * i + 3].copy_from_slice(&f);
            out[LOAD_LEN * i + 3..LOAD_LEN * (i + 1)].copy_from_slice(&t);
        }
        self.comm.sum(&mut out);
        out
    }
}

/// Obeys `order` on this rank (every rank calls it with the same order);
/// a failure fails on every rank together, with this message.
fn obey(g: &mut Gas, order: Order) -> Result<Done, String> {
    if let Order::Advance { .. } = order {
        g.move_bodies()?;
    }
    let gas = &mut g.gas;
    Ok(match order {
        Order::Monitors => Done::Monitors(monitors(gas, AdvanceReport::default())),
        Order::Output { .. } => {
            let cells = gas.gathered_primitives();
            let inside = gas.gathered_inside();
            Done::Output(cells.zip(inside))
        }
        Order::Advance { dt, window_end, .. } => {
            let report = gas
                .advance(dt)
                .map_err(|e: GasError| format!("gas step: {e}"))?;
            let m = if window_end {
                monitors(gas, report)
            } else {
                Vec::new()
            };
            Done::Advanced(m, report.steps, g.loads())
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
const GAS_MONITORS: [&str; 13] = [
    "mass",
    "momentum_x",
    "momentum_y",
    "momentum_z",
    "energy",
    "mass_in",
    "momentum_in_x",
    "momentum_in_y",
    "momentum_in_z",
    "energy_in",
    "min_density",
    "min_pressure",
    "steps",
];

/// Mass, momentum and energy of the gas cells, what has come in through
/// the box's sides since the start (the gas's budget: without bodies each
/// total less its inflow stays at its start), the lowest density and
/// pressure (what fails first), and the steps of the last call. Sums and
/// minima over every rank: every rank calls it together.
fn monitors(gas: &Compressible, r: AdvanceReport) -> Vec<Monitor> {
    let totals = gas.totals();
    let inflow = gas.inflow();
    let [density, pressure] = gas.lowest();
    let values = totals
        .into_iter()
        .chain(inflow)
        .chain([density, pressure, r.steps as f64]);
    GAS_MONITORS
        .iter()
        .zip(values)
        .map(|(name, v)| Monitor::new(*name, v))
        .collect()
}

/// Rank 0 (or the only rank): as many stable steps per window as the
/// fastest wave allows (`cfl`), the gas written as `fluid.pvd`; the
/// bodies' states read and their loads written every window.
pub fn lead(joining: Joining, scene: &Scene, comm: Arc<dyn Comm>) -> Result<(), Stopped> {
    let c = comm.as_ref();
    let mut g = Gas::new(scene, comm.clone()).map_err(|e| Stopped::before_order(c, e))?;
    let mut names: Vec<String> = GAS_MONITORS.iter().map(|n| n.to_string()).collect();
    names.extend(body_monitors(&g, None).into_iter().map(|m| m.name));
    let declared = declaration(g.rigid.len(), true, names).restarts();
    let mut p = joining
        .declare(declared)
        .map_err(|e| Stopped::before_order(c, e))?;
    g.place = Place::of(&p);
    let steps = p.reporting(|p| run(p, g, comm))?;
    p.finish(steps)?;
    Ok(())
}

/// The force on each body in the gas, from the window's `loads` (NaN
/// before the first window).
fn body_monitors(g: &Gas, loads: Option<&[f64]>) -> Vec<Monitor> {
    let mut out = Vec::new();
    for &i in &g.shaped {
        for (d, axis) in ["x", "y", "z"].iter().enumerate() {
            let v = loads.map_or(f64::NAN, |l| l[LOAD_LEN * i + d]);
            let name = format!("{}_fluid_force_{axis}", g.rigid[i].name);
            out.push(Monitor::new(name, v));
        }
    }
    out
}

/// The schedule's commands, turned into orders every rank obeys.
fn run(p: &mut Participant, mut g: Gas, comm: Arc<dyn Comm>) -> Result<u64, Stopped> {
    let origin = g.origin;
    let mut series = Series::new(p.run_dir(), "fluid");
    let mut steps = 0u64;
    loop {
        // A failure to hear the coupler stops the other ranks too.
        let mut command = p.next_command();
        if let Ok(Command::Advance(_)) = command {
            if let Err(e) = g.read_states(p) {
                command = Err(e);
            }
        }
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
            (_, Ok(Done::Monitors(mut m))) => {
                m.extend(body_monitors(&g, None));
                p.done(m)?
            }
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
                let (cells, inside) = cells.ok_or("rank 0 gathers the cells")?;
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
                        ("inside_body", 1, &inside),
                    ],
                };
                series.write_image(index, time, &image)?;
                p.done(Vec::new())?
            }
            (Command::Advance(a), Ok(Done::Advanced(mut m, n, loads))) => {
                steps += n;
                if p.is_connected(BODY_LOADS) {
                    p.write_field(BODY_LOADS, loads.len(), |out| out.copy_from_slice(&loads))?;
                }
                if a.window_end {
                    m.extend(body_monitors(&g, Some(&loads)));
                }
                p.done(m)?
            }
            (_, Ok(Done::Output(_) | Done::Advanced(..))) => {
                unreachable!("an output or advance order comes from its command")
            }
        }
    }
    Ok(steps)
}

/// A rank other than 0: obeys rank 0's orders until it stops, or until a
/// step fails (rank 0 meets the same failure and reports it).
#[cfg_attr(not(feature = "mpi"), allow(dead_code))]
pub fn follow(scene: &Scene, comm: Arc<dyn Comm>) -> Result<(), Error> {
    let mut g = Gas::new(scene, comm.clone())?;
    loop {
        let order = Order::Stop.share(comm.as_ref());
        match obey(&mut g, order) {
            Ok(Done::Stop) | Err(_) => return Ok(()),
            Ok(_) => {}
        }
    }
}
