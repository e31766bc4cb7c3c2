//! The adapter, the device and the precision the kernels run in.

use thiserror::Error;

/// The precision of the device's arithmetic: f64 where the adapter has it
/// (`SHADER_F64`: every Vulkan driver of a desktop GPU, and Mesa's llvmpipe),
/// else f32.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Precision {
    F64,
    F32,
}

impl Precision {
    /// Bytes per real.
    pub fn size(self) -> usize {
        match self {
            Precision::F64 => 8,
            Precision::F32 => 4,
        }
    }

    /// The WGSL type of a real.
    pub fn wgsl(self) -> &'static str {
        match self {
            Precision::F64 => "f64",
            Precision::F32 => "f32",
        }
    }

    /// `values` as the device stores them.
    pub fn bytes(self, values: &[f64]) -> Vec<u8> {
        match self {
            Precision::F64 => bytemuck::cast_slice(values).to_vec(),
            Precision::F32 => {
                let narrow: Vec<f32> = values.iter().map(|&v| v as f32).collect();
                bytemuck::cast_slice(&narrow).to_vec()
            }
        }
    }

    /// Reals the device stored, widened to f64 into `out`.
    pub fn read(self, bytes: &[u8], out: &mut [f64]) {
        match self {
            Precision::F64 => out.copy_from_slice(bytemuck::cast_slice(bytes)),
            Precision::F32 => {
                let narrow: &[f32] = bytemuck::cast_slice(bytes);
                for (o, &v) in out.iter_mut().zip(narrow) {
                    *o = v as f64;
                }
            }
        }
    }
}

/// Everything that can go wrong on the device, one variant per cause.
#[derive(Debug, Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found ({0}); on Linux without a GPU, Mesa's CPU Vulkan driver gives one: \
         apt-get install -y --no-install-recommends mesa-vulkan-drivers libvulkan1"
    )]
    NoAdapter(String),
    #[error("the adapter {adapter} refused a device: {source}")]
    Device {
        adapter: String,
        source: wgpu::RequestDeviceError,
    },
    #[error("too large for this adapter: {what} needs {needed} bytes, it binds at most {limit}")]
    TooLarge {
        what: &'static str,
        needed: u64,
        limit: u64,
    },
    #[error("{0} does not fit the device's 32-bit indices")]
    TooManyElements(&'static str),
    #[error("the device rejected the kernels: {0}")]
    Kernel(String),
    #[error("the device stopped while running: {0}")]
    Lost(String),
}

/// The environment variable that makes a missing adapter a test failure
/// rather than a skip (`.ci/run` sets it: Mesa's llvmpipe is installed there).
pub const REQUIRE_GPU: &str = "CANOPY_REQUIRE_GPU";

/// An adapter, its device and queue, and the precision kernels use on it.
pub struct Gpu {
    device: wgpu::Device,
    queue: wgpu::Queue,
    precision: Precision,
    name: String,
}

impl Gpu {
    /// The first adapter of the platform's primary backends (Vulkan, Metal,
    /// DX12; `WGPU_BACKEND` chooses others), preferring a discrete GPU, with
    /// f64 where it has it.
    pub fn new() -> Result<Gpu, GpuError> {
        Gpu::with_precision(None)
    }

    /// As [`Gpu::new`], with the precision forced (f32 on an f64 adapter
    /// measures what an f32-only adapter would give).
    pub fn with_precision(precision: Option<Precision>) -> Result<Gpu, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::from_env_or_default();
        if std::env::var_os("WGPU_BACKEND").is_none() {
            // The GL backend's probe complains on a machine without a display.
            desc.backends = wgpu::Backends::PRIMARY;
        }
        let instance = wgpu::Instance::new(&desc);
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        };
        let adapter = pollster::block_on(instance.request_adapter(&options))
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let name = format!("{} ({:?}, {:?})", info.name, info.device_type, info.backend);
        let has_f64 = adapter.features().contains(wgpu::Features::SHADER_F64);
        let precision = match precision {
            Some(Precision::F64) if !has_f64 => {
                return Err(GpuError::NoAdapter(format!("{name} has no f64 arithmetic")))
            }
            Some(p) => p,
            None if has_f64 => Precision::F64,
            None => Precision::F32,
        };
        let features = match precision {
            Precision::F64 => wgpu::Features::SHADER_F64,
            Precision::F32 => wgpu::Features::empty(),
        };
        let desc = wgpu::DeviceDescriptor {
            label: Some("canopy"),
            required_features: features,
            // As large as the adapter binds: big canopies need big buffers.
            required_limits: adapter.limits(),
            ..Default::default()
        };
        let (device, queue) =
            pollster::block_on(adapter.request_device(&desc)).map_err(|source| {
                GpuError::Device {
                    adapter: name.clone(),
                    source,
                }
            })?;
        Ok(Gpu {
            device,
            queue,
            precision,
            name,
        })
    }

    /// For tests: the device in `precision`, or None (with a note) where
    /// no adapter is found and [`REQUIRE_GPU`] is unset; where it is set
    /// (CI sets it) a missing adapter fails the test.
    pub fn for_tests(precision: Option<Precision>) -> Option<Gpu> {
        match Gpu::with_precision(precision) {
            Ok(gpu) => Some(gpu),
            Err(e) if std::env::var_os(REQUIRE_GPU).is_none() => {
                eprintln!("skipped: {e}");
                None
            }
            Err(e) => panic!("{REQUIRE_GPU} is set: {e}"),
        }
    }

    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// The adapter's name, type and backend, for reports.
    pub fn name(&self) -> &str {
        &self.name
    }
}
