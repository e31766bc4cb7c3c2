//! A window that implicit coupling may take again (fluid-proc's
//! checkpoint.rs and prediction.rs, on the device):
//!
//! - its start is copied on the device ([`Flow::snapshot`]) and copied
//!   back for a later try ([`Flow::restore_snapshot`]), so no state crosses
//!   to the host and back between tries;
//! - the first try's prediction, Nⁿ and δ (the advection and the three
//!   viscous solves), is kept on the device, and a later try that starts
//!   from the restored start with the same step takes it instead of
//!   computing it again: the same bits, as it reads the same arrays;
//! - a later try's pressure solve starts from the last try's correction φ,
//!   which differs from try to try only as the interface's forcing does.

use crate::flow::{Flow, Moving};
use gpu_device::GpuError;

/// A window's first prediction, kept on the device: what it was computed
/// from (the step, the last step, the sides), and the arrays (Nⁿ and δ of
/// each component, then the last try's φ) in `buffer`.
pub(crate) struct Kept {
    dt: f64,
    last_dt: Option<f64>,
    sides: [[[f64; 3]; 2]; 3],
    buffer: wgpu::Buffer,
    /// The viscous solves' iterations it took.
    pub(crate) viscous_iterations: usize,
}

impl Flow {
    /// The arrays a step starts from, as (first, len): u, Nⁿ and δ of each
    /// component, q and φ.
    fn state_arrays(&self) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for (c, a) in self.active() {
            let len = self.spec.padded_len(c);
            out.extend([(a.u, len), (a.n[1 - self.parity], len), (a.delta, len)]);
        }
        out.extend([
            (self.mem.q, self.spec.cells()),
            (self.mem.phi, self.spec.cells()),
        ]);
        out
    }

    /// The arrays of a prediction, as (first, len): the Nⁿ a step writes and
    /// δ of each component, then φ.
    fn prediction_arrays(&self) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for (c, a) in self.active() {
            let len = self.spec.padded_len(c);
            out.extend([(a.n[self.parity], len), (a.delta, len)]);
        }
        out.push((self.mem.phi, self.spec.cells()));
        out
    }

    /// A buffer of at least the bytes of `arrays` (`old` where it is
    /// large enough).
    fn holding(&self, old: Option<wgpu::Buffer>, arrays: &[(usize, usize)]) -> wgpu::Buffer {
        let size = self.precision.size() as u64;
        let bytes: u64 = arrays.iter().map(|a| a.1 as u64 * size).sum();
        match old {
            Some(b) if b.size() >= bytes => b,
            _ => self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("window"),
                size: bytes,
                usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        }
    }

    /// Copies `arrays` one after the other into `buffer` from its byte
    /// `offset` on (`into`), or back from it.
    fn copy(&self, arrays: &[(usize, usize)], buffer: &wgpu::Buffer, offset: u64, into: bool) {
        let size = self.precision.size() as u64;
        let mut encoder = self.device.create_command_encoder(&Default::default());
        let mut at = offset;
        for &(first, len) in arrays {
            for (k, local, n) in self.segments.pieces(first, len) {
                let (f, bytes) = (&self.buffers.f[k], n as u64 * size);
                match into {
                    true => {
                        encoder.copy_buffer_to_buffer(f, local as u64 * size, buffer, at, bytes)
                    }
                    false => {
                        encoder.copy_buffer_to_buffer(buffer, at, f, local as u64 * size, bytes)
                    }
                }
                at += bytes;
            }
        }
        self.queue.submit([encoder.finish()]);
    }

    /// Copies the state a step starts from into a buffer on the device, for
    /// [`Flow::restore_snapshot`]: a window that implicit coupling may take
    /// again goes back to its start without the state crossing to the host.
    /// A new window: the last one's prediction goes.
    pub fn snapshot(&mut self) -> Result<(), GpuError> {
        let arrays = self.state_arrays();
        let old = self.snapshot.take().map(|s| s.0);
        let buffer = self.holding(old, &arrays);
        self.copy(&arrays, &buffer, 0, true);
        self.snapshot = Some((buffer, self.last_dt));
        self.kept_valid = false;
        Ok(())
    }

    /// Whether a [`Flow::snapshot`] was taken.
    pub fn has_snapshot(&self) -> bool {
        self.snapshot.is_some()
    }

    /// Returns to the state of the last [`Flow::snapshot`]; false where
    /// none was taken.
    pub fn restore_snapshot(&mut self) -> Result<bool, GpuError> {
        let Some((buffer, last_dt)) = &self.snapshot else {
            return Ok(false);
        };
        self.copy(&self.state_arrays(), buffer, 0, false);
        self.last_dt = *last_dt;
        self.restored = true;
        self.measure()?;
        Ok(true)
    }

    /// Whether the first step of a window's try takes the kept prediction:
    /// it starts from the restored start, with the step and sides the
    /// prediction was computed with.
    pub(crate) fn takes_kept(&self, dt: f64, moving: &Moving) -> bool {
        let Some(k) = self
            .kept
            .as_ref()
            .filter(|_| self.kept_valid && self.restored)
        else {
            return false;
        };
        k.dt.to_bits() == dt.to_bits()
            && k.last_dt.map(f64::to_bits) == self.last_dt.map(f64::to_bits)
            && k.sides == moving.sides
    }

    /// The kept Nⁿ, δ and last correction φ into the step's arrays.
    pub(crate) fn load_kept(&self) {
        if let Some(k) = &self.kept {
            self.copy(&self.prediction_arrays(), &k.buffer, 0, false);
        }
    }

    /// Keeps this first try's Nⁿ and δ, after its viscous solves.
    pub(crate) fn keep_prediction(&mut self, dt: f64, moving: &Moving, viscous_iterations: usize) {
        let arrays = self.prediction_arrays();
        let old = self.kept.take().map(|k| k.buffer);
        let buffer = self.holding(old, &arrays);
        // φ, the last of them, follows once the projection is done.
        self.copy(&arrays[..arrays.len() - 1], &buffer, 0, true);
        self.kept = Some(Kept {
            dt,
            last_dt: self.last_dt,
            sides: moving.sides,
            buffer,
            viscous_iterations,
        });
        self.kept_valid = true;
    }

    /// Keeps the try's correction φ, the next try's first guess.
    pub(crate) fn keep_correction(&self) {
        let Some(k) = &self.kept else { return };
        let arrays = self.prediction_arrays();
        let size = self.precision.size() as u64;
        let before: u64 = arrays[..arrays.len() - 1]
            .iter()
            .map(|a| a.1 as u64 * size)
            .sum();
        self.copy(&arrays[arrays.len() - 1..], &k.buffer, before, true);
    }
}
