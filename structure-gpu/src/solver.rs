//! A network's state on the device and the explicit steps that advance it
//! there: positions and velocities stay on the device across steps; only
//! what the caller uploads and downloads crosses.

use crate::device::{Gpu, GpuError, Precision};
use crate::network::Network;
use crate::program::{vector, Pass, Scheme};
use wgpu::util::DeviceExt;

/// Threads per workgroup (the kernels' `@workgroup_size`).
const WORKGROUP: u32 = 64;

/// Steps encoded in one command buffer: long runs are submitted in pieces.
const STEPS_PER_SUBMIT: u64 = 256;

/// The kernels' three entry points.
struct Pipelines {
    slots: wgpu::ComputePipeline,
    gather: wgpu::ComputePipeline,
    combine: wgpu::ComputePipeline,
}

/// A network on the device under one explicit scheme.
pub struct Solver {
    device: wgpu::Device,
    queue: wgpu::Queue,
    precision: Precision,
    nodes: usize,
    elements: u32,
    passes: Vec<Pass>,
    pipelines: Pipelines,
    bind_group: wgpu::BindGroup,
    vecs: wgpu::Buffer,
    params: wgpu::Buffer,
    /// One op record per pass, `op_stride` bytes apart.
    op_stride: u32,
    readback: wgpu::Buffer,
    /// The step the coefficients were written for.
    h: Option<f64>,
}

impl Solver {
    /// Hand `net` to the device for steps of `scheme`. The state starts at
    /// rest at the origin: [`Solver::upload`] sets it.
    pub fn new(gpu: &Gpu, net: &Network, scheme: Scheme) -> Result<Solver, GpuError> {
        let device = gpu.device.clone();
        let precision = gpu.precision();
        let nodes = net.nodes();
        let elements = u32::try_from(net.springs.len() + net.acting_dampers().len())
            .map_err(|_| GpuError::TooManyElements("the springs and dampers"))?;
        let passes = scheme.passes();
        let vec_len = 3 * nodes as u64 * precision.size() as u64;
        check_size(&device, "the state", vec_len * scheme.vectors() as u64)?;
        check_size(
            &device,
            "the element slots",
            3 * elements as u64 * precision.size() as u64,
        )?;

        let storage = wgpu::BufferUsages::STORAGE;
        let reals = |label, values: &[f64]| {
            buffer(&device, label, &padded(precision.bytes(values)), storage)
        };
        let vecs = buffer(
            &device,
            "state",
            &vec![0u8; (vec_len * scheme.vectors() as u64) as usize],
            storage | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        );
        let slots = reals("slots", &vec![0.0; 3 * elements as usize]);
        let ends = buffer(
            &device,
            "ends",
            &padded(bytemuck::cast_slice(&net.ends()?).to_vec()),
            storage,
        );
        let element_reals = reals("elements", &net.element_reals());
        let node_reals = reals("nodes", &net.node_reals());
        let assembly = buffer(
            &device,
            "assembly",
            bytemuck::cast_slice(&net.assembly()?),
            storage,
        );
        let mut params = net.gravity.to_vec();
        params.resize(3 + passes.len(), 0.0);
        let params = buffer(
            &device,
            "params",
            &precision.bytes(&params),
            storage | wgpu::BufferUsages::COPY_DST,
        );
        let op_stride = 16u32.max(device.limits().min_uniform_buffer_offset_alignment);
        let ops = buffer(
            &device,
            "ops",
            &op_records(&passes, op_stride),
            wgpu::BufferUsages::UNIFORM,
        );
        let layout = bind_group_layout(&device);
        let pipelines = pipelines(&device, &layout, &source(precision, net))?;
        let storage_buffers = [
            &vecs,
            &slots,
            &ends,
            &element_reals,
            &node_reals,
            &assembly,
            &params,
        ];
        let mut entries: Vec<wgpu::BindGroupEntry> = storage_buffers
            .iter()
            .enumerate()
            .map(|(b, buf)| wgpu::BindGroupEntry {
                binding: b as u32,
                resource: buf.as_entire_binding(),
            })
            .collect();
        entries.push(wgpu::BindGroupEntry {
            binding: 7,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &ops,
                offset: 0,
                size: wgpu::BufferSize::new(16),
            }),
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("structure"),
            layout: &layout,
            entries: &entries,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: 2 * vec_len,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Ok(Solver {
            device,
            queue: gpu.queue.clone(),
            precision,
            nodes,
            elements,
            passes,
            pipelines,
            bind_group,
            vecs,
            params,
            op_stride,
            readback,
            h: None,
        })
    }

    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// Set the state: positions `x` [m] and velocities `v` [m/s], 3 per node.
    pub fn upload(&mut self, x: &[f64], v: &[f64]) {
        assert!(
            x.len() == 3 * self.nodes && v.len() == 3 * self.nodes,
            "3 values a node"
        );
        let mut both = x.to_vec();
        both.extend_from_slice(v);
        self.queue
            .write_buffer(&self.vecs, 0, &self.precision.bytes(&both));
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
            let at = 3 * self.precision.size() as u64;
            self.queue
                .write_buffer(&self.params, at, &self.precision.bytes(&coefs));
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
                    let (x, y) = workgroups(threads);
                    pass.dispatch_workgroups(x, y, 1);
                }
            }
        }
        encoder.finish()
    }

    /// Wait for the queued steps and read the state back into `x`, `v`.
    pub fn download(&self, x: &mut [f64], v: &mut [f64]) -> Result<(), GpuError> {
        let len = 3 * self.nodes;
        assert!(x.len() == len && v.len() == len, "3 values a node");
        let bytes = self.readback.size();
        let mut encoder = self.device.create_command_encoder(&Default::default());
        // X and V are the state's first two vectors, one after the other.
        const { assert!(vector::X == 0 && vector::V == 1) };
        encoder.copy_buffer_to_buffer(&self.vecs, 0, &self.readback, 0, bytes);
        self.queue.submit([encoder.finish()]);
        let slice = self.readback.slice(..);
        let (sent, mapped) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = sent.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Lost(e.to_string()))?;
        mapped
            .recv()
            .map_err(|e| GpuError::Lost(e.to_string()))?
            .map_err(|e| GpuError::Lost(e.to_string()))?;
        {
            let data = slice.get_mapped_range();
            let size = self.precision.size() * len;
            self.precision.read(&data[..size], x);
            self.precision.read(&data[size..2 * size], v);
        }
        self.readback.unmap();
        Ok(())
    }

    /// Wait for the queued steps (for timing).
    pub fn finish(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Lost(e.to_string()))
    }
}

