//! A network's state on the device and the explicit steps that advance it
//! there: positions and velocities stay on the device across steps; only
//! what the caller uploads and downloads crosses.

use crate::network::Network;
use crate::program::{vector, Pass, Scheme};
use gpu_device::{buffer, check_size, non_empty, read_back, workgroups, Gpu, GpuError, Precision};

/// Threads per workgroup (the kernels' `@workgroup_size`).
const WORKGROUP: u32 = 64;

/// Where the step's coefficients start in the params buffer (the kernels' COEFS).
const COEFS: usize = 10;

/// Steps encoded in one command buffer: long runs are submitted in pieces.
const STEPS_PER_SUBMIT: u64 = 256;

/// The kernels' three entry points.
struct Pipelines {
    slots: wgpu::ComputePipeline,
    gather: wgpu::ComputePipeline,
    combine: wgpu::ComputePipeline,
}

/// The device's buffers, bound at the kernels' binding numbers (0–6, 8).
struct Buffers {
    /// 0: the vectors (positions, velocities, forces, stage values).
    vecs: wgpu::Buffer,
    /// 1: the element slots.
    slots: wgpu::Buffer,
    /// 2–5: the elements' nodes and reals, the nodes' masses, the assembly.
    element_nodes: wgpu::Buffer,
    elements: wgpu::Buffer,
    nodes: wgpu::Buffer,
    assembly: wgpu::Buffer,
    /// 6: gravity, the porous law, the step's coefficients.
    params: wgpu::Buffer,
    /// 8: the fluid's pressure jump per pressure triangle.
    received: wgpu::Buffer,
}

impl Buffers {
    fn new(
        device: &wgpu::Device,
        p: Precision,
        net: &Network,
        scheme: Scheme,
    ) -> Result<Buffers, GpuError> {
        // The scheme's vectors and the reaction.
        let vectors = scheme.vectors() as usize + 1;
        let state_bytes = 3 * (net.nodes() * vectors * p.size()) as u64;
        check_size(device, "the state", state_bytes)?;
        check_size(
            device,
            "the element slots",
            (3 * net.slots() * p.size()) as u64,
        )?;
        let (element_nodes, element_reals) = (net.element_nodes()?, net.element_reals());
        let assembly = net.assembly()?;
        check_size(
            device,
            "the elements",
            (element_reals.len() * p.size()) as u64,
        )?;
        check_size(device, "the element nodes", 4 * element_nodes.len() as u64)?;
        check_size(device, "the assembly", 4 * assembly.len() as u64)?;
        let storage = wgpu::BufferUsages::STORAGE;
        let copied = storage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let reals = |label, values: &[f64], usage| {
            buffer(device, label, &non_empty(p.bytes(values)), usage)
        };
        let words = |label, values: &[u32]| {
            buffer(
                device,
                label,
                &non_empty(bytemuck::cast_slice(values).to_vec()),
                storage,
            )
        };
        let mut params = net.gravity.to_vec();
        if let Some(law) = &net.porous {
            params.extend(law.free_stream);
            params.extend([law.a, law.b, law.porosity, law.thickness]);
        }
        params.resize(COEFS + scheme.passes().len(), 0.0);
        Ok(Buffers {
            vecs: reals("state", &vec![0.0; state_bytes as usize / p.size()], copied),
            slots: reals("slots", &vec![0.0; 3 * net.slots()], storage),
            element_nodes: words("element nodes", &element_nodes),
            elements: reals("elements", &element_reals, storage),
            nodes: reals("nodes", &net.node_reals(), storage),
            assembly: words("assembly", &assembly),
            params: reals("params", &params, copied),
            received: reals("received", &vec![0.0; net.triangles.len()], copied),
        })
    }

    /// The bind group of these buffers and the op records `ops`.
    fn bind_group(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        ops: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let storage = [
            (0, &self.vecs),
            (1, &self.slots),
            (2, &self.element_nodes),
            (3, &self.elements),
            (4, &self.nodes),
            (5, &self.assembly),
            (6, &self.params),
            (8, &self.received),
        ];
        let mut entries: Vec<wgpu::BindGroupEntry> = storage
            .iter()
            .map(|&(binding, buf)| wgpu::BindGroupEntry {
                binding,
                resource: buf.as_entire_binding(),
            })
            .collect();
        entries.push(wgpu::BindGroupEntry {
            binding: 7,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: ops,
                offset: 0,
                size: wgpu::BufferSize::new(16),
            }),
        });
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("structure"),
            layout,
            entries: &entries,
        })
    }
}

/// A network on the device under one explicit scheme.
pub struct Solver {
    device: wgpu::Device,
    queue: wgpu::Queue,
    precision: Precision,
    nodes: usize,
    /// Threads of the element pass: springs, membrane triangles, dampers
    /// and pressure triangles.
    elements: u32,
    triangles: usize,
    passes: Vec<Pass>,
    pipelines: Pipelines,
    buffers: Buffers,
    bind_group: wgpu::BindGroup,
    /// One op record per pass, `op_stride` bytes apart.
    op_stride: u32,
    /// Large enough for X and V.
    readback: wgpu::Buffer,
    /// The vector that sums the reactions: after the scheme's own.
    reaction: u32,
    /// The step the coefficients were written for.
    h: Option<f64>,
}

