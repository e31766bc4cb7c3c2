//! The flow on the device: its buffers and kernels, the state uploaded
//! once and kept there, a step run as the lists of `plan.rs` with the
//! solves iterated on the device until their flags say they are done.

use crate::markers::{Law, Marker, Sorted, MARKER};
use crate::memory::{block, slot, slots, Memory};
use crate::plan::{
    Kernel, Pass, Plan, Rec, FORCING_PASSES, FORCING_RECORDS, KERNELS, RECORD_BYTES,
    SPREAD_WORKGROUP, WORKGROUP,
};
use crate::spec::{FlowBox, Side};
use gpu_device::{buffer, check_size, non_empty, read_back, workgroups, Gpu, GpuError, Precision};

/// Relative residual of the pressure and the viscous solves (fluid-proc's
/// PRESSURE_TOLERANCE and VISCOUS_TOLERANCE).
pub const TOLERANCE: f64 = 1e-8;
/// The same in f32, whose rounding (6·10⁻⁸ relative) a residual of 10⁻⁸
/// cannot reach: the solves stop at 10⁻⁵.
pub const TOLERANCE_F32: f64 = 1e-5;
/// Most iterations of a viscous solve and of the pressure solve (fluid-proc's).
const MAX_VISCOUS: usize = 1000;
const MAX_PRESSURE: usize = 500;
/// Symmetric sweeps of the coarsest multigrid level (fluid-proc's).
const COARSEST_SWEEPS: usize = 40;

/// Why a step on the device failed.
#[derive(Debug, thiserror::Error)]
pub enum FlowError {
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error("the viscous (Crank–Nicolson) solve of velocity component {component} did not converge in {iterations} iterations (relative residual {reached:e})")]
    Viscous {
        component: usize,
        iterations: usize,
        reached: f64,
    },
    #[error("the pressure solve did not converge in {iterations} iterations (relative residual {reached:e})")]
    Pressure { iterations: usize, reached: f64 },
    #[error("the velocity is no longer finite")]
    NonFinite,
}

/// How the box moves over a step, when it follows the parachute
/// (fluid-proc's frame.rs): the sides' given velocities seen from it at the
/// step's start and at its end (`sides[d][high]`, zero where a side is
/// not of given velocity), its velocity over the ground at the end, and
/// its change of velocity over the step [m/s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moving {
    pub sides: [[[f64; 3]; 2]; 3],
    pub sides_end: [[[f64; 3]; 2]; 3],
    pub frame: [f64; 3],
    pub dv: [f64; 3],
}

/// The given velocities of `sides` (zero where a side gives none).
pub fn given(sides: &[[Side; 2]; 3]) -> [[[f64; 3]; 2]; 3] {
    sides.map(|pair| {
        pair.map(|s| match s {
            Side::Velocity(v) | Side::Parabolic(v) => v,
            _ => [0.0; 3],
        })
    })
}

/// What a step did.
#[derive(Debug, Clone, Copy, Default)]
pub struct Report {
    pub pressure_iterations: usize,
    pub viscous_iterations: usize,
}

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
struct Segments {
    ends: [usize; SEGMENTS],
}

/// Bindings the arrays may take (flow.wgsl's f0 … f3).
const SEGMENTS: usize = 4;

impl Segments {
    /// `len` reals in bindings of at most `most` reals each.
    fn of(len: usize, most: usize) -> Option<Segments> {
        let ends = std::array::from_fn(|k| (most * (k + 1)).min(len));
        (ends[SEGMENTS - 1] == len).then_some(Segments { ends })
    }

    fn start(&self, k: usize) -> usize {
        if k == 0 {
            0
        } else {
            self.ends[k - 1]
        }
    }

    fn len(&self, k: usize) -> usize {
        self.ends[k] - self.start(k)
    }

    /// The pieces (binding, first within it, length) of entries [first, first + len).
    fn pieces(&self, first: usize, len: usize) -> Vec<(usize, usize, usize)> {
        let end = first + len;
        (0..SEGMENTS)
            .filter_map(|k| {
                let (lo, hi) = (first.max(self.start(k)), end.min(self.ends[k]));
                (lo < hi).then(|| (k, lo - self.start(k), hi - lo))
            })
            .collect()
    }
}

