//! The scenario's rigid bodies as the incompressible flow sees them: their
//! shapes' markers placed at the poses rigid-proc sends every window, and
//! the fluid's load on each sent back (`immersed.rs` does the physics).

use crate::incompressible::clearance::keep_clear;
use crate::incompressible::immersed::{place_markers, ImmersedBody, RETRACTION};
use crate::incompressible::pressure_force::pressure_load;
use crate::incompressible::Incompressible;
use crate::surface::Surface;
use exchange::body::read_states;
use exchange::fields::LOAD_LEN;
use exchange::{Body, Shape};
use fluid_section::Scene;
use participant::Monitor;

pub struct FlowBodies {
    bodies: Vec<Body>,
    surfaces: Vec<Option<Surface>>,
    /// The box's low corner in the world at the start [m].
    lower: [f64; 3],
}

impl FlowBodies {
    /// The bodies of the scenario's `[rigid]` section (none without one),
    /// placed in `flow` at their initial poses. Mass points have no
    /// surface: the dissertation's mass-point parachutist, outside the flow.
    pub fn new(
        scenario: &Scene,
        flow: &mut Incompressible,
        lower: [f64; 3],
    ) -> Result<FlowBodies, String> {
        let bodies = scenario
            .rigid
            .as_ref()
            .map_or(Ok(Vec::new()), |r| r.bodies())?;
        let g = flow.grid();
        let thick = (0..3).filter(|&d| g.n[d] > 1).count();
        if thick < 2 && bodies.iter().any(|b| b.shape.is_some()) {
            return Err(
                "a body with a shape needs a flow box more than one cell thick \
                        along at least two axes (a 2-D or 3-D flow)"
                    .into(),
            );
        }
        let spacing = g.spacing_range().0;
        // A 2-D flow takes the section of the finer polygon.
        let three_d = g.n.iter().all(|&n| n > 1);
        let surface = |s: &Shape| match three_d {
            true => Surface::for_markers(s, spacing),
            false => Surface::of(s, spacing),
        };
        let surfaces = bodies
            .iter()
            .map(|b| b.shape.as_ref().map(surface))
            .collect();
        flow.bodies = vec![ImmersedBody::default(); bodies.len()];
        let mut all = FlowBodies {
            bodies,
            surfaces,
            lower,
        };
        all.place(flow)?;
        Ok(all)
    }

    /// The velocity over the ground [m/s] of the body named `name`, as
    /// last read.
    pub fn velocity_of(&self, name: &str) -> Option<[f64; 3]> {
        let body = self.bodies.iter().find(|b| b.name == name)?;
        Some(body.state.v.into())
    }

    /// Takes the states rigid-proc sent (13 per body, [`read_states`]) and puts
    /// the bodies there.
    pub fn read(&mut self, states: &[f64], flow: &mut Incompressible) -> Result<(), String> {
        read_states(&mut self.bodies, states)?;
        self.place(flow)
    }

    fn place(&mut self, flow: &mut Incompressible) -> Result<(), String> {
        // Where the box is now: it moves when it follows the parachute.
        let o = flow.box_origin(self.lower);
        for ((body, surface), immersed) in
            self.bodies.iter().zip(&self.surfaces).zip(&mut flow.bodies)
        {
            let Some(surface) = surface else { continue };
            let g = &flow.setup.grid;
            let state = [body.state.x, body.state.v, body.world_angular_velocity()];
            if state.iter().any(|v| v.iter().any(|c| !c.is_finite())) {
                return Err(format!(
                    "body `{}` has a state that is not finite",
                    body.name
                ));
            }
            let (markers, volume) = place_markers(surface, &body.own_pose(), g, o);
            if markers.is_empty() {
                return Err(format!(
                    "body `{}` does not reach the mid-plane of the 2-D flow box, so the flow \
                     would not see it: place it across the box's thin axis",
                    body.name
                ));
            }
            keep_clear(g, &markers, o, &format!("body `{}`", body.name))?;
            let x = body.state.x;
            immersed.place(
                markers,
                [0, 1, 2].map(|d| x[d] - o[d]),
                body.state.v.into(),
                body.world_angular_velocity().into(),
                volume,
            );
        }
        Ok(())
    }

    /// The fluid's mean load on each body since the last call, 6 per body:
    /// force [N] then torque about the centre of mass [N·m].
    pub fn take_loads(&self, flow: &mut Incompressible, out: &mut [f64]) {
        let density = flow.setup.density;
        for (b, o) in flow.bodies.iter_mut().zip(out.chunks_exact_mut(6)) {
            let (f, t) = b.take_load(density);
            o[..3].copy_from_slice(&f);
            o[3..].copy_from_slice(&t);
        }
    }

    /// Monitors of each body with a shape: the force from the `loads`, and
    /// the pressure force of eq. (2.40) alone from the whole box's
    /// `pressure` [Pa] (both NaN before the first window).
    pub fn monitors(&self, flow: &Incompressible, read: Option<(&[f64], &[f64])>) -> Vec<Monitor> {
        let (loads, pressure) = (read.map(|r| r.0), read.map(|r| r.1));
        let g = flow.grid();
        let spacing = g.spacing_range().0;
        let mut out = Vec::new();
        let shaped = self.bodies.iter().zip(&self.surfaces).zip(&flow.bodies);
        for (i, ((b, s), immersed)) in shaped.enumerate() {
            if s.is_none() {
                continue;
            }
            let by_pressure = pressure.map(|p| {
                let surface = RETRACTION * spacing;
                pressure_load(g, p, &immersed.markers, immersed.centre, spacing, surface).0
            });
            for (d, axis) in ["x", "y", "z"].iter().enumerate() {
                let v = loads.map_or(f64::NAN, |l| l[LOAD_LEN * i + d]);
                out.push(Monitor::new(format!("{}_fluid_force_{axis}", b.name), v));
            }
            for (d, axis) in ["x", "y", "z"].iter().enumerate() {
                let v = by_pressure.map_or(f64::NAN, |f| f[d]);
                out.push(Monitor::new(format!("{}_pressure_force_{axis}", b.name), v));
            }
        }
        out
    }
}
