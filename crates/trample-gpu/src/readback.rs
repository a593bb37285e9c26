//! Copying a GPU buffer back to the CPU (tests, dumps; never per frame).

use bytemuck::Pod;

use crate::error::GpuError;

/// Copies `buffer` (which needs `COPY_SRC`) into a staging buffer, waits, and
/// returns its contents as `T`s.
///
/// # Errors
/// [`GpuError::ReadBack`] when the map or the wait fails (device lost).
pub fn read_buffer<T: Pod>(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
    what: &'static str,
) -> Result<Vec<T>, GpuError> {
    let size = buffer.size();
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("trample-gpu read-back"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("trample-gpu read-back"),
    });
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
    queue.submit([encoder.finish()]);
    let (tx, rx) = std::sync::mpsc::channel();
    staging
        .slice(..)
        .map_async(wgpu::MapMode::Read, move |r| drop(tx.send(r)));
    let fail = |why: String| GpuError::ReadBack { what, why };
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| fail(e.to_string()))?;
    rx.recv()
        .map_err(|e| fail(e.to_string()))?
        .map_err(|e| fail(e.to_string()))?;
    let out = {
        let view = staging.slice(..).get_mapped_range();
        bytemuck::cast_slice::<u8, T>(&view).to_vec()
    };
    staging.unmap();
    Ok(out)
}
