//! The state crossing between host and device: uploaded, downloaded,
//! the step history read back; and the arrays split into bindings.

use crate::flow::Flow;
use crate::memory::{slots, Memory};
use gpu_device::{read_back, GpuError};

/// What a step reads beyond (u, q): φ, the last Δt, and per active
/// component its newest Nⁿ and its δ, in the padded layout (fluid-proc's
/// `checkpoint::History`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct History {
    pub phi: Vec<f64>,
    pub last_dt: Option<f64>,
    pub advection: Vec<Vec<f64>>,
    pub delta: Vec<Vec<f64>>,
}

/// The arrays split into bindings of at most an adapter's binding size:
/// entry i lies in binding k where `ends[k − 1] ≤ i < ends[k]`
/// (flow.wgsl's SEG1, SEG2, SEG3).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Segments {
    pub(crate) ends: [usize; SEGMENTS],
}

/// Bindings the arrays may take (flow.wgsl's f0 … f3).
pub(crate) const SEGMENTS: usize = 4;

impl Segments {
    /// `len` reals in bindings of at most `most` reals each.
    pub(crate) fn of(len: usize, most: usize) -> Option<Segments> {
        let ends = std::array::from_fn(|k| (most * (k + 1)).min(len));
        (ends[SEGMENTS - 1] == len).then_some(Segments { ends })
    }

    pub(crate) fn start(&self, k: usize) -> usize {
        if k == 0 {
            0
        } else {
            self.ends[k - 1]
        }
    }

    pub(crate) fn len(&self, k: usize) -> usize {
        self.ends[k] - self.start(k)
    }

    /// The pieces (binding, first within it, length) of entries [first, first + len).
    pub(crate) fn pieces(&self, first: usize, len: usize) -> Vec<(usize, usize, usize)> {
        let end = first + len;
        (0..SEGMENTS)
            .filter_map(|k| {
                let (lo, hi) = (first.max(self.start(k)), end.min(self.ends[k]));
                (lo < hi).then(|| (k, lo - self.start(k), hi - lo))
            })
            .collect()
    }
}

impl Flow {
    pub(crate) fn write_array(&self, first: usize, values: &[f64]) {
        let size = self.precision.size();
        let mut from = 0;
        for (k, at, len) in self.segments.pieces(first, values.len()) {
            let bytes = self.precision.bytes(&values[from..from + len]);
            self.queue
                .write_buffer(&self.buffers.f[k], (at * size) as u64, &bytes);
            from += len;
        }
    }

    /// Sets the state: the face velocities `u[d]` as fluid-proc's `Faces`
    /// (n + 1 faces along d, x fastest) and the kinematic pressure `q` per
    /// cell [m²/s²]; the history too where given (a restart), else the
    /// next step starts as a first one.
    pub fn upload(
        &mut self,
        u: &[Vec<f64>; 3],
        q: &[f64],
        history: Option<&History>,
    ) -> Result<(), GpuError> {
        assert_eq!(q.len(), self.spec.cells(), "a pressure per cell");
        for (c, a) in self.active() {
            self.write_array(a.u, &self.padded(c, &u[c]));
        }
        self.write_array(self.mem.q, q);
        let cells = self.spec.cells();
        let (phi, last_dt) = match history {
            Some(h) => (h.phi.clone(), h.last_dt),
            None => (vec![0.0; cells], None),
        };
        self.write_array(self.mem.phi, &phi);
        self.last_dt = last_dt;
        // A state set here is no window's restored start: its next step
        // takes no kept prediction.
        (self.restored, self.kept_valid) = (false, false);
        for (k, (_, a)) in self.active().into_iter().enumerate() {
            let len = self.spec.padded_len(a_comp(&self.mem, a.u));
            let zero = vec![0.0; len];
            let pick = |v: Option<&Vec<Vec<f64>>>| {
                v.and_then(|v| v.get(k)).cloned().unwrap_or(zero.clone())
            };
            self.write_array(a.n[1 - self.parity], &pick(history.map(|h| &h.advection)));
            self.write_array(a.delta, &pick(history.map(|h| &h.delta)));
        }
        self.measure()
    }

    /// Component c's faces, padded with zero ghosts.
    fn padded(&self, c: usize, faces: &[f64]) -> Vec<f64> {
        let b = &self.spec;
        let (g, st) = (b.ghosts(), b.strides(c));
        let m = [0, 1, 2].map(|a| b.n[a] + (a == c) as usize);
        assert_eq!(
            faces.len(),
            m.iter().product::<usize>(),
            "faces of component {c}"
        );
        let mut out = vec![0.0; b.padded_len(c)];
        for k in 0..m[2] {
            for j in 0..m[1] {
                let from = m[0] * (j + m[1] * k);
                let to = g[0] + st[1] * (j + g[1]) + st[2] * (k + g[2]);
                out[to..to + m[0]].copy_from_slice(&faces[from..from + m[0]]);
            }
        }
        out
    }

