//! Uploads recorded into a command encoder (issue 14 item 4: `step`
//! records into the host's encoder). `Queue::write_buffer` lands before the
//! next submission runs, so several sub-steps recorded into one encoder
//! cannot each write the same uniform through the queue: the last write
//! would win for all. Here each upload is written through the queue into
//! its own slice of a staging buffer, and a copy from that slice into the
//! destination is recorded in the encoder, in order with the passes.
//!
//! The slices' bytes are gathered on the host and written with one
//! `Queue::write_buffer` ([`Uploads::flush`]) before the encoder holding
//! their copies is submitted: each `write_buffer` is a staging allocation
//! and a copy of its own in the driver, and a step makes a dozen uploads
//! or more (parameters, roots, object tables, broad-phase rectangles,
//! every sub-step).
//!
//! The staging slices are reused from the start at every
//! [`Uploads::begin`]: record one step per submission (submit the encoder
//! before recording the next step), and flush before submitting.

/// Alignment of each slice (`wgpu::COPY_BUFFER_ALIGNMENT` is 4).
const ALIGN: u64 = 16;

/// A staging buffer, the next free byte of it, and the bytes of the
/// slices not written to it yet.
#[derive(Default)]
pub struct Uploads {
    buffer: Option<wgpu::Buffer>,
    next: u64,
    /// The bytes of the slices from `pending_at` up to `next`, waiting for
    /// [`Uploads::flush`].
    pending: Vec<u8>,
    pending_at: u64,
    /// The queue the uploads go through (the one given to
    /// [`Uploads::upload`]), kept to flush on drop.
    queue: Option<wgpu::Queue>,
    /// Each slice written as it is recorded ([`Uploads::write_at_once`]).
    at_once: bool,
}

impl Uploads {
    /// An empty set of uploads (the staging buffer is made when needed).
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Starts a step: the slices are used from the start again, and the
    /// staging buffer is made to hold at least `bytes` (the step's uploads).
    /// Flushes what the last step left unwritten first.
    pub fn begin(&mut self, device: &wgpu::Device, bytes: u64) {
        self.flush();
        self.next = 0;
        if self.buffer.as_ref().is_none_or(|b| b.size() < bytes) {
            self.buffer = Some(staging(device, bytes.max(ALIGN)));
        }
    }

    /// With `on`, each upload is written to the staging buffer as it is
    /// recorded (one `Queue::write_buffer` each), for a caller that submits
    /// partial encoders between uploads without flushing (the wall-time
    /// profiling's laps: [`crate::StageTiming::Wall`]).
    pub fn write_at_once(&mut self, on: bool) {
        self.flush();
        self.at_once = on;
    }

    /// Writes `data` (a multiple of 4 bytes) into `dst` at `offset` at this
    /// point of `encoder`'s commands: into a slice of the staging buffer
    /// (held on the host until [`Uploads::flush`]), then a copy recorded in
    /// `encoder`. A full staging buffer is flushed and replaced by a larger
    /// one (copies already recorded keep the old one alive).
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
        if self.queue.is_none() {
            self.queue = Some(queue.clone());
        }
        let room = self.buffer.as_ref().map_or(0, wgpu::Buffer::size);
        if self.next + len > room {
            self.flush();
            self.buffer = Some(staging(device, (2 * room).max(len).max(ALIGN)));
            self.next = 0;
        }
        let Some(buffer) = &self.buffer else {
            return;
        };
        if self.pending.is_empty() {
            self.pending_at = self.next;
        }
        let padded = len.div_ceil(ALIGN) * ALIGN;
        self.pending.extend_from_slice(data);
        self.pending
            .resize(self.pending.len() + (padded - len) as usize, 0);
        encoder.copy_buffer_to_buffer(buffer, self.next, dst, offset, len);
        self.next += padded;
        if self.at_once {
            self.flush();
        }
    }

    /// Writes the slices recorded since the last flush into the staging
    /// buffer (one `Queue::write_buffer`, which lands before the next
    /// submission): call it before submitting the encoder their copies are
    /// in. Dropping the uploads flushes too.
    pub fn flush(&mut self) {
        if self.pending.is_empty() {
            return;
        }
        if let (Some(buffer), Some(queue)) = (&self.buffer, &self.queue) {
            queue.write_buffer(buffer, self.pending_at, &self.pending);
        }
        self.pending.clear();
    }
}

impl Drop for Uploads {
    fn drop(&mut self) {
        self.flush();
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