impl Solver {
    /// Hand `net` to the device for steps of `scheme`. The state starts at
    /// rest at the origin: [`Solver::upload`] sets it.
    pub fn new(gpu: &Gpu, net: &Network, scheme: Scheme) -> Result<Solver, GpuError> {
        // Errors in creating buffers, pipelines and bindings come back here
        // instead of reaching wgpu's default handler, which panics.
        gpu.device()
            .push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        gpu.device().push_error_scope(wgpu::ErrorFilter::Validation);
        let made = Solver::make(gpu, net, scheme);
        for _ in 0..2 {
            if let Some(e) = pollster::block_on(gpu.device().pop_error_scope()) {
                return Err(GpuError::Kernel(e.to_string()));
            }
        }
        made
    }

    fn make(gpu: &Gpu, net: &Network, scheme: Scheme) -> Result<Solver, GpuError> {
        let device = gpu.device().clone();
        let precision = gpu.precision();
        let items = net.springs.len()
            + net.membrane.len()
            + net.acting_dampers().len()
            + net.triangles.len();
        let elements =
            u32::try_from(items).map_err(|_| GpuError::TooManyElements("the elements"))?;
        let passes = scheme.passes();
        let buffers = Buffers::new(&device, precision, net, scheme)?;
        let op_stride = 16u32.max(device.limits().min_uniform_buffer_offset_alignment);
        let ops = buffer(
            &device,
            "ops",
            &op_records(&passes, op_stride),
            wgpu::BufferUsages::UNIFORM,
        );
        let layout = bind_group_layout(&device);
        let pipelines = pipelines(&device, &layout, &source(precision, net, scheme))?;
        let bind_group = buffers.bind_group(&device, &layout, &ops);
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: (6 * net.nodes() * precision.size()) as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(Solver {
            device,
            queue: gpu.queue().clone(),
            precision,
            nodes: net.nodes(),
            elements,
            triangles: net.triangles.len(),
            passes,
            pipelines,
            buffers,
            bind_group,
            op_stride,
            readback,
            reaction: scheme.vectors(),
            h: None,
        })
    }

    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// Set the state: positions `x` [m] and velocities `v` [m/s], 3 per
    /// node; the reaction starts again from zero.
    pub fn upload(&mut self, x: &[f64], v: &[f64]) {
        assert!(
            x.len() == 3 * self.nodes && v.len() == 3 * self.nodes,
            "3 values a node"
        );
        let mut both = x.to_vec();
        both.extend_from_slice(v);
        let p = self.precision;
        self.queue
            .write_buffer(&self.buffers.vecs, 0, &p.bytes(&both));
        let at = (self.reaction as usize * x.len() * p.size()) as u64;
        self.queue
            .write_buffer(&self.buffers.vecs, at, &p.bytes(&vec![0.0; x.len()]));
    }

    /// Set the fluid's pressure jump on each of the network's pressure
    /// triangles [Pa], held until set again (zero until first set).
    pub fn set_pressure(&mut self, jump: &[f64]) {
        assert_eq!(jump.len(), self.triangles, "a jump per pressure triangle");
        if !jump.is_empty() {
            self.queue
                .write_buffer(&self.buffers.received, 0, &self.precision.bytes(jump));
        }
    }

    /// Advance the state on the device by `steps` steps of `h` [s]. Returns
    /// once the work is queued; [`Solver::download`] waits for it.
    pub fn advance(&mut self, h: f64, steps: u64) -> Result<(), GpuError> {
        if self.h != Some(h) {
            let coefs: Vec<f64> = self
                .passes
                .iter()
                .map(|p| match p {
                    Pass::Combine { c, .. } => c.of(h),
                    _ => 0.0,
                })
                .collect();
            let at = (COEFS * self.precision.size()) as u64;
            self.queue
                .write_buffer(&self.buffers.params, at, &self.precision.bytes(&coefs));
            self.h = Some(h);
        }
        self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut left = steps;
        while left > 0 {
            let now = left.min(STEPS_PER_SUBMIT);
            self.queue.submit([self.encode(now)]);
            left -= now;
        }
        match pollster::block_on(self.device.pop_error_scope()) {
            Some(e) => Err(GpuError::Kernel(e.to_string())),
            None => Ok(()),
        }
    }

