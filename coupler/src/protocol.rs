//! What crosses between the coupler and the participants.
//!
//! Control messages ([`Command`], [`Status`]) are serde types encoded with
//! bincode 2. Bulk data travels as [`Field`]s: flat `[f64]` slices in shared
//! memory, written and read in place.

use crate::scenario::Scenario;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The three solver roles a scenario can list. The program that plays a role is
/// swappable; the role fixes which fields it reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Role {
    Fluid,
    Structure,
    Rigid,
}

impl Role {
    pub const ALL: [Role; 3] = [Role::Fluid, Role::Structure, Role::Rigid];

    pub fn name(self) -> &'static str {
        match self {
            Role::Fluid => "fluid",
            Role::Structure => "structure",
            Role::Rigid => "rigid",
        }
    }

    pub fn from_name(s: &str) -> Option<Role> {
        Role::ALL.into_iter().find(|r| r.name() == s)
    }
}

/// Bulk fields. Layouts are flat and interleaved (`x0 y0 z0 x1 y1 z1 …`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Field {
    /// Canopy triangle vertex indices (3 per triangle, as exact f64), once at initialisation.
    CanopyTriangles,
    /// Canopy vertex positions [m], 3 per vertex, at the end of every window.
    CanopyPositions,
    /// Canopy vertex velocities [m/s], 3 per vertex, at the end of every window.
    CanopyVelocities,
    /// Signed pressure jump [Pa] per canopy triangle: the load on a triangle is
    /// `jump · area · n`, with `n` the unit normal of its vertex order (right-hand rule).
    CanopyPressure,
    /// Attachment points on rigid bodies: position [m] then velocity [m/s], 6 per point,
    /// at the start of every impulse sub-step.
    AttachmentState,
    /// Impulse [N·s] the structure exerts on each attachment point over one impulse
    /// sub-step, 3 per point.
    AttachmentImpulse,
    /// Rigid bodies at the end of every window, 13 per body: centre of mass [m],
    /// its velocity [m/s], Euler parameters e₀…e₃ (A(e) of seed 000 eq. 3.5
    /// takes world axes to body axes) and angular velocity in world axes [rad/s].
    BodyStates,
    /// Fluid load on each rigid body, the mean over one window, 6 per body:
    /// force [N] (the pressure of seed 000 eq. 2.40 and the friction) and
    /// torque about the centre of mass [N·m], world axes.
    BodyLoads,
    /// Rigid bodies at the start of every impulse sub-step, laid out as
    /// [`Field::BodyStates`]: the obstacles of the structure's collision pass.
    /// Exchanged only when the scenario has `[structure.collision]`.
    CollisionBodies,
    /// What the structure's collisions gave each rigid body over one impulse
    /// sub-step, 6 per body: the linear impulse [N·s] and the angular impulse
    /// about the centre of mass sent in [`Field::CollisionBodies`] [N·m·s],
    /// world axes. Exchanged only with `[structure.collision]`.
    CollisionImpulse,
}

