//! Compute pipelines from one WGSL source: one a named entry point, all
//! sharing one bind group layout.

use crate::device::GpuError;

/// The pipelines of `entries` in the WGSL `source` (`label` names the
/// module in the adapter's messages); a source the device rejects is the
/// error.
pub fn pipelines(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    label: &str,
    source: &str,
    entries: &[&str],
) -> Result<Vec<wgpu::ComputePipeline>, GpuError> {
    device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[layout],
        push_constant_ranges: &[],
    });
    let made = entries
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
    match pollster::block_on(device.pop_error_scope()) {
        Some(e) => Err(GpuError::Kernel(e.to_string())),
        None => Ok(made),
    }
}