struct Buffers {
    /// The arrays, in up to SEGMENTS bindings.
    f: Vec<wgpu::Buffer>,
    s: wgpu::Buffer,
    part: wgpu::Buffer,
    ops: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// The markers' records and their blocks (`markers.rs`), grown as needed.
    markers: wgpu::Buffer,
    blocks: wgpu::Buffer,
}

/// The incompressible flow on a box, its state on the device.
pub struct Flow {
    device: wgpu::Device,
    queue: wgpu::Queue,
    precision: Precision,
    spec: FlowBox,
    mem: Memory,
    plan: Plan,
    pipelines: Vec<wgpu::ComputePipeline>,
    buffers: Buffers,
    segments: Segments,
    layout: wgpu::BindGroupLayout,
    bind_group: wgpu::BindGroup,
    op_stride: u32,
    /// A copy of the state on the device (`snapshot`), and the step
    /// history's scalars with it.
    snapshot: Option<(wgpu::Buffer, Option<f64>)>,
    /// The markers as the device holds them, and the forcing's passes.
    sorted: Option<Sorted>,
    forcing: Vec<Pass>,
    /// The slot the next step's Nⁿ goes to.
    parity: usize,
    last_dt: Option<f64>,
    /// Σ_a|u_a|/h_a's largest over the cells, and their sum (not finite
    /// where a velocity is not), of the state as it is.
    courant: [f64; 2],
    /// Iterations a submit runs of the viscous and the pressure solves
    /// (their last counts: most steps then need one submit each).
    batch: [usize; 2],
}

impl Flow {
    /// The flow on `spec`'s box, at rest, on `gpu`.
    pub fn new(gpu: &Gpu, spec: &FlowBox) -> Result<Flow, GpuError> {
        Flow::binding_at_most(gpu, spec, u64::MAX)
    }

    /// [`Flow::new`], the arrays split as if the adapter bound at most
    /// `bytes` a binding (the tests split a small box so).
    pub fn binding_at_most(gpu: &Gpu, spec: &FlowBox, bytes: u64) -> Result<Flow, GpuError> {
        if let Some(why) = spec.refused() {
            return Err(GpuError::Kernel(format!("the box: {why}")));
        }
        let device = gpu.device();
        device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        device.push_error_scope(wgpu::ErrorFilter::Validation);
        let made = Flow::make(gpu, spec, bytes);
        for _ in 0..2 {
            if let Some(e) = pollster::block_on(device.pop_error_scope()) {
                return Err(GpuError::Kernel(e.to_string()));
            }
        }
        let mut flow = made?;
        flow.write_constants();
        flow.measure()?;
        Ok(flow)
    }

    fn make(gpu: &Gpu, spec: &FlowBox, most: u64) -> Result<Flow, GpuError> {
        let device = gpu.device().clone();
        let precision = gpu.precision();
        let mem = Memory::of(spec);
        let plan = Plan::of(spec, &mem);
        let size = precision.size() as u64;
        let limits = device.limits();
        let binds = (limits.max_storage_buffer_binding_size as u64)
            .min(limits.max_buffer_size)
            .min(most);
        let segments =
            Segments::of(mem.len, (binds / size) as usize).ok_or(GpuError::TooLarge {
                what: "the flow's arrays (in four bindings)",
                needed: mem.len as u64 * size,
                limit: SEGMENTS as u64 * binds,
            })?;
        let op_stride = (RECORD_BYTES as u32)
            .next_multiple_of(device.limits().min_uniform_buffer_offset_alignment);
        let storage = wgpu::BufferUsages::STORAGE;
        let copied = storage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let zeros = |n: usize| non_empty(precision.bytes(&vec![0.0; n]));
        let levels = mem.levels.len();
        // A download reads u, q, or the history: at most 3 padded arrays
        // a component and a cell field.
        let most = (0..3).map(|c| spec.padded_len(c)).sum::<usize>() * 2 + spec.cells();
        let readback_bytes = (most.max(slots(levels)) as u64) * size;
        let buffers = Buffers {
            f: (0..SEGMENTS)
                .map(|k| buffer(&device, "flow", &zeros(segments.len(k)), copied))
                .collect(),
            s: buffer(&device, "scalars", &zeros(slots(levels)), copied),
            part: buffer(&device, "partial sums", &zeros(plan.partials), storage),
            ops: buffer(
                &device,
                "ops",
                &records(&plan, op_stride),
                wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            ),
            markers: buffer(&device, "markers", &zeros(MARKER), copied),
            blocks: buffer(&device, "blocks", &[0; 8], copied),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: readback_bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        };
        let layout = bind_group_layout(&device);
        let pipelines = pipelines(&device, &layout, &source(precision, spec, &mem, &segments))?;
        let bind_group = bind_group(&device, &layout, &buffers);
        Ok(Flow {
            device,
            queue: gpu.queue().clone(),
            precision,
            spec: spec.clone(),
            mem,
            plan,
            pipelines,
            buffers,
            segments,
            layout,
            bind_group,
            op_stride,
            snapshot: None,
            sorted: None,
            forcing: Vec::new(),
            parity: 0,
            last_dt: None,
            courant: [0.0; 2],
            batch: [8, 8],
        })
    }

