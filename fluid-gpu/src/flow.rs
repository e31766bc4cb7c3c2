//! The flow on the device: its buffers and kernels, the state uploaded
//! once and kept there, a step run as the lists of `plan.rs` with the
//! solves iterated on the device until their flags say they are done.

use crate::kernels::{bind_group, bind_group_layout, pipelines, records, source};
use crate::markers::{Sorted, MARKER};
use crate::memory::{block, slot, slots, Memory};
use crate::pass::{Pass, RECORD_BYTES};
use crate::plan::Plan;
use crate::spec::{FlowBox, Side};
use crate::state::{Segments, SEGMENTS};
use gpu_device::{buffer, non_empty, Gpu, GpuError, Precision};

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
pub(crate) const COARSEST_SWEEPS: usize = 40;

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

/// The flow's monitors as the device sums them: Σ|v|² and Σv over the
/// cells (v the mean of a cell's faces along each axis), the largest
/// |∇·u| [1/s], and the largest change of a face velocity since
/// [`Flow::remember`] [m/s].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Monitors {
    pub sum_squares: f64,
    pub sum: [f64; 3],
    pub max_divergence: f64,
    pub max_change: f64,
}

/// What a step did.
#[derive(Debug, Clone, Copy, Default)]
pub struct Report {
    /// Whether the step took its window's kept prediction (`window.rs`).
    pub kept_prediction: bool,
    pub pressure_iterations: usize,
    pub viscous_iterations: usize,
}

pub(crate) struct Buffers {
    /// The arrays, in up to SEGMENTS bindings.
    pub(crate) f: Vec<wgpu::Buffer>,
    pub(crate) s: wgpu::Buffer,
    pub(crate) part: wgpu::Buffer,
    pub(crate) ops: wgpu::Buffer,
    pub(crate) readback: wgpu::Buffer,
    /// The markers' records and their blocks (`markers.rs`), grown as needed.
    pub(crate) markers: wgpu::Buffer,
    pub(crate) blocks: wgpu::Buffer,
}

