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
        let view = staging
            .slice(..)
            .get_mapped_range()
            .mapped()
            .map_err(fail)?;
        bytemuck::cast_slice::<u8, T>(&view).to_vec()
    };
    staging.unmap();
    Ok(out)
}

/// `BufferSlice::get_mapped_range`'s answer as a `Result`, whichever wgpu
/// this crate is built against: wgpu 30 returns a `Result`, wgpu 29 (the
/// one Bevy 0.19 renders with, for which `trample-gpu-wgpu29` builds these
/// same sources) the view itself.
trait Mapped {
    /// The mapped view, or why it could not be had.
    fn mapped(self) -> Result<wgpu::BufferView, String>;
}

impl Mapped for wgpu::BufferView {
    fn mapped(self) -> Result<wgpu::BufferView, String> {
        Ok(self)
    }
}

impl<E: std::fmt::Display> Mapped for Result<wgpu::BufferView, E> {
    fn mapped(self) -> Result<wgpu::BufferView, String> {
        self.map_err(|e| e.to_string())
    }
}
