//! Buffers on the device: made from bytes, checked against what the
//! adapter binds, read back; and how many workgroups a pass of threads takes.

use crate::device::GpuError;
use wgpu::util::DeviceExt;

/// Refuse a buffer larger than the device binds.
pub fn check_size(device: &wgpu::Device, what: &'static str, needed: u64) -> Result<(), GpuError> {
    let limit = binding_limit(device);
    if needed > limit {
        return Err(GpuError::TooLarge {
            what,
            needed,
            limit,
        });
    }
    Ok(())
}

/// The most bytes one storage binding of `device` may hold.
pub fn binding_limit(device: &wgpu::Device) -> u64 {
    let limits = device.limits();
    (limits.max_storage_buffer_binding_size as u64).min(limits.max_buffer_size)
}

/// A binding may not be empty: an empty array gets one unused word.
pub fn non_empty(mut bytes: Vec<u8>) -> Vec<u8> {
    if bytes.is_empty() {
        bytes.resize(8, 0);
    }
    bytes
}

/// A buffer holding `contents`.
pub fn buffer(
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

/// Workgroups of `size` threads for `threads` threads: along x up to the
/// 65 535 every adapter allows, then rows of y (a kernel's thread index is
/// gid.x + gid.y·x·size).
pub fn workgroups(threads: u32, size: u32) -> (u32, u32) {
    const MAX: u32 = 65_535;
    let groups = threads.div_ceil(size).max(1);
    if groups <= MAX {
        (groups, 1)
    } else {
        (MAX, groups.div_ceil(MAX))
    }
}

/// The byte ranges (source, offset, length), one after the other,
/// through the mappable `readback` buffer (at least their sum long):
/// waits for the queue.
pub fn read_back(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    ranges: &[(&wgpu::Buffer, u64, u64)],
    readback: &wgpu::Buffer,
) -> Result<Vec<u8>, GpuError> {
    let mut encoder = device.create_command_encoder(&Default::default());
    let mut bytes = 0;
    for &(source, offset, len) in ranges {
        encoder.copy_buffer_to_buffer(source, offset, readback, bytes, len);
        bytes += len;
    }
    queue.submit([encoder.finish()]);
    let slice = readback.slice(..bytes);
    let (sent, mapped) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = sent.send(r);
    });
    let lost = |e: &dyn std::fmt::Display| GpuError::Lost(e.to_string());
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| lost(&e))?;
    mapped.recv().map_err(|e| lost(&e))?.map_err(|e| lost(&e))?;
    let data = slice.get_mapped_range().to_vec();
    readback.unmap();
    Ok(data)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every thread index gid.x + gid.y·x·size below n is reached, and x
    /// stays within the 65 535 workgroups an adapter allows.
    #[test]
    fn the_workgroups_cover_every_thread() {
        for size in [64, 256] {
            for n in [1, 63, 64, 65, 65_535 * 64, 65_535 * 64 + 1, 10_000_000] {
                let (x, y) = workgroups(n, size);
                assert!(x <= 65_535 && y >= 1, "{n}: {x} × {y}");
                let threads = x as u64 * y as u64 * size as u64;
                assert!(threads >= n as u64, "{n}: {threads} threads");
                // The last row must be needed: no row past n.
                assert!(
                    (x as u64 * (y as u64 - 1) * size as u64) < n as u64,
                    "{n}: a spare row"
                );
            }
        }
    }
}
