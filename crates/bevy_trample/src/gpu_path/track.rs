//! The track on the ground on the GPU path: the cells' flatness
//! (`Cells::flatness`, which the ground's texture shows,
//! [`crate::render::ground`]) copied back from the GPU without waiting for
//! it. Each step's encoder copies the GPU's flatness into one of two
//! staging buffers and asks to map it; a later step (or frame) takes the
//! ones mapped since, oldest first, writes the cells that changed into
//! [`TrampleField::sim`] and marks them for the ground, as the CPU path's
//! steps do. The ground follows a frame or two behind the grass.
//!
//! A field of more than [`CELLS_A_COPY`] cells is copied back every so many
//! steps (one every `cells / CELLS_A_COPY`, rounded up), so that the copies
//! stay about 4 MiB a step.

use crate::field::TrampleField;
use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};
use trample_gpu::wgpu;

/// Cells copied back each step at most, on average (4 bytes each).
pub const CELLS_A_COPY: u64 = 1 << 20;

/// A staging buffer's state, set by its map callback.
const MAPPING: u8 = 0;
const MAPPED: u8 = 1;
const FAILED: u8 = 2;

/// One staging buffer and the copy in it.
struct Staging {
    buffer: wgpu::Buffer,
    /// Set while a copy is in it: its step number and map state.
    copy: Option<(u64, Arc<AtomicU8>)>,
}

/// The flatness read back from the GPU path, two staging buffers deep.
pub struct TrackReadback {
    staging: [Staging; 2],
    /// Steps recorded so far.
    steps: u64,
    /// The newest step whose flatness was taken.
    taken: Option<u64>,
    /// Copy every this many steps.
    every: u64,
}

impl TrackReadback {
    /// Staging for a field of `cells` cells.
    pub fn new(device: &wgpu::Device, cells: u64) -> Self {
        let staging = || Staging {
            buffer: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("bevy_trample flatness read-back"),
                size: (cells * 4).max(4),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            copy: None,
        };
        Self {
            staging: [staging(), staging()],
            steps: 0,
            taken: None,
            every: cells.div_ceil(CELLS_A_COPY).max(1),
        }
    }

    /// Records into the step's `encoder` a copy of the GPU's `flatness`
    /// into a free staging buffer, when one is free and this step is one
    /// to copy; returns which, to map once the encoder is submitted.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        flatness: &wgpu::Buffer,
    ) -> Option<usize> {
        self.steps += 1;
        if !self.steps.is_multiple_of(self.every) {
            return None;
        }
        let k = self.staging.iter().position(|s| s.copy.is_none())?;
        let s = &mut self.staging[k];
        let size = s.buffer.size().min(flatness.size());
        encoder.copy_buffer_to_buffer(flatness, 0, &s.buffer, 0, size);
        s.copy = Some((self.steps, Arc::new(AtomicU8::new(MAPPING))));
        Some(k)
    }

    /// Asks to map staging buffer `k` (after its copy was submitted).
    pub fn map(&self, k: usize) {
        let s = &self.staging[k];
        if let Some((_, state)) = &s.copy {
            let state = state.clone();
            s.buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
                state.store(if r.is_ok() { MAPPED } else { FAILED }, Ordering::Release);
            });
        }
    }

    /// Takes the copies mapped since the last call, oldest first, into
    /// `field`: its cells' flatness, and the cells that changed marked for
    /// the ground. Does not wait for the GPU.
    pub fn take(&mut self, device: &wgpu::Device, field: &mut TrampleField) {
        let _ = device.poll(wgpu::PollType::Poll);
        let mut ready: Vec<usize> = (0..2)
            .filter(|&k| {
                self.staging[k]
                    .copy
                    .as_ref()
                    .is_some_and(|(_, s)| s.load(Ordering::Acquire) != MAPPING)
            })
            .collect();
        ready.sort_by_key(|&k| self.staging[k].copy.as_ref().map_or(0, |c| c.0));
        for k in ready {
            let Some((step, state)) = self.staging[k].copy.take() else {
                continue;
            };
            if state.load(Ordering::Acquire) != MAPPED {
                continue;
            }
            let buffer = &self.staging[k].buffer;
            if self.taken.is_none_or(|t| step > t) {
                let view = buffer.slice(..).get_mapped_range();
                let flatness: &[f32] = bytemuck::cast_slice(&view);
                let cells = &mut field.sim.field.cells.flatness;
                for (c, (&now, was)) in flatness.iter().zip(cells.iter_mut()).enumerate() {
                    if now.to_bits() != was.to_bits() {
                        *was = now;
                        field.cell_changes.mark(c);
                    }
                }
                self.taken = Some(step);
            }
            buffer.unmap();
        }
    }
}
