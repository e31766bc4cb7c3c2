//! What crosses back from the device (`device.rs`) and when: a window's end
//! brings the pressure back, which the canopy's jumps and the bodies'
//! loads read, and what the forcing gave the fluid; the monitors are summed
//! on the device; the velocities come back only where the host reads them
//! (the output, probes, a run checkpoint, a change of the state on the
//! host, a step called alone).

use crate::incompressible::device::gpu;
use crate::incompressible::faces::Faces;
use crate::incompressible::{FlowError, Incompressible};

/// The flow's monitors at a window's end: kinetic energy [J], momentum
/// [kg·m/s], the largest |∇·u| [1/s] and the largest change of a face
/// velocity since the window's start [m/s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowMonitors {
    pub kinetic_energy: f64,
    pub momentum: [f64; 3],
    pub max_divergence: f64,
    pub max_change: f64,
}

impl Incompressible {
    /// Brings the device's `u` and `q` to the host, where they are older.
    pub fn fetch(&mut self) -> Result<(), FlowError> {
        self.fetch_window_end()?;
        self.fetch_velocities()
    }

    /// A window's end: the pressure back to the host, where it is older,
    /// and what the forcing gave the fluid recorded on the bodies.
    pub fn fetch_window_end(&mut self) -> Result<(), FlowError> {
        self.fetch_pressure()?;
        let Some(d) = self.device.as_mut() else {
            return Ok(());
        };
        let given = d.flow.take_given().map_err(gpu)?;
        let grid = self.setup.grid.clone();
        let mut given = given.into_iter();
        for body in self.forced() {
            for k in 0..body.markers.len() {
                let push = given.next().unwrap_or_default();
                let x = body.markers[k].x;
                body.record(&grid, x, push);
            }
        }
        Ok(())
    }

    /// The pressure back to the host, where it is older.
    pub(crate) fn fetch_pressure(&mut self) -> Result<(), FlowError> {
        let Some(d) = self.device.as_mut().filter(|d| d.q_stale) else {
            return Ok(());
        };
        d.flow.download_pressure(&mut self.q).map_err(gpu)?;
        d.q_stale = false;
        Ok(())
    }

    /// The velocities back to the host, where they are older.
    pub fn fetch_velocities(&mut self) -> Result<(), FlowError> {
        let Some(d) = self.device.as_mut().filter(|d| d.u_stale) else {
            return Ok(());
        };
        d.flow.download_velocities(&mut self.u.u).map_err(gpu)?;
        d.u_stale = false;
        Ok(())
    }

    /// The face velocities into `out`, from the device where the host's
    /// are older (a run checkpoint's save, which cannot fetch).
    pub(crate) fn velocities_into(&self, out: &mut Faces) -> Result<(), FlowError> {
        match self.device.as_ref().filter(|d| d.u_stale) {
            Some(d) => {
                out.n = self.u.n;
                d.flow.download_velocities(&mut out.u).map_err(gpu)
            }
            None => {
                out.clone_from(&self.u);
                Ok(())
            }
        }
    }

    /// The current pressure into `out`: the device's where the host's is
    /// older.
    pub(crate) fn pressure_into(&self, out: &mut Vec<f64>) -> Result<(), FlowError> {
        match self.device.as_ref().filter(|d| d.q_stale) {
            Some(d) => {
                out.resize(self.q.len(), 0.0);
                d.flow.download_pressure(out).map_err(gpu)
            }
            None => {
                out.clone_from(&self.q);
                Ok(())
            }
        }
    }

    /// A window begins: its velocities kept for the steady residual, in
    /// `before` on the host, or on the device where the flow runs there
    /// (the state sent up first where the host holds it).
    pub fn remember_window_start(&mut self, before: &mut Faces) -> Result<(), FlowError> {
        self.send_state()?;
        match self.device.as_mut() {
            Some(d) => d.flow.remember().map_err(gpu),
            None => {
                before.clone_from(&self.u);
                Ok(())
            }
        }
    }

    /// The monitors at a window's end, `before` the velocities at its
    /// start ([`Incompressible::remember_window_start`]): summed on the
    /// device where it holds the state (`before` then unread); else on the
    /// host, over every rank, which all call it together.
    pub fn window_monitors(&mut self, before: &Faces) -> Result<WindowMonitors, FlowError> {
        let Some(d) = self.device.as_mut().filter(|d| d.current) else {
            let momentum = self.momentum();
            return Ok(WindowMonitors {
                kinetic_energy: self.kinetic_energy(),
                momentum,
                max_divergence: self.max_divergence(),
                max_change: self.max_change(before),
            });
        };
        let m = d.flow.monitors().map_err(gpu)?;
        // A uniform box: each cell's volume Π h, as `cell_sums` takes it.
        let volume: f64 = self.setup.grid.h.iter().product();
        let rho = self.setup.density;
        Ok(WindowMonitors {
            kinetic_energy: 0.5 * rho * m.sum_squares * volume,
            momentum: m.sum.map(|s| rho * s * volume),
            max_divergence: m.max_divergence,
            max_change: m.max_change,
        })
    }
}
