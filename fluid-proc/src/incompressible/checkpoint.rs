//! A window's checkpoint of the incompressible flow: what it saves at the
//! start of a coupling window so that the window can be taken again, bit
//! for bit, from the same inputs (implicit coupling repeats a window until
//! the interface converges; Degroote et al. 2009).
//!
//! That state is the face velocities uⁿ, the kinematic pressure q^{n−½}
//! the predictor's gradient uses (dissertation eq. 3.18), the time, the
//! box's place and motion when it follows the parachute (`frame.rs`), the
//! last step's length and advection term Nⁿ (second-order Adams–Bashforth
//! reads both), the solvers' first guesses (the pressure correction φ and
//! each component's viscous change δ: a solve that starts elsewhere stops
//! elsewhere within its tolerance), and the bodies and canopy in the flow
//! with the forcing they have recorded since their loads were taken. The
//! rest of the flow is work space every step overwrites before it reads.
//!
//! A run checkpoint (`[run] checkpoint_interval`) writes the same state to
//! disk, one file per rank (`run.rs`, through `incompressible/run.rs`).

use crate::incompressible::faces::Faces;
use crate::incompressible::frame::Frame;
use crate::incompressible::immersed::ImmersedBody;
use crate::incompressible::Incompressible;

/// The flow's state at a window's start, on this rank. Saving into the
/// same checkpoint every window reuses its buffers.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Checkpoint {
    u: Option<Faces>,
    q: Vec<f64>,
    time: f64,
    /// Solver warm starts and step history (`Incompressible::save_history`).
    history: History,
    bodies: Vec<ImmersedBody>,
    canopy: Option<ImmersedBody>,
    /// Where the box is and how it moves, when it follows the parachute.
    frame: Option<Frame>,
    /// The step history stayed on the device, in its copy of the window's
    /// start (`device.rs`): a window's checkpoint, never written to disk.
    #[serde(skip)]
    on_device: bool,
}

/// What a flow step reads beyond (u, q): φ, the last Δt, and per advected
/// component its Nⁿ and δ.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct History {
    pub(crate) phi: Vec<f64>,
    pub(crate) last_dt: Option<f64>,
    pub(crate) advection: Vec<Vec<f64>>,
    pub(crate) delta: Vec<Vec<f64>>,
}

impl Checkpoint {
    /// Whether its step history stayed on the device (`device.rs`).
    pub fn on_device(&self) -> bool {
        self.on_device
    }
}

impl Incompressible {
    /// Save this rank's flow into `into`.
    pub fn save(&self, into: &mut Checkpoint) {
        // A window's checkpoint whose start the device copied keeps the
        // host's velocities as they are (a restore reads the device's);
        // any other takes the device's where the host's are older.
        into.on_device = self.take_snapshot();
        let u = into.u.get_or_insert_with(|| self.u.clone());
        let read = match into.on_device {
            true => {
                u.clone_from(&self.u);
                Ok(())
            }
            false => self.velocities_into(u),
        };
        if let Err(e) = read {
            eprintln!("fluid-proc: {e}");
        }
        if let Err(e) = self.pressure_into(&mut into.q) {
            // A device lost while saving: the host's older pressure, and
            // the next step stops the run with the device's error.
            eprintln!("fluid-proc: {e}");
            into.q.clone_from(&self.q);
        }
        into.time = self.time;
        if !into.on_device {
            self.save_history(&mut into.history);
        }
        into.bodies.clone_from(&self.bodies);
        into.canopy.clone_from(&self.canopy);
        into.frame = self.frame;
    }

    /// Whether `from` holds this rank's part of the flow: a checkpoint
    /// written by a run on other cells or ranks does not.
    pub fn fits(&self, from: &Checkpoint) -> bool {
        from.u.as_ref().is_some_and(|u| u.n == self.u.n) && from.q.len() == self.q.len()
    }

    /// Return to the state `from` holds. A checkpoint never saved leaves
    /// the flow as it is.
    pub fn restore(&mut self, from: &Checkpoint) {
        let Some(u) = &from.u else { return };
        // The device's own copy of the window's start, where it took one;
        // else the state goes up before the next step.
        let on_device = from.on_device && self.restore_snapshot();
        self.u.clone_from(u);
        self.q.clone_from(&from.q);
        self.time = from.time;
        if !on_device {
            self.restore_history(&from.history);
        }
        self.bodies.clone_from(&from.bodies);
        self.canopy.clone_from(&from.canopy);
        self.frame = from.frame;
        if self.frame.is_some() {
            self.frame_sides();
        }
    }
}