    /// The box.
    pub fn spec(&self) -> &FlowBox {
        &self.spec
    }

    /// The scalars that hold for the whole run.
    fn write_constants(&self) {
        let b = &self.spec;
        let mut s = vec![0.0; slot::LEVEL_H2 + 3 * self.mem.levels.len()];
        s[slot::NU] = b.nu;
        s[slot::ONE] = 1.0;
        s[slot::HUGE] = match self.precision {
            Precision::F64 => f64::MAX,
            Precision::F32 => f32::MAX as f64,
        };
        let tolerance = match self.precision {
            Precision::F64 => TOLERANCE,
            Precision::F32 => TOLERANCE_F32,
        };
        s[slot::TOL_V] = tolerance;
        s[slot::TOL_P] = tolerance;
        s[slot::CELLS] = b.cells() as f64;
        s[slot::RHO] = b.density;
        s[slot::SPACING] = b.spacing();
        s[slot::CELL] = b.h.iter().product();
        for d in 0..3 {
            s[slot::INV_H + d] = 1.0 / b.h[d];
            s[slot::INV_H2 + d] = 1.0 / (b.h[d] * b.h[d]);
        }
        for (l, (_, h)) in b.levels().iter().enumerate() {
            for d in 0..3 {
                s[slot::LEVEL_H2 + 3 * l + d] = 1.0 / (h[d] * h[d]);
            }
        }
        self.write_scalars(0, &s);
    }

    fn write_scalars(&self, first: usize, values: &[f64]) {
        let at = (first * self.precision.size()) as u64;
        let bytes = self.precision.bytes(values);
        self.queue.write_buffer(&self.buffers.s, at, &bytes);
    }

    fn write_array(&self, first: usize, values: &[f64]) {
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

    /// The arrays a step starts from, as (first, len): u, Nⁿ and δ of each
    /// component, q and φ.
    fn state_arrays(&self) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for (c, a) in self.active() {
            let len = self.spec.padded_len(c);
            out.extend([(a.u, len), (a.n[1 - self.parity], len), (a.delta, len)]);
        }
        out.extend([(self.mem.q, self.spec.cells()), (self.mem.phi, self.spec.cells())]);
        out
    }

    /// Copies the state a step starts from into a buffer on the device, for
    /// [`Flow::restore_snapshot`]: a window that implicit coupling may take
    /// again goes back to its start without the state crossing to the host.
    pub fn snapshot(&mut self) -> Result<(), GpuError> {
        let arrays = self.state_arrays();
        let size = self.precision.size() as u64;
        let bytes: u64 = arrays.iter().map(|a| a.1 as u64 * size).sum();
        let buffer = match self.snapshot.take() {
            Some((b, _)) if b.size() >= bytes => b,
            _ => self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("snapshot"),
                size: bytes,
                usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        };
        let mut encoder = self.device.create_command_encoder(&Default::default());
        let mut at = 0;
        for (first, len) in arrays {
            for (k, from, n) in self.segments.pieces(first, len) {
                let f = &self.buffers.f[k];
                encoder.copy_buffer_to_buffer(f, from as u64 * size, &buffer, at, n as u64 * size);
                at += n as u64 * size;
            }
        }
        self.queue.submit([encoder.finish()]);
        self.snapshot = Some((buffer, self.last_dt));
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
        let size = self.precision.size() as u64;
        let mut encoder = self.device.create_command_encoder(&Default::default());
        let mut at = 0;
        for (first, len) in self.state_arrays() {
            for (k, to, n) in self.segments.pieces(first, len) {
                let f = &self.buffers.f[k];
                encoder.copy_buffer_to_buffer(buffer, at, f, to as u64 * size, n as u64 * size);
                at += n as u64 * size;
            }
        }
        self.queue.submit([encoder.finish()]);
        self.last_dt = *last_dt;
        self.measure()?;
        Ok(true)
    }

