//! A window's checkpoint of the rigid bodies: what rigid-proc saves at the
//! start of a coupling window so that implicit coupling can take the
//! window again, bit for bit, from the same inputs. That is every body's
//! state (centre, velocity, Euler parameters, angular velocity) and the
//! count of contact impulses and the time (which says whether a body is
//! still held until its release); no contact persists from step to step (each
//! step detects its own, `contact.rs`), and shapes and masses do not change.

//!
//! A run checkpoint (`[run] checkpoint_interval`) writes the same state to
//! disk, each body's as its 13 values bit for bit.

use crate::motion::{pack, unpack};
use crate::Bodies;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Each body's centre, velocity, Euler parameters and principal-axes
    /// angular velocity.
    states: Vec<[f64; 13]>,
    contact_impulses: u64,
    /// The bodies' time, which says which are still held.
    time: f64,
}

impl Bodies {
    /// Save the bodies' state into `into`, reusing its buffer.
    pub fn save(&self, into: &mut Checkpoint) {
        into.states.clear();
        into.states
            .extend(self.bodies.iter().map(|b| pack(&b.state)));
        into.contact_impulses = self.contact_impulses;
        into.time = self.time;
    }

    /// Return to the state `from` holds.
    pub fn restore(&mut self, from: &Checkpoint) {
        for (body, state) in self.bodies.iter_mut().zip(&from.states) {
            body.state = unpack(state);
        }
        self.contact_impulses = from.contact_impulses;
        self.time = from.time;
        self.hold();
    }
}
