//! The porous free-stream model in the run loop (`run.rs`): a pressure
//! jump on each canopy triangle from the Darcy–Forchheimer law of thesis
//! §2.1 (the `porous` crate, which structure solvers apply too with
//! `[structure.porous]`), on the canopy the structure left at the window's
//! start. There is no flow field: nothing to write, and the jumps depend
//! on the window's inputs alone, so there is nothing to save either.
//! It runs on one rank.

use crate::comm::Comm;
use crate::driver::{declaration, Error};
use crate::model::{Cells, Lead, Model, Window};
use crate::{check_triangles, triangles_from_field, Porous};
use exchange::fields::{
    BODY_LOADS, CANOPY_POSITIONS, CANOPY_PRESSURE, CANOPY_TRIANGLES, CANOPY_VELOCITIES, LOAD_LEN,
};
use fluid_section::Scene;
use participant::{Advance, Declaration, Monitor, Participant};
use std::sync::Arc;

/// The law, and the canopy it acts on this window.
pub struct FreeStream {
    law: Porous,
    /// The canopy's triangles (sent once), its nodes' positions [m] and
    /// velocities [m/s] at the window's start, when a structure writes it.
    triangles: Option<Vec<[usize; 3]>>,
    x: Vec<f64>,
    v: Vec<f64>,
    /// The jump across each triangle [Pa].
    jumps: Vec<f64>,
}

impl Model for FreeStream {
    /// Whether the window had a canopy to push on.
    type Advanced = bool;
    type Started = ();
    type Saved = ();
    const FIELD: bool = false;

    fn on(scene: &Scene, _: Arc<dyn Comm>) -> Result<FreeStream, String> {
        let load = (scene.fluid.porous_load())
            .ok_or("[fluid] lacks a key of the porous free-stream model")?;
        Ok(FreeStream {
            law: Porous::new(&load.params()),
            triangles: None,
            x: Vec::new(),
            v: Vec::new(),
            jumps: Vec::new(),
        })
    }

    fn start(&mut self) {}

    fn advance(&mut self, _: Window) -> Result<(bool, u64), String> {
        let Some(tris) = &self.triangles else {
            return Ok((false, 1));
        };
        self.jumps.resize(tris.len(), 0.0);
        self.law.pressure(tris, &self.x, &self.v, &mut self.jumps);
        Ok((true, 1))
    }

    // The jumps depend on the window's inputs alone: nothing to save or
    // to go back to (the canopy's triangles come again when a restarted
    // run resumes).
    fn save(&self, _: &mut ()) {}

    fn restore(&mut self, _: &()) -> Result<(), String> {
        Ok(())
    }

    fn cells(&mut self) -> Option<Cells> {
        None
    }
}

/// What rank 0 reads and answers: the canopy in, its jumps out, and no
/// load on the bodies.
pub struct Jumps {
    /// The scenario's rigid bodies, each with its (zero) load.
    bodies: usize,
}

impl Lead for Jumps {
    type Model = FreeStream;

    fn new(scene: &Scene, _: &mut FreeStream) -> Result<Jumps, String> {
        let bodies = scene.rigid.as_ref().map_or(0, |r| r.bodies.len());
        Ok(Jumps { bodies })
    }

    fn declaration(&self, _: &FreeStream) -> Declaration {
        // No flow goes round the bodies here: their states are not read.
        declaration(self.bodies, false, vec!["mean_pressure_jump".into()])
    }

    /// No pressure exists before the first window; NaN marks it in
    /// monitors.csv.
    fn start(
        &mut self,
        _: &mut Participant,
        _: &mut FreeStream,
        _: (),
    ) -> Result<Vec<Monitor>, Error> {
        Ok(vec![Monitor::new("mean_pressure_jump", f64::NAN)])
    }

    /// The canopy the structure left at the window's start.
    fn place(&mut self, p: &mut Participant, m: &mut FreeStream, _: &Advance) -> Result<(), Error> {
        if !p.is_connected(CANOPY_POSITIONS) {
            return Ok(());
        }
        if m.triangles.is_none() {
            // Connectivity arrives once, at initialisation.
            m.triangles = Some(triangles_from_field(&p.read_field(CANOPY_TRIANGLES)?));
        }
        let x = p.read_field(CANOPY_POSITIONS)?;
        check_triangles(m.triangles.as_deref().unwrap_or(&[]), x.len() / 3)?;
        m.x.clear();
        m.x.extend_from_slice(&x);
        let v = p.read_field(CANOPY_VELOCITIES)?;
        m.v.clear();
        m.v.extend_from_slice(&v);
        Ok(())
    }

    fn answer(
        &mut self,
        p: &mut Participant,
        m: &mut FreeStream,
        canopy: bool,
        _: &Advance,
    ) -> Result<Vec<Monitor>, Error> {
        if p.is_connected(BODY_LOADS) {
            // The porous free-stream model has no flow around bodies, so
            // it exerts no force on them: a body here is what the
            // dissertation (§2.4) calls a mass-point parachutist, outside
            // the flow. The pressure integral of eq. (2.40) comes with a
            // flow field.
            p.write_field(BODY_LOADS, LOAD_LEN * self.bodies, |out| out.fill(0.0))?;
        }
        if !canopy {
            return Ok(Vec::new());
        }
        let jumps = &m.jumps;
        p.write_field(CANOPY_PRESSURE, jumps.len(), |out| {
            out.copy_from_slice(jumps)
        })?;
        let mean = jumps.iter().sum::<f64>() / jumps.len().max(1) as f64;
        Ok(vec![Monitor::new("mean_pressure_jump", mean)])
    }
}