impl Field {
    pub const ALL: [Field; 10] = [
        Field::CanopyTriangles,
        Field::CanopyPositions,
        Field::CanopyVelocities,
        Field::CanopyPressure,
        Field::AttachmentState,
        Field::AttachmentImpulse,
        Field::BodyStates,
        Field::BodyLoads,
        Field::CollisionBodies,
        Field::CollisionImpulse,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Field::CanopyTriangles => "canopy.triangles",
            Field::CanopyPositions => "canopy.positions",
            Field::CanopyVelocities => "canopy.velocities",
            Field::CanopyPressure => "canopy.pressure",
            Field::AttachmentState => "attachment.state",
            Field::AttachmentImpulse => "attachment.impulse",
            Field::BodyStates => "body.states",
            Field::BodyLoads => "body.loads",
            Field::CollisionBodies => "collision.bodies",
            Field::CollisionImpulse => "collision.impulse",
        }
    }

    /// (producer, consumer)
    pub fn route(self) -> (Role, Role) {
        match self {
            Field::CanopyTriangles | Field::CanopyPositions | Field::CanopyVelocities => {
                (Role::Structure, Role::Fluid)
            }
            Field::CanopyPressure => (Role::Fluid, Role::Structure),
            Field::AttachmentState => (Role::Rigid, Role::Structure),
            Field::AttachmentImpulse => (Role::Structure, Role::Rigid),
            Field::BodyStates => (Role::Rigid, Role::Fluid),
            Field::BodyLoads => (Role::Fluid, Role::Rigid),
            Field::CollisionBodies => (Role::Rigid, Role::Structure),
            Field::CollisionImpulse => (Role::Structure, Role::Rigid),
        }
    }

    /// A field is exchanged only when both its producer and consumer take
    /// part, and the collision fields only when the scene asks for collisions.
    pub fn is_connected(self, present: &[Role], scenario: &Scenario) -> bool {
        let (p, c) = self.route();
        let wanted = match self {
            Field::CollisionBodies | Field::CollisionImpulse => scenario
                .structure
                .as_ref()
                .is_some_and(|s| s.collision.is_some()),
            _ => true,
        };
        wanted && present.contains(&p) && present.contains(&c)
    }
}

/// Everything a participant needs to know, sent once after it connects.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Setup {
    pub run_id: String,
    /// Where the participant writes its `.vtu`/`.pvd` output.
    pub run_dir: PathBuf,
    /// The resolved scenario as TOML; parse it with [`crate::Scenario::from_resolved`].
    pub scenario_toml: String,
    /// Roles taking part in this run.
    pub present: Vec<Role>,
}

/// One step of the schedule for one participant.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Advance {
    /// Index of the coupling (FSI) window, from 0.
    pub window: u64,
    /// Simulated time at the start of this step [s].
    pub time: f64,
    /// Length of this step [s].
    pub dt: f64,
    /// How many internal sub-steps of `dt / substeps` to take.
    pub substeps: u32,
    /// True on the last step of a window: report monitors and publish window-end fields.
    pub window_end: bool,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Command {
    Setup(Setup),
    /// Publish the initial values of your output fields.
    Initialize,
    Advance(Advance),
    /// Write output number `index` (simulated time `time`) into the run directory.
    Output {
        index: u64,
        time: f64,
    },
    /// Finish: reply with [`Status::Finished`] and exit 0.
    Stop,
}

/// A named scalar the coupler writes to `monitors.csv`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Monitor {
    pub name: String,
    pub value: f64,
}

impl Monitor {
    pub fn new(name: impl Into<String>, value: f64) -> Self {
        Monitor {
            name: name.into(),
            value,
        }
    }
}

/// Counters a participant reports when it finishes.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    pub cpu_s: f64,
    pub wall_s: f64,
    /// Seconds inside field reads and writes and status replies.
    pub exchange_s: f64,
    /// Seconds spent waiting for the next command.
    pub wait_s: f64,
    pub commands: u64,
    /// Internal sub-steps taken, as counted by the solver.
    pub substeps: u64,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub enum Status {
    /// Ports are open; send the setup.
    Connected,
    /// Field ports are open; the participant is ready for `Initialize`.
    Ready,
    /// The last command is done. Monitors are reported at window ends.
    Done {
        monitors: Vec<Monitor>,
    },
    /// The participant cannot go on (diverged, bad input); it exits non-zero after this.
    Failed {
        reason: String,
    },
    Finished(Stats),
}

/// bincode configuration used for every control message.
pub fn encode<T: Serialize>(msg: &T) -> Vec<u8> {
    bincode::serde::encode_to_vec(msg, bincode::config::standard())
        .expect("control messages always encode")
}

pub fn decode<T: for<'de> Deserialize<'de>>(
    bytes: &[u8],
) -> Result<T, bincode::error::DecodeError> {
    bincode::serde::decode_from_slice(bytes, bincode::config::standard()).map(|(v, _)| v)
}
