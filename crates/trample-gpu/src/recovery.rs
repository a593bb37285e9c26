//! Recovery on the GPU (ours, DESIGN §6): dispatches `recovery.wgsl` over
//! the displaced blades of the active patches that may hold one
//! ([`crate::active_patches`]), listed first ([`crate::active_list`];
//! every blade without a broad phase); displaced ones relax towards rest as
//! `trample::step::recover` does (`recovery::recover_blade`, with each
//! blade's track owner's settings and not while an object holds it), and
//! are counted. Billboard slopes recover in `slopes.wgsl` (the paper's
//! mode) or follow their blades (`follow.wgsl`).

use crate::active_list::{ActiveList, Listed};
use crate::broad_phase::{BroadPhase, NoBroad};
use crate::field::GpuField;
use crate::kernel::{Kernel, Slot};
use trample::recovery::RecoveryParams;

/// The WGSL source as compiled (`blade.wgsl`, `guard.wgsl`, `chunk.wgsl`
/// and `broad_params.wgsl` prepended).
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}\n{}\n{}\n{}",
        crate::BLADE_WGSL,
        crate::GUARD_WGSL,
        crate::CHUNK_WGSL,
        include_str!("broad_params.wgsl"),
        include_str!("recovery.wgsl")
    )
}

/// Track owners a recovery table holds (`Simulation::track_owner` is a `u8`).
pub const OWNERS: usize = 256;

/// The compiled recovery kernel, the list of its blades and the table of
/// the track owners' recovery settings.
pub struct Recovery {
    kernel: Kernel,
    list: ActiveList,
    owners: wgpu::Buffer,
    /// Per patch: this step's recovery time as a multiple of `h`
    /// (`Simulation::recovery_scale`), read when far patches take turns.
    turns: wgpu::Buffer,
    /// Slow blades in strides (`SimParams::recovery_stride_m`): per blade,
    /// the recovery time it owes and the time it waits for, seconds
    /// (`trample::step::Scratch::recover_clock`); 16 bytes
    /// while no stride is asked for ([`Recovery::ensure_clock`]).
    clock: wgpu::Buffer,
    no_broad: NoBroad,
    /// The owner table as last written to `owners` (none yet: empty): a
    /// step whose table is the same writes nothing
    /// ([`Recovery::write_owner_table`]).
    written: Vec<[f32; 4]>,
}