    /// The arrays (first, len) of `f`, read at once.
    fn read_arrays(&self, ranges: &[(usize, usize)]) -> Result<Vec<Vec<f64>>, GpuError> {
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

    fn read_scalars(&self) -> Result<Vec<f64>, GpuError> {
        let len = slots(self.mem.levels.len());
        let size = self.precision.size();
        let range = [(&self.buffers.s, 0, (len * size) as u64)];
        let bytes = read_back(&self.device, &self.queue, &range, &self.buffers.readback)?;
        let mut out = vec![0.0; len];
        self.precision.read(&bytes, &mut out);
        Ok(out)
    }

    /// The Courant number Σ_a|u_a|Δt/h_a of a step of `dt` from the state
    /// as it is (NaN where a velocity is not finite).
    pub fn courant(&self, dt: f64) -> f64 {
        match self.courant[1].is_finite() {
            true => self.courant[0] * dt,
            false => f64::NAN,
        }
    }

    /// Measures the state's Courant number.
    fn measure(&mut self) -> Result<(), GpuError> {
        self.run(&[&self.plan.measure])?;
        let s = self.read_scalars()?;
        self.courant = [s[slot::COURANT], s[slot::FINITE]];
        Ok(())
    }

    /// Advances the flow by `dt` [s] (fluid-proc's `Incompressible::step`
    /// on the device): the predictor, the projection, the pressure update.
    pub fn step(&mut self, dt: f64) -> Result<Report, FlowError> {
        let sides = given(&self.spec.sides);
        self.step_moving(
            dt,
            &Moving {
                sides,
                sides_end: sides,
                frame: [0.0; 3],
                dv: [0.0; 3],
            },
        )
    }

    /// [`Flow::step`] in a box that moves (fluid-proc's frame.rs).
    pub fn step_moving(&mut self, dt: f64, moving: &Moving) -> Result<Report, FlowError> {
        let mut m = Vec::with_capacity(2 * 18 + 6);
        m.extend(moving.sides.iter().flatten().flatten());
        self.write_scalars(slot::SIDE_U, &m);
        m.clear();
        m.extend(moving.sides_end.iter().flatten().flatten());
        m.extend(moving.frame.iter().chain(&moving.dv));
        self.write_scalars(slot::SIDE_END, &m);
        let ab = match self.last_dt {
            Some(old) => [1.0 + 0.5 * dt / old, -0.5 * dt / old],
            None => [1.0, 0.0],
        };
        self.write_scalars(slot::DT, &[dt, ab[0], ab[1], 0.5 * self.spec.nu * dt]);
        let levels = self.mem.levels.len();
        self.write_scalars(block(levels, 0), &vec![0.0; 4 * slot::BLOCK]);
        let start = self.plan.start[self.parity].clone();
        let viscous = self.iterate(&start, 0)?;
        let plan = &self.plan;
        let first =
            [&plan.change, &self.forcing, &plan.impose, &plan.projection].map(|l| l.as_slice());
        let first: Vec<Pass> = first.concat();
        let pressure = self.iterate(&first, 1)?;
        self.run(&[&self.plan.end])?;
        let s = self.read_scalars()?;
        self.courant = [s[slot::COURANT], s[slot::FINITE]];
        if !self.courant[1].is_finite() {
            return Err(FlowError::NonFinite);
        }
        self.parity = 1 - self.parity;
        self.last_dt = Some(dt);
        Ok(Report {
            pressure_iterations: pressure,
            viscous_iterations: viscous,
        })
    }

    /// Runs `first`, then the solve's iterations (0: the viscous solves,
    /// 1: the pressure's) in submits of `batch` until every one is done;
    /// returns the iterations (summed over the viscous components).
    fn iterate(&mut self, first: &[Pass], which: usize) -> Result<usize, FlowError> {
        let levels = self.mem.levels.len();
        let solves: Vec<usize> = match which {
            0 => self.active().iter().map(|&(c, _)| c).collect(),
            _ => vec![3],
        };
        let iteration = match which {
            0 => self.plan.viscous_iteration.clone(),
            _ => self.plan.pressure_iteration.clone(),
        };
        let most = [MAX_VISCOUS, MAX_PRESSURE][which];
        let mut lists: Vec<&[Pass]> = vec![first];
        let mut taken = 0;
        loop {
            let batch = self.batch[which].clamp(1, most - taken);
            lists.extend(std::iter::repeat_n(iteration.as_slice(), batch));
            self.run(&lists)?;
            taken += batch;
            lists.clear();
            let s = self.read_scalars()?;
            let at = |k: usize, what: usize| s[block(levels, k) + what];
            if solves.iter().any(|&k| at(k, slot::FAIL) != 0.0) {
                return Err(FlowError::NonFinite);
            }
            let iterations: Vec<usize> =
                solves.iter().map(|&k| at(k, slot::ITER) as usize).collect();
            if solves.iter().all(|&k| at(k, slot::DONE) != 0.0) {
                let most_taken = iterations.iter().copied().max().unwrap_or(0);
                self.batch[which] = most_taken.max(1);
                return Ok(iterations.iter().sum());
            }
            if taken >= most {
                let k = *solves.iter().find(|&&k| at(k, slot::DONE) == 0.0).unwrap();
                let reached = at(k, slot::RR).sqrt() / at(k, slot::SCALE);
                return Err(match which {
                    0 => FlowError::Viscous {
                        component: k,
                        iterations: most,
                        reached,
                    },
                    _ => FlowError::Pressure {
                        iterations: most,
                        reached,
                    },
                });
            }
        }
    }

    /// Encodes `lists` in one compute pass and submits it.
    fn run(&self, lists: &[&[Pass]]) -> Result<(), GpuError> {
        self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut encoder = self.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            for p in lists.iter().flat_map(|l| l.iter()) {
                pass.set_pipeline(&self.pipelines[p.kernel as usize]);
                pass.set_bind_group(0, &self.bind_group, &[p.op * self.op_stride]);
                pass.dispatch_workgroups(p.groups.0, p.groups.1, 1);
            }
        }
        self.queue.submit([encoder.finish()]);
        match pollster::block_on(self.device.pop_error_scope()) {
            Some(e) => Err(GpuError::Kernel(e.to_string())),
            None => Ok(()),
        }
    }

