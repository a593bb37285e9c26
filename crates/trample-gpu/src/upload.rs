//! Uploads recorded into a command encoder (issue 14 item 4: `step`
//! records into the host's encoder). `Queue::write_buffer` lands before the
//! next submission runs, so several sub-steps recorded into one encoder
//! cannot each write the same uniform through the queue: the last write
//! would win for all. Here each upload is written through the queue into
//! its own slice of a staging buffer, and a copy from that slice into the
//! destination is recorded in the encoder, in order with the passes.
//!
//! The staging slices are reused from the start at every
//! [`Uploads::begin`]: record one step per submission (submit the encoder
//! before recording the next step).

/// Alignment of each slice (`wgpu::COPY_BUFFER_ALIGNMENT` is 4).
const ALIGN: u64 = 16;

/// A staging buffer and the next free byte of it.
#[derive(Default)]
pub struct Uploads {
    buffer: Option<wgpu::Buffer>,
    next: u64,
}

impl Uploads {
    /// An empty set of uploads (the staging buffer is made when needed).
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Starts a step: the slices are used from the start again, and the
    /// staging buffer is made to hold at least `bytes` (the step's uploads).
    pub fn begin(&mut self, device: &wgpu::Device, bytes: u64) {
        self.next = 0;
        if self.buffer.as_ref().is_none_or(|b| b.size() < bytes) {
            self.buffer = Some(staging(device, bytes.max(ALIGN)));
        }
    }

    /// Writes `data` (a multiple of 4 bytes) into `dst` at `offset` at this
    /// point of `encoder`'s commands: through `queue` into a slice of the
    /// staging buffer, then a copy recorded in `encoder`. A full staging
    /// buffer is replaced by a larger one (copies already recorded keep the
    /// old one alive).
    pub fn upload(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        dst: &wgpu::Buffer,
        offset: u64,
        data: &[u8],
    ) {
        let len = data.len() as u64;
        if len == 0 {
            return;
        }
        let room = self.buffer.as_ref().map_or(0, wgpu::Buffer::size);
        if self.next + len > room {
            self.buffer = Some(staging(device, (2 * room).max(len).max(ALIGN)));
            self.next = 0;
        }
        let Some(buffer) = &self.buffer else {
            return;
        };
        queue.write_buffer(buffer, self.next, data);
        encoder.copy_buffer_to_buffer(buffer, self.next, dst, offset, len);
        self.next += len.div_ceil(ALIGN) * ALIGN;
    }
}

fn staging(device: &wgpu::Device, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("trample-gpu uploads"),
        size: size.div_ceil(ALIGN) * ALIGN,
        usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