impl Recovery {
    /// Compiles the kernel on `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Self {
        use Slot::{Read, ReadWrite, Uniform};
        Self {
            kernel: Kernel::new(
                device,
                "trample-gpu recovery",
                &source(),
                &[
                    Uniform, ReadWrite, ReadWrite, Read, ReadWrite, Uniform, Read, Read, Read,
                    Uniform, Uniform, ReadWrite, Read, ReadWrite, Read,
                ],
                &["recover", "recover_listed"],
            ),
            list: ActiveList::new(device),
            no_broad: NoBroad::new(device),
            turns: turns_buffer(device, 16),
            clock: clock_buffer(device, 0),
            owners: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu track owners"),
                size: (OWNERS * 16) as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            written: Vec::new(),
        }
    }

    /// Writes the recovery settings of every track owner of `sim`
    /// (`Simulation::recovery_params`: 0 for `[sim]`, 1 + i for body i).
    /// Returns whether any owner recovers.
    pub fn write_owners(&mut self, queue: &wgpu::Queue, sim: &trample::Simulation) -> bool {
        let count = (1 + sim.bodies.len()).min(OWNERS);
        let table: Vec<RecoveryParams> = (0..count).map(|o| sim.recovery_params(o as u8)).collect();
        self.write_owner_table(queue, &table)
    }

    /// Writes `table[o]` as the recovery settings of track owner `o`
    /// (owners past the table, up to [`OWNERS`], take `table[0]`'s: a body
    /// removed since). Returns whether any entry recovers (a finite
    /// `recovery_s`). The table changes only when bodies come and go or
    /// their track settings change, so one equal to the last written is
    /// not written again (a `queue.write_buffer` and its staging copy every
    /// step were 9 % of the default scene's recording on lavapipe:
    /// BENCHMARKS.md, "Session 45").
    pub fn write_owner_table(&mut self, queue: &wgpu::Queue, table: &[RecoveryParams]) -> bool {
        let row = |p: &RecoveryParams| {
            let finite = p.recovery_s.is_finite();
            [if finite { p.recovery_s } else { 0.0 }, p.trail, 0.0, 0.0]
        };
        let fallback = table.first().map_or([0.0; 4], row);
        let rows = (0..OWNERS).map(|o| table.get(o).map_or(fallback, row));
        if self.written.len() != OWNERS || !rows.clone().eq(self.written.iter().copied()) {
            self.written.clear();
            self.written.extend(rows);
            queue.write_buffer(&self.owners, 0, bytemuck::cast_slice(&self.written));
        }
        table.iter().any(|p| p.recovery_s.is_finite())
    }

    /// Writes this step's recovery time of every patch
    /// (`Simulation::recovery_scale`: far patches in turns) at this point of
    /// `encoder`'s commands, before the step's recovery is recorded.
    /// When patches take turns the step uniform says so (`b.w` = 2,
    /// `recovery.wgsl`); nothing is written when they do not (`None`).
    pub fn write_turns(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        uploads: &mut crate::upload::Uploads,
        encoder: &mut wgpu::CommandEncoder,
        scale: Option<&[f32]>,
    ) {
        let Some(scale) = scale else {
            return;
        };
        let bytes = std::mem::size_of_val(scale) as u64;
        if self.turns.size() < bytes {
            self.turns = turns_buffer(device, bytes);
        }
        uploads.upload(
            device,
            queue,
            encoder,
            &self.turns,
            0,
            bytemuck::cast_slice(scale),
        );
    }

    /// Makes room for the strides' clock of `blades` blades when `strides`
    /// (`SimParams::recovery_stride_m` > 0). A new clock is zero: every
    /// displaced blade recovers at its next step, as after
    /// `trample::Simulation::rescan_displaced`.
    pub fn ensure_clock(&mut self, device: &wgpu::Device, blades: u32, strides: bool) {
        if strides && self.clock.size() < u64::from(blades) * 8 {
            self.clock = clock_buffer(device, blades);
        }
    }

    /// Records the recovery of every displaced blade, per chunk: over the
    /// displaced blades of `broad`'s active recover lists (the active
    /// patches' `record_lists` recorded before in the sub-step, told that
    /// recovery runs), listed first (three dispatches), or every blade
    /// without (one).
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        params: &wgpu::Buffer,
        state: &wgpu::Buffer,
        broad: Option<&BroadPhase>,
    ) {
        let (broad_params, lists) = self.no_broad.or(broad);
        for (c, chunk) in field.chunks.iter().enumerate() {
            let group = self.kernel.bind(
                device,
                &[
                    params,
                    state,
                    &chunk.pos,
                    &chunk.rest,
                    &field.displaced,
                    &chunk.uniform,
                    &field.ground,
                    &field.force,
                    &field.class,
                    &self.owners,
                    broad_params,
                    lists,
                    &self.turns,
                    &self.clock,
                    &field.near_blades,
                ],
            );
            self.list.record(
                device,
                encoder,
                field,
                c,
                broad,
                Listed::Displaced,
                (&self.kernel, &group),
                chunk.groups,
            );
        }
    }
}

/// The strides' clock of `blades` blades (8 bytes each, at least 16 bytes), zero.
fn clock_buffer(device: &wgpu::Device, blades: u32) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("trample-gpu recovery clock"),
        size: (u64::from(blades) * 8).max(16),
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    })
}

/// The per-patch turns table, `bytes` long (at least 16).
fn turns_buffer(device: &wgpu::Device, bytes: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("trample-gpu recovery turns"),
        size: bytes.max(16).div_ceil(16) * 16,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