    fn active(&self) -> Vec<(usize, crate::memory::Component)> {
        (0..3)
            .filter_map(|c| self.mem.comp[c].map(|a| (c, a)))
            .collect()
    }

    /// Puts the bodies' and the canopy's `markers` in the flow (none: the
    /// flow alone): each step from now on forces the air at them
    /// (fluid-proc's `immersed::force`), and what each gives the fluid is
    /// summed on the device until [`Flow::take_given`].
    pub fn set_markers(&mut self, markers: &[Marker]) -> Result<(), GpuError> {
        let sorted = Sorted::of(&self.spec, markers);
        let p = self.precision;
        let (record_bytes, table_bytes) = (sorted.records.len() * p.size(), sorted.table.len() * 4);
        check_size(&self.device, "the markers", record_bytes as u64)?;
        let storage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST;
        let mut grown = false;
        if (record_bytes as u64) > self.buffers.markers.size() {
            let bytes = non_empty(p.bytes(&vec![0.0; 2 * sorted.records.len()]));
            self.buffers.markers = buffer(&self.device, "markers", &bytes, storage);
            grown = true;
        }
        if (table_bytes as u64) > self.buffers.blocks.size() {
            let bytes = vec![0u8; 2 * table_bytes];
            self.buffers.blocks = buffer(&self.device, "blocks", &bytes, storage);
            grown = true;
        }
        if grown {
            self.bind_group = bind_group(&self.device, &self.layout, &self.buffers);
        }
        if (record_bytes as u64) > self.buffers.readback.size() {
            self.buffers.readback = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: record_bytes as u64,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
        }
        if !markers.is_empty() {
            self.queue
                .write_buffer(&self.buffers.markers, 0, &p.bytes(&sorted.records));
            self.queue
                .write_buffer(&self.buffers.blocks, 0, bytemuck::cast_slice(&sorted.table));
        }
        self.forcing = self.forcing_passes(&sorted, markers);
        self.sorted = Some(sorted);
        Ok(())
    }