/// The incompressible flow on a box, its state on the device.
pub struct Flow {
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    pub(crate) precision: Precision,
    pub(crate) spec: FlowBox,
    pub(crate) mem: Memory,
    pub(crate) plan: Plan,
    pub(crate) pipelines: Vec<wgpu::ComputePipeline>,
    pub(crate) buffers: Buffers,
    pub(crate) segments: Segments,
    pub(crate) layout: wgpu::BindGroupLayout,
    pub(crate) bind_group: wgpu::BindGroup,
    pub(crate) op_stride: u32,
    /// A copy of the state on the device (`snapshot`), and the step
    /// history's scalars with it.
    pub(crate) snapshot: Option<(wgpu::Buffer, Option<f64>)>,
    /// A window's first prediction (`window.rs`), whether it is this
    /// window's, and whether the state was just restored to the window's
    /// start.
    pub(crate) kept: Option<crate::window::Kept>,
    pub(crate) kept_valid: bool,
    pub(crate) restored: bool,
    /// The markers as the device holds them, and the forcing's passes.
    pub(crate) sorted: Option<Sorted>,
    pub(crate) forcing: Vec<Pass>,
    /// The slot the next step's Nⁿ goes to.
    pub(crate) parity: usize,
    pub(crate) last_dt: Option<f64>,
    /// Σ_a|u_a|/h_a's largest over the cells, and their sum (not finite
    /// where a velocity is not), of the state as it is.
    pub(crate) courant: [f64; 2],
    /// Iterations a submit runs of the viscous and the pressure solves
    /// (their last counts: most steps then need one submit each).
    pub(crate) batch: [usize; 2],
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
            kept: None,
            kept_valid: false,
            restored: false,
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
    pub(crate) fn write_constants(&self) {
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

    pub(crate) fn write_scalars(&self, first: usize, values: &[f64]) {
        let at = (first * self.precision.size()) as u64;
        let bytes = self.precision.bytes(values);
        self.queue.write_buffer(&self.buffers.s, at, &bytes);
    }

    /// The Courant number Σ_a|u_a|Δt/h_a of a step of `dt` from the state
    /// as it is (NaN where a velocity is not finite).
    pub fn courant(&self, dt: f64) -> f64 {
        match self.courant[1].is_finite() {
            true => self.courant[0] * dt,
            false => f64::NAN,
        }
    }

    /// Copies u as the window's start, for [`Monitors::max_change`].
    pub fn remember(&mut self) -> Result<(), GpuError> {
        self.run(&[&self.plan.remember])
    }

    /// The monitors of the state as it is, summed on the device.
    pub fn monitors(&mut self) -> Result<Monitors, GpuError> {
        self.run(&[&self.plan.monitors])?;
        let s = self.read_scalars()?;
        let m = &s[slot::MON..slot::MON + 8];
        Ok(Monitors {
            sum_squares: m[0],
            sum: [m[1], m[2], m[3]],
            max_divergence: m[4],
            max_change: (0..3)
                .filter(|&c| self.mem.comp[c].is_some())
                .map(|c| m[5 + c])
                .fold(0.0, f64::max),
        })
    }

    /// Measures the state's Courant number.
    pub(crate) fn measure(&mut self) -> Result<(), GpuError> {
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
        self.step_in_window(dt, moving, false)
    }

    /// [`Flow::step_moving`]; `first`: the step is the first of a window
    /// implicit coupling may take again, whose prediction a later try takes
    /// (`window.rs`).
    pub fn step_in_window(
        &mut self,
        dt: f64,
        moving: &Moving,
        first: bool,
    ) -> Result<Report, FlowError> {
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
        let kept = first && self.takes_kept(dt, moving);
        let viscous = match kept {
            true => {
                self.load_kept();
                self.kept.as_ref().map_or(0, |k| k.viscous_iterations)
            }
            false => {
                let start = self.plan.start[self.parity].clone();
                let viscous = self.iterate(&start, 0, &[])?.0;
                if first {
                    self.keep_prediction(dt, moving, viscous);
                }
                viscous
            }
        };
        self.restored = false;
        let plan = &self.plan;
        let lists =
            [&plan.change, &self.forcing, &plan.impose, &plan.projection].map(|l| l.as_slice());
        let projection: Vec<Pass> = lists.concat();
        let end = self.plan.end.clone();
        let (pressure, s) = self.iterate(&projection, 1, &end)?;
        if first {
            self.keep_correction();
        }
        self.courant = [s[slot::COURANT], s[slot::FINITE]];
        if !self.courant[1].is_finite() {
            return Err(FlowError::NonFinite);
        }
        self.parity = 1 - self.parity;
        self.last_dt = Some(dt);
        Ok(Report {
            kept_prediction: kept,
            pressure_iterations: pressure,
            viscous_iterations: viscous,
        })
    }

    /// Runs `first`, then the solve's iterations (0: the viscous solves,
    /// 1: the pressure's) in submits of `batch` until every one is done;
    /// returns the iterations (summed over the viscous components).
    fn iterate(
        &mut self,
        first: &[Pass],
        which: usize,
        tail: &[Pass],
    ) -> Result<(usize, Vec<f64>), FlowError> {
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
            lists.push(tail);
            self.run(&lists)?;
            taken += batch;
            lists.clear();
            let s = self.read_scalars()?;
            let at = |k: usize, what: usize| s[block(levels, k) + what];
            // The kernels flag a value that is not finite, but a driver may
            // take floats as always finite and fold their test away (Vulkan
            // keeps NaN and Inf only where a shader asks): so the residuals
            // read here are checked too.
            let blown = |k: usize| at(k, slot::FAIL) != 0.0 || !at(k, slot::RR).is_finite();
            if solves.iter().any(|&k| blown(k)) {
                return Err(FlowError::NonFinite);
            }
            let iterations: Vec<usize> =
                solves.iter().map(|&k| at(k, slot::ITER) as usize).collect();
            if solves.iter().all(|&k| at(k, slot::DONE) != 0.0) {
                let most_taken = iterations.iter().copied().max().unwrap_or(0);
                self.batch[which] = most_taken.max(1);
                return Ok((iterations.iter().sum(), s));
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
    pub(crate) fn run(&self, lists: &[&[Pass]]) -> Result<(), GpuError> {
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

    pub(crate) fn active(&self) -> Vec<(usize, crate::memory::Component)> {
        (0..3)
            .filter_map(|c| self.mem.comp[c].map(|a| (c, a)))
            .collect()
    }
}