    /// `steps` steps in one command buffer.
    fn encode(&self, steps: u64) -> wgpu::CommandBuffer {
        let mut encoder = self.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            let nodes = self.nodes as u32;
            for _ in 0..steps {
                for (k, p) in self.passes.iter().enumerate() {
                    let (pipeline, threads) = match p {
                        Pass::Slots { .. } => (&self.pipelines.slots, self.elements),
                        Pass::Gather { .. } => (&self.pipelines.gather, nodes),
                        Pass::Combine { .. } => (&self.pipelines.combine, 3 * nodes),
                    };
                    pass.set_pipeline(pipeline);
                    pass.set_bind_group(0, &self.bind_group, &[k as u32 * self.op_stride]);
                    let (x, y) = workgroups(threads, WORKGROUP);
                    pass.dispatch_workgroups(x, y, 1);
                }
            }
        }
        encoder.finish()
    }

    /// Wait for the queued steps and read the state back into `x`, `v`.
    pub fn download(&self, x: &mut [f64], v: &mut [f64]) -> Result<(), GpuError> {
        // X and V are the state's first two vectors, one after the other.
        const { assert!(vector::X == 0 && vector::V == 1) };
        self.read(vector::X, &mut [x, v])
    }

    /// Wait for the queued steps and read into `out` the impulse [N·s] on
    /// every node with 1/m = 0 (held, or attached to a rigid body) since
    /// the last [`Solver::upload`], 3 per node (0 on the others): what
    /// the structure gave whatever holds them.
    pub fn reaction(&self, out: &mut [f64]) -> Result<(), GpuError> {
        self.read(self.reaction, &mut [out])
    }

    /// Wait for the queued steps and read the vectors from `first` on into
    /// `outs`, one after another.
    fn read(&self, first: u32, outs: &mut [&mut [f64]]) -> Result<(), GpuError> {
        let len = 3 * self.nodes;
        assert!(outs.iter().all(|o| o.len() == len), "3 values a node");
        if len == 0 {
            return Ok(());
        }
        let size = (self.precision.size() * len) as u64;
        let bytes = size * outs.len() as u64;
        let range = [(&self.buffers.vecs, first as u64 * size, bytes)];
        let data = read_back(&self.device, &self.queue, &range, &self.readback)?;
        for (k, out) in outs.iter_mut().enumerate() {
            let at = k * size as usize;
            self.precision.read(&data[at..at + size as usize], out);
        }
        Ok(())
    }
}

/// One `Op` record (out, a, b, coefficient << 2 | reacts << 1 | scaled) per pass.
fn op_records(passes: &[Pass], stride: u32) -> Vec<u8> {
    let mut bytes = vec![0u8; passes.len() * stride as usize];
    for (k, p) in passes.iter().enumerate() {
        let record: [u32; 4] = match *p {
            Pass::Slots { x, v } => [0, x, v, 0],
            Pass::Gather { out } => [out, 0, 0, 0],
            Pass::Combine {
                out,
                a,
                b,
                scaled,
                reacts,
                ..
            } => [
                out,
                a,
                b,
                (k as u32) << 2 | (reacts as u32) << 1 | scaled as u32,
            ],
        };
        let at = k * stride as usize;
        bytes[at..at + 16].copy_from_slice(bytemuck::cast_slice(&record));
    }
    bytes
}

/// The kernels' source with the network's sizes and the precision.
fn source(precision: Precision, net: &Network, scheme: Scheme) -> String {
    let law = match net.damping {
        Some(crate::DampingLaw::Axial) => 1,
        _ => 0,
    };
    let constants = [
        ("NODES", net.nodes()),
        ("SPRINGS", net.springs.len()),
        ("MEMBRANE", net.membrane.len()),
        ("DAMPERS", net.acting_dampers().len()),
        ("TRIANGLES", net.triangles.len()),
        ("DAMPING_LAW", law),
        ("POROUS", net.porous.is_some() as usize),
        ("REACTION", scheme.vectors() as usize),
    ];
    let mut header = format!("alias real = {};\n", precision.wgsl());
    for (name, value) in constants {
        header += &format!("const {name}: u32 = {value}u;\n");
    }
    header + include_str!("solver.wgsl")
}

/// Bindings 0–1 read and written, 2–6 and 8 read, 7 the pass's op.
fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let storage = |binding: u32, read_only: bool| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let mut entries: Vec<_> = (0..7).map(|b| storage(b, b >= 2)).collect();
    entries.push(wgpu::BindGroupLayoutEntry {
        binding: 7,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: true,
            min_binding_size: wgpu::BufferSize::new(16),
        },
        count: None,
    });
    entries.push(storage(8, true));
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("structure"),
        entries: &entries,
    })
}

/// The three kernels, compiled; a shader the device rejects is an error.
fn pipelines(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    source: &str,
) -> Result<Pipelines, GpuError> {
    let entries = ["element_slots", "gather", "combine"];
    let [slots, gather, combine]: [wgpu::ComputePipeline; 3] =
        gpu_device::pipelines(device, layout, "structure", source, &entries)?
            .try_into()
            .expect("a pipeline an entry");
    Ok(Pipelines {
        slots,
        gather,
        combine,
    })
}
