//! The kernels on the device: their source (the box's constants, then
//! the WGSL), their bindings and pipelines, and the passes' records.

use crate::flow::{Buffers, COARSEST_SWEEPS};
use crate::markers::MARKER;
use crate::memory::{slot, Memory};
use crate::pass::{Kernel, KERNELS, RECORD_BYTES};
use crate::plan::Plan;
use crate::spec::FlowBox;
use crate::state::{Segments, SEGMENTS};
use gpu_device::{GpuError, Precision};

/// The records, one per `op_stride` bytes.
pub(crate) fn records(plan: &Plan, stride: u32) -> Vec<u8> {
    let mut bytes = vec![0u8; plan.records.len().max(1) * stride as usize];
    for (k, r) in plan.records.iter().enumerate() {
        let at = k * stride as usize;
        bytes[at..at + RECORD_BYTES].copy_from_slice(bytemuck::cast_slice(r));
    }
    bytes
}

/// The kernels' source: the box's constants, then flow.wgsl (bindings,
/// layouts, sides) and the passes' files.
pub(crate) fn source(
    precision: Precision,
    b: &FlowBox,
    mem: &Memory,
    segments: &Segments,
) -> String {
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
    let parts = [
        include_str!("flow.wgsl"),
        include_str!("advection.wgsl"),
        include_str!("solve.wgsl"),
        include_str!("projection.wgsl"),
        include_str!("forcing.wgsl"),
        include_str!("monitors.wgsl"),
    ];
    h + &parts.join("\n")
}

pub(crate) fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
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

pub(crate) fn bind_group(
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

pub(crate) fn pipelines(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    source: &str,
) -> Result<Vec<wgpu::ComputePipeline>, GpuError> {
    debug_assert_eq!(KERNELS.len(), Kernel::FaceChange as usize + 1);
    gpu_device::pipelines(device, layout, "flow", source, &KERNELS)
}