    /// The forcing passes over `sorted`, their records written: the porous
    /// sheets' drag, then FORCING_PASSES − 1 passes over the others.
    fn forcing_passes(&self, sorted: &Sorted, markers: &[Marker]) -> Vec<Pass> {
        let porous = markers.iter().any(|m| matches!(m.law, Law::Porous(_)));
        let others = markers.iter().any(|m| !matches!(m.law, Law::Porous(_)));
        let count = markers.len();
        let mut list = Vec::new();
        let mut recs = Vec::new();
        for pass in 0..FORCING_PASSES {
            let aux = (pass > 0) as usize;
            if (aux == 0 && !porous) || (aux == 1 && !others) {
                continue;
            }
            let each = Rec {
                aux,
                count,
                ..Rec::default()
            };
            for kernel in [Kernel::Interpolate, Kernel::Pushes] {
                list.push((kernel, each, workgroups(count as u32, WORKGROUP)));
            }
            for &(start, blocks) in &sorted.colours {
                let rec = Rec {
                    o: [start, 0, 0, 0],
                    aux,
                    count: blocks,
                    ..Rec::default()
                };
                list.push((
                    Kernel::Spread,
                    rec,
                    workgroups(blocks as u32, SPREAD_WORKGROUP),
                ));
            }
        }
        debug_assert!(list.len() <= FORCING_RECORDS);
        let passes = list
            .into_iter()
            .enumerate()
            .map(|(i, (kernel, rec, groups))| {
                recs.push(rec.words());
                Pass {
                    kernel,
                    op: (self.plan.forcing + i) as u32,
                    groups,
                }
            })
            .collect();
        let mut bytes = vec![0u8; recs.len() * self.op_stride as usize];
        for (k, r) in recs.iter().enumerate() {
            let at = k * self.op_stride as usize;
            bytes[at..at + RECORD_BYTES].copy_from_slice(bytemuck::cast_slice(r));
        }
        if !bytes.is_empty() {
            let at = (self.plan.forcing * self.op_stride as usize) as u64;
            self.queue.write_buffer(&self.buffers.ops, at, &bytes);
        }
        passes
    }

    /// What each marker (in the order [`Flow::set_markers`] took them)
    /// has given the fluid since the markers were set or last taken: Σ
    /// F_k ΔV_k Δt, momentum per unit density [m⁴/s]; the sums start again.
    pub fn take_given(&mut self) -> Result<Vec<[f64; 3]>, GpuError> {
        let Some(sorted) = &self.sorted else {
            return Ok(Vec::new());
        };
        if sorted.order.is_empty() {
            return Ok(Vec::new());
        }
        let size = self.precision.size();
        let bytes = (sorted.records.len() * size) as u64;
        let range = [(&self.buffers.markers, 0, bytes)];
        let read = read_back(&self.device, &self.queue, &range, &self.buffers.readback)?;
        let mut records = vec![0.0; sorted.records.len()];
        self.precision.read(&read, &mut records);
        let given = sorted.given(&records);
        self.queue.write_buffer(
            &self.buffers.markers,
            0,
            &self.precision.bytes(&sorted.records),
        );
        Ok(given)
    }
}

/// The component whose velocity array starts at `u`.
fn a_comp(mem: &Memory, u: usize) -> usize {
    (0..3)
        .find(|&c| mem.comp[c].is_some_and(|a| a.u == u))
        .expect("an active component")
}

