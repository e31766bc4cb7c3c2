//! A window's checkpoint: what the structure saves at the start of a
//! coupling window so that the window can be taken again, bit for bit, from
//! the same inputs. Implicit coupling repeats every window until the
//! interface converges (preCICE's implicit schemes; Degroote et al. 2009),
//! so a repeated window must start from exactly the state the first try did.
//!
//! That state is the model's positions and velocities, the attachment
//! points with their impulses, whether the payload still holds the
//! parachute (`release.rs`), the suspension lines' breaks (a break undone
//! gives its segment back its stiffness and damping), and the stepper's
//! history: what its next step reads beyond (x, v), such as Newmark's
//! carried acceleration a_n (thesis §2.4) or the adaptive step size of
//! Dormand–Prince. The network's topology and parameters do not change in
//! a window but through a line's break, so they are not copied.

use crate::model::{Attachment, Model};

/// One suspension line's break state: whether it is broken, and the
/// stiffness and damping its top segment had (what a break zeroes).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
struct LineState {
    broken: bool,
    k: f64,
    c: Option<f64>,
}

/// The structure's state at a window's start. Saving into the same
/// checkpoint every window reuses its buffers.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Checkpoint {
    x: Vec<f64>,
    v: Vec<f64>,
    attachments: Vec<Attachment>,
    lines: Vec<LineState>,
    /// Whether the payload still holds the parachute (`release.rs`).
    held: bool,
    /// The stepper's history, as it saved it.
    pub history: Vec<f64>,
}

impl Model {
    /// Save the model's part of a checkpoint and empty its history, which
    /// the stepper then fills (`stepper.save_history(&mut into.history)`).
    pub fn save(&self, into: &mut Checkpoint) {
        into.history.clear();
        into.x.clone_from(&self.x);
        into.v.clone_from(&self.v);
        into.attachments.clone_from(&self.attachments);
        into.held = self.held();
        into.lines.clear();
        into.lines.extend(self.lines.iter().map(|l| {
            let top = l.springs[0];
            LineState {
                broken: l.broken,
                k: self.net.springs[top].k,
                c: self.net.dampers.get(top).map(|d| d.c),
            }
        }));
    }

    /// Return to the state `from` holds: positions, velocities,
    /// attachments, and the lines as they were (a line broken since is
    /// whole again, and the network's derived data is rebuilt).
    pub fn restore(&mut self, from: &Checkpoint) {
        self.x.clone_from(&from.x);
        self.v.clone_from(&from.v);
        self.attachments.clone_from(&from.attachments);
        if self.held() != from.held {
            self.set_held(from.held);
        }
        let mut changed = false;
        for (line, saved) in self.lines.iter_mut().zip(&from.lines) {
            if line.broken == saved.broken {
                continue;
            }
            changed = true;
            line.broken = saved.broken;
            let top = line.springs[0];
            self.net.springs[top].k = saved.k;
            if let (Some(d), Some(c)) = (self.net.dampers.get_mut(top), saved.c) {
                d.c = c;
            }
        }
        if changed {
            self.net.prepare();
        }
    }
}
