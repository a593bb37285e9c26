//! Per-stage GPU times without timestamp queries: in profiling mode each
//! stage is submitted on its own and waited for, and the wall time of that
//! wait is the stage's. This serialises the step (slower, and each time
//! includes one submission), but works on every adapter, the software ones
//! included. Timestamp queries (`wgpu::Features::TIMESTAMP_QUERY`) are not
//! used yet.

use std::time::Instant;

/// Splits a sub-step's command stream at stage boundaries when profiling.
pub(crate) struct Laps {
    profiling: bool,
    clock: Instant,
}

impl Laps {
    pub(crate) fn new(profiling: bool) -> Self {
        Self {
            profiling,
            clock: Instant::now(),
        }
    }

    /// When profiling: submits what `encoder` holds, waits for the GPU,
    /// adds the time since the last lap to `into` (ms) and gives `encoder`
    /// a fresh encoder. Otherwise nothing.
    pub(crate) fn lap(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        into: &mut f64,
    ) {
        if !self.profiling {
            return;
        }
        let done = std::mem::replace(encoder, new_encoder(device));
        queue.submit([done.finish()]);
        // A failed wait (device lost) shows up in the next read-back.
        let _ = device.poll(wgpu::PollType::wait_indefinitely());
        *into += self.clock.elapsed().as_secs_f64() * 1e3;
        self.clock = Instant::now();
    }
}

/// A command encoder for one sub-step.
pub(crate) fn new_encoder(device: &wgpu::Device) -> wgpu::CommandEncoder {
    device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("trample-gpu sub-step"),
    })
}