/// The records, one per `op_stride` bytes.
fn records(plan: &Plan, stride: u32) -> Vec<u8> {
    let mut bytes = vec![0u8; plan.records.len().max(1) * stride as usize];
    for (k, r) in plan.records.iter().enumerate() {
        let at = k * stride as usize;
        bytes[at..at + RECORD_BYTES].copy_from_slice(bytemuck::cast_slice(r));
    }
    bytes
}

/// The kernels' source: the box's constants, then flow.wgsl.
fn source(precision: Precision, b: &FlowBox, mem: &Memory, segments: &Segments) -> String {
    let vec3 = |v: [usize; 3]| format!("vec3<u32>({}u, {}u, {}u)", v[0], v[1], v[2]);
    let mut h = format!("alias real = {};\n", precision.wgsl());
    h += &format!("const NC: vec3<u32> = {};\n", vec3(b.n));
    h += &format!("const GH: vec3<u32> = {};\n", vec3(b.ghosts()));
    let sides: Vec<String> = b
        .sides
        .iter()
        .flatten()
        .map(|s| format!("{}u", s.kind()))
        .collect();
    h += &format!(
        "var<private> SIDE: array<u32, 6> = array<u32, 6>({});\n",
        sides.join(", ")
    );
    let u_off = mem.comp.map(|a| a.map_or(0, |a| a.u));
    h += &format!(
        "var<private> U_OFF: array<u32, 3> = array<u32, 3>({}u, {}u, {}u);\n",
        u_off[0], u_off[1], u_off[2]
    );
    h += &format!(
        "const Q_OFF: u32 = {}u;\nconst PHI_OFF: u32 = {}u;\n",
        mem.q, mem.phi
    );
    let levels: Vec<String> = mem.levels.iter().map(|l| vec3(l.cells)).collect();
    h += &format!(
        "var<private> LEVEL_N: array<vec3<u32>, {}> = array<vec3<u32>, {}>({});\n",
        levels.len(),
        levels.len(),
        levels.join(", ")
    );
    h += &format!("const SINGULAR: bool = {};\n", b.singular());
    h += &format!("const COARSEST_SWEEPS: u32 = {COARSEST_SWEEPS}u;\n");
    h += &format!("const MARKER: u32 = {MARKER}u;\n");
    for k in 0..SEGMENTS - 1 {
        h += &format!("const SEG{}: u32 = {}u;\n", k + 1, segments.ends[k]);
    }
    for (name, at) in slot::NAMED {
        h += &format!("const {name}: u32 = {at}u;\n");
    }
    h + include_str!("flow.wgsl")
}

fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let storage = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: false },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let blocks = wgpu::BindGroupLayoutEntry {
        binding: 5,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let op = wgpu::BindGroupLayoutEntry {
        binding: 3,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: true,
            min_binding_size: wgpu::BufferSize::new(RECORD_BYTES as u64),
        },
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("flow"),
        entries: &[
            storage(0),
            storage(1),
            storage(2),
            op,
            storage(4),
            blocks,
            storage(6),
            storage(7),
            storage(8),
        ],
    })
}

fn bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    b: &Buffers,
) -> wgpu::BindGroup {
    fn whole(binding: u32, buf: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
        wgpu::BindGroupEntry {
            binding,
            resource: buf.as_entire_binding(),
        }
    }
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("flow"),
        layout,
        entries: &[
            whole(0, &b.f[0]),
            whole(6, &b.f[1]),
            whole(7, &b.f[2]),
            whole(8, &b.f[3]),
            whole(1, &b.s),
            whole(2, &b.part),
            whole(4, &b.markers),
            whole(5, &b.blocks),
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &b.ops,
                    offset: 0,
                    size: wgpu::BufferSize::new(RECORD_BYTES as u64),
                }),
            },
        ],
    })
}

fn pipelines(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    source: &str,
) -> Result<Vec<wgpu::ComputePipeline>, GpuError> {
    device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("flow"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("flow"),
        bind_group_layouts: &[layout],
        push_constant_ranges: &[],
    });
    let made = KERNELS
        .iter()
        .map(|entry| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        })
        .collect();
    debug_assert_eq!(KERNELS.len(), Kernel::Spread as usize + 1);
    match pollster::block_on(device.pop_error_scope()) {
        Some(e) => Err(GpuError::Kernel(e.to_string())),
        None => Ok(made),
    }
}
