//! The Euler model in the run loop (`run.rs`): as many stable steps per
//! window as the fastest wave allows (`cfl`), the gas written as
//! `fluid.pvd`. Every rank steps its slab together (with the halo
//! exchanges and the global Δt), sums the monitors (sums and minima over
//! the box) and gathers the output to rank 0, which writes it.
//!
//! Rigid bodies with a shape are walls of the gas (`bodies.rs`): rank 0
//! reads their states from rigid-proc at each window's start and shares
//! them; every rank moves them on through the window and adds the load on
//! its part of their surfaces; the sum goes back to rigid-proc.

use crate::comm::Comm;
use crate::driver::{declaration, Error};
use crate::euler::bodies::Kinematics;
use crate::euler::setup::gas_scene;
use crate::euler::{AdvanceReport, Compressible, GasCheckpoint, GasError};
use crate::model::{Cells, Lead, Model, Window};
use exchange::body::read_states;
use exchange::fields::{BODY_LOADS, BODY_STATES, LOAD_LEN};
use exchange::Body;
use fluid_section::Scene;
use participant::{Advance, Declaration, Monitor, Participant};
use std::sync::Arc;

/// One rank's gas and the scenario's rigid bodies.
pub struct Gas {
    gas: Compressible,
    comm: Arc<dyn Comm>,
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

    /// The force on each body in the gas, from the window's `loads` (NaN
    /// before the first window).
    fn body_monitors(&self, loads: Option<&[f64]>) -> Vec<Monitor> {
        let mut out = Vec::new();
        for &i in &self.shaped {
            for (d, axis) in ["x", "y", "z"].iter().enumerate() {
                let v = loads.map_or(f64::NAN, |l| l[LOAD_LEN * i + d]);
                let name = format!("{}_fluid_force_{axis}", self.rigid[i].name);
                out.push(Monitor::new(name, v));
            }
        }
        out
    }
}

/// What an advance hands rank 0: the gas's monitors at a window's end,
/// and the mean load on each body over the window (6 each: force [N],
/// torque [N·m]), summed over the ranks.
pub struct Advanced {
    monitors: Vec<Monitor>,
    loads: Vec<f64>,
}

impl Model for Gas {
    type Advanced = Advanced;
    type Started = Vec<Monitor>;
    type Saved = GasCheckpoint;
    const FIELD: bool = true;

    /// The scene's gas on this rank, its bodies placed.
    fn on(scene: &Scene, comm: Arc<dyn Comm>) -> Result<Gas, String> {
        let s = gas_scene(scene, comm.clone())?;
        Ok(Gas {
            gas: s.gas,
            comm,
            rigid: s.rigid,
            shaped: s.shaped,
            origin: s.origin,
            states: Vec::new(),
        })
    }

    fn start(&mut self) -> Vec<Monitor> {
        monitors(&self.gas, AdvanceReport::default())
    }

    fn advance(&mut self, w: Window) -> Result<(Advanced, u64), String> {
        self.move_bodies()?;
        let report = self
            .gas
            .advance(w.dt)
            .map_err(|e: GasError| format!("gas step: {e}"))?;
        let monitors = match w.window_end {
            true => monitors(&self.gas, report),
            false => Vec::new(),
        };
        let loads = self.loads();
        Ok((Advanced { monitors, loads }, report.steps))
    }

    fn save(&self, into: &mut GasCheckpoint) {
        self.gas.save(into);
    }

    fn restore(&mut self, from: &GasCheckpoint) -> Result<(), String> {
        match self.gas.restore(from) {
            true => Ok(()),
            false => Err("another part of the gas than this rank's".into()),
        }
    }

    fn cells(&mut self) -> Option<Cells> {
        let (cells, inside) = self
            .gas
            .gathered_primitives()
            .zip(self.gas.gathered_inside())?;
        let density = cells.iter().map(|w| w.density).collect();
        let velocity = cells.iter().flat_map(|w| w.velocity).collect();
        let pressure = cells.iter().map(|w| w.pressure).collect();
        Some(Cells {
            origin: self.origin,
            spacing: self.gas.setup.h,
            cells: self.gas.setup.n,
            faces: None,
            fields: vec![
                ("density", 1, density),
                ("velocity", 3, velocity),
                ("pressure", 1, pressure),
                ("inside_body", 1, inside),
            ],
        })
    }
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

/// What rank 0 reads and answers for the gas: the bodies' states in, their
/// loads out. It keeps nothing of its own: the bodies are the model's.
pub struct Walls;

impl Lead for Walls {
    type Model = Gas;

    fn new(_: &Scene, _: &mut Gas) -> Result<Walls, String> {
        Ok(Walls)
    }

    fn declaration(&self, g: &Gas) -> Declaration {
        let mut names: Vec<String> = GAS_MONITORS.iter().map(|n| n.to_string()).collect();
        names.extend(g.body_monitors(None).into_iter().map(|m| m.name));
        declaration(g.rigid.len(), true, names)
    }

    fn start(
        &mut self,
        _: &mut Participant,
        g: &mut Gas,
        mut monitors: Vec<Monitor>,
    ) -> Result<Vec<Monitor>, Error> {
        monitors.extend(g.body_monitors(None));
        Ok(monitors)
    }

    /// The states rigid-proc sent, for [`Gas::move_bodies`] to share.
    fn place(&mut self, p: &mut Participant, g: &mut Gas, _: &Advance) -> Result<(), Error> {
        if p.is_connected(BODY_STATES) {
            g.states = p.read_field(BODY_STATES)?.to_vec();
        }
        Ok(())
    }

    fn answer(
        &mut self,
        p: &mut Participant,
        g: &mut Gas,
        advanced: Advanced,
        a: &Advance,
    ) -> Result<Vec<Monitor>, Error> {
        let loads = &advanced.loads;
        if p.is_connected(BODY_LOADS) {
            p.write_field(BODY_LOADS, loads.len(), |out| out.copy_from_slice(loads))?;
        }
        let mut monitors = advanced.monitors;
        if a.window_end {
            monitors.extend(g.body_monitors(Some(loads)));
        }
        Ok(monitors)
    }
}
