//! Where the attachment points start a try at an implicit window.
//!
//! Reads come in order, so a try after the first reads, as its first
//! `attachment.state`, where the bodies ended the last try, not where they
//! started the window. When the structure and the bodies iterate each
//! window (`CouplingSection::bodies_iterate`: one impulse exchange per
//! window) that is what the try needs: the attachment points move along
//! the chord from their window-start positions to there, and the
//! structure's impulse is its force integrated along that path. With more
//! exchanges per window the try starts where the window started, as its
//! first try did, and the later exchanges come in turn as in an explicit
//! window.

use crate::Model;
use participant::Advance;

pub struct WindowStart {
    /// Whether a try moves the attachment points along the chord.
    chord: bool,
    /// The attachment state the window's first try read first.
    state: Vec<f64>,
    /// Whether the next read is a try's first (set at each checkpoint
    /// command; never in an explicit run).
    pub first: bool,
}

impl WindowStart {
    pub fn new(chord: bool) -> WindowStart {
        WindowStart {
            chord,
            state: Vec::new(),
            first: false,
        }
    }

    /// Place the attachment points of `m` for the step `step` that read
    /// `state` (position then velocity, 6 per point).
    pub fn place(&mut self, m: &mut Model, state: &[f64], step: &Advance) {
        let first = std::mem::take(&mut self.first);
        if !first {
            return m.set_attachments(state);
        }
        if step.iteration == 0 {
            self.state.clear();
            self.state.extend_from_slice(state);
            return m.set_attachments(state);
        }
        match self.chord {
            true => m.set_attachments_along(&self.state, state, step.dt),
            false => m.set_attachments(&self.state),
        }
    }
}
