//! A payload that holds the parachute until a release time
//! (`[structure.parachute] release_time`, issue 23's start conditions): the
//! confluence moves on at the release velocity whatever the lines pull,
//! as a held node does (no inverse mass, so every integrator drifts it at
//! its velocity), and from the release time on it is a free mass point of
//! the payload's mass.

use crate::model::Model;
use crate::network::NodeKind;

/// The held payload node, its mass, and when it lets go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hold {
    pub node: usize,
    /// The payload's mass [kg], which it takes on at release.
    pub mass: f64,
    /// The release time [s].
    pub until: f64,
    pub released: bool,
}

impl Model {
    /// Holds `node` (a payload of `mass` [kg]) until time `until` [s].
    pub fn hold_until(&mut self, node: usize, mass: f64, until: f64) {
        self.hold = Some(Hold {
            node,
            mass,
            until,
            released: false,
        });
        self.set_held(true);
    }

    /// Lets the payload go once `time` [s] reaches its release time; a
    /// message when it does.
    pub fn release(&mut self, time: f64) -> Option<String> {
        let h = self.hold?;
        // Within round-off of the sub-steps' summed time.
        if h.released || time < h.until - 1e-9 * h.until.abs().max(1e-3) {
            return None;
        }
        self.set_held(false);
        Some(format!("the payload was released at t = {time:.6} s"))
    }

    /// Whether the payload is still held (none: false).
    pub fn held(&self) -> bool {
        self.hold.is_some_and(|h| !h.released)
    }

    /// Holds the payload node or lets it go, and rebuilds what the
    /// integrators read.
    pub fn set_held(&mut self, held: bool) {
        let Some(h) = &mut self.hold else { return };
        h.released = !held;
        let (node, mass) = (h.node, h.mass);
        self.net.kind[node] = if held {
            NodeKind::Fixed
        } else {
            NodeKind::Free
        };
        self.net.mass[node] = if held { 0.0 } else { mass };
        self.net.prepare();
    }
}