    /// The face velocities and the pressure, as [`Flow::upload`] takes them.
    pub fn download(&self, u: &mut [Vec<f64>; 3], q: &mut [f64]) -> Result<(), GpuError> {
        let active = self.active();
        let mut ranges: Vec<(usize, usize)> = active
            .iter()
            .map(|&(c, a)| (a.u, self.spec.padded_len(c)))
            .collect();
        ranges.push((self.mem.q, self.spec.cells()));
        let read = self.read_arrays(&ranges)?;
        for (&(c, _), padded) in active.iter().zip(&read) {
            self.unpadded(c, padded, &mut u[c]);
        }
        q.copy_from_slice(&read[active.len()]);
        Ok(())
    }

    /// The face velocities alone, as [`Flow::upload`] takes them.
    pub fn download_velocities(&self, u: &mut [Vec<f64>; 3]) -> Result<(), GpuError> {
        let active = self.active();
        let ranges: Vec<(usize, usize)> = active
            .iter()
            .map(|&(c, a)| (a.u, self.spec.padded_len(c)))
            .collect();
        let read = self.read_arrays(&ranges)?;
        for (&(c, _), padded) in active.iter().zip(&read) {
            self.unpadded(c, padded, &mut u[c]);
        }
        Ok(())
    }

    /// The kinematic pressure alone [m²/s²].
    pub fn download_pressure(&self, q: &mut [f64]) -> Result<(), GpuError> {
        let read = self.read_arrays(&[(self.mem.q, self.spec.cells())])?;
        q.copy_from_slice(&read[0]);
        Ok(())
    }

    /// Component c's faces from its `padded` array, ghosts left out.
    fn unpadded(&self, c: usize, padded: &[f64], faces: &mut Vec<f64>) {
        let b = &self.spec;
        let (g, st) = (b.ghosts(), b.strides(c));
        let m = [0, 1, 2].map(|t| b.n[t] + (t == c) as usize);
        faces.resize(m.iter().product(), 0.0);
        for k in 0..m[2] {
            for j in 0..m[1] {
                let to = m[0] * (j + m[1] * k);
                let from = g[0] + st[1] * (j + g[1]) + st[2] * (k + g[2]);
                faces[to..to + m[0]].copy_from_slice(&padded[from..from + m[0]]);
            }
        }
    }

    /// The step history, as [`Flow::upload`] takes it.
    pub fn history(&self) -> Result<History, GpuError> {
        let active = self.active();
        let mut ranges = vec![(self.mem.phi, self.spec.cells())];
        for &(c, a) in &active {
            ranges.push((a.n[1 - self.parity], self.spec.padded_len(c)));
            ranges.push((a.delta, self.spec.padded_len(c)));
        }
        let mut read = self.read_arrays(&ranges)?.into_iter();
        let phi = read.next().unwrap_or_default();
        let (mut advection, mut delta) = (Vec::new(), Vec::new());
        while let (Some(n), Some(d)) = (read.next(), read.next()) {
            advection.push(n);
            delta.push(d);
        }
        Ok(History {
            phi,
            last_dt: self.last_dt,
            advection,
            delta,
        })
    }

    /// The arrays (first, len) of `f`, read at once.
    pub(crate) fn read_arrays(&self, ranges: &[(usize, usize)]) -> Result<Vec<Vec<f64>>, GpuError> {
        let size = self.precision.size() as u64;
        let f = &self.buffers.f;
        let bytes: Vec<(&wgpu::Buffer, u64, u64)> = ranges
            .iter()
            .flat_map(|&(first, len)| self.segments.pieces(first, len))
            .map(|(k, at, len)| (&f[k], at as u64 * size, len as u64 * size))
            .collect();
        let bytes = read_back(&self.device, &self.queue, &bytes, &self.buffers.readback)?;
        let mut out = Vec::with_capacity(ranges.len());
        let mut from = 0;
        for &(_, len) in ranges {
            let mut v = vec![0.0; len];
            let b = len * size as usize;
            self.precision.read(&bytes[from..from + b], &mut v);
            from += b;
            out.push(v);
        }
        Ok(out)
    }

    pub(crate) fn read_scalars(&self) -> Result<Vec<f64>, GpuError> {
        let len = slots(self.mem.levels.len());
        let size = self.precision.size();
        let range = [(&self.buffers.s, 0, (len * size) as u64)];
        let bytes = read_back(&self.device, &self.queue, &range, &self.buffers.readback)?;
        let mut out = vec![0.0; len];
        self.precision.read(&bytes, &mut out);
        Ok(out)
    }
}

/// The component whose velocity array starts at `u`.
fn a_comp(mem: &Memory, u: usize) -> usize {
    (0..3)
        .find(|&c| mem.comp[c].is_some_and(|a| a.u == u))
        .expect("an active component")
}