/// Refuse a buffer larger than the device binds.
fn check_size(device: &wgpu::Device, what: &'static str, needed: u64) -> Result<(), GpuError> {
    let limits = device.limits();
    let limit = (limits.max_storage_buffer_binding_size as u64).min(limits.max_buffer_size);
    if needed > limit {
        return Err(GpuError::TooLarge {
            what,
            needed,
            limit,
        });
    }
    Ok(())
}

/// A binding may not be empty: an element-free network gets one unused word.
fn padded(mut bytes: Vec<u8>) -> Vec<u8> {
    if bytes.is_empty() {
        bytes.resize(8, 0);
    }
    bytes
}

fn buffer(
    device: &wgpu::Device,
    label: &str,
    contents: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents,
        usage,
    })
}

/// Workgroups for `threads` threads: along x up to the 65 535 every
/// adapter allows, then rows of y (the kernels' `index`).
fn workgroups(threads: u32) -> (u32, u32) {
    const MAX: u32 = 65_535;
    let groups = threads.div_ceil(WORKGROUP).max(1);
    if groups <= MAX {
        (groups, 1)
    } else {
        (MAX, groups.div_ceil(MAX))
    }
}

/// One `Op` record (out, a, b, coefficient << 1 | scaled) per pass.
fn op_records(passes: &[Pass], stride: u32) -> Vec<u8> {
    let mut bytes = vec![0u8; passes.len() * stride as usize];
    for (k, p) in passes.iter().enumerate() {
        let record: [u32; 4] = match *p {
            Pass::Slots { x, v } => [0, x, v, 0],
            Pass::Gather { out } => [out, 0, 0, 0],
            Pass::Combine {
                out, a, b, scaled, ..
            } => [out, a, b, (k as u32) << 1 | scaled as u32],
        };
        let at = k * stride as usize;
        bytes[at..at + 16].copy_from_slice(bytemuck::cast_slice(&record));
    }
    bytes
}

/// The kernels' source with the network's sizes and the precision.
fn source(precision: Precision, net: &Network) -> String {
    let law = match net.damping {
        Some(crate::DampingLaw::Axial) => 1,
        _ => 0,
    };
    let header = format!(
        "alias real = {};\nconst NODES: u32 = {}u;\nconst SPRINGS: u32 = {}u;\nconst DAMPERS: u32 = {}u;\nconst DAMPING_LAW: u32 = {}u;\n",
        precision.wgsl(),
        net.nodes(),
        net.springs.len(),
        net.acting_dampers().len(),
        law,
    );
    header + include_str!("solver.wgsl")
}

/// Bindings 0–1 read and written, 2–6 read, 7 the pass's op.
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
    device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("structure"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("structure"),
        bind_group_layouts: &[layout],
        push_constant_ranges: &[],
    });
    let pipeline = |entry: &str| {
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        })
    };
    let pipelines = Pipelines {
        slots: pipeline("element_slots"),
        gather: pipeline("gather"),
        combine: pipeline("combine"),
    };
    match pollster::block_on(device.pop_error_scope()) {
        Some(e) => Err(GpuError::Kernel(e.to_string())),
        None => Ok(pipelines),
    }
}
