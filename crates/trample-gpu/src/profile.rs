//! Per-stage GPU times for `sim.timings` (issue 4, item 4), in one of two
//! ways, chosen by what the device has ([`StageTiming`]):
//!
//! - **timestamp queries**, on a device created with [`TIMESTAMP_FEATURES`]:
//!   a timestamp is written into the command stream at the start of each
//!   sub-step and after each stage (between passes,
//!   `CommandEncoder::write_timestamp`), the sub-steps are submitted as
//!   usual (one submission each, nothing waited for between stages), and
//!   the timestamps of the whole step are resolved and read back once, at
//!   its end (more than [`MAX_QUERIES`] of them: once per that many).
//!   A stage's time is the difference of the timestamps around it, in
//!   nanoseconds times `Queue::get_timestamp_period`. What a timestamp
//!   means is the driver's: wgpu notes that it may not be strictly after
//!   all earlier commands on every backend.
//! - **wall time**, otherwise: each stage is submitted on its own and waited
//!   for, and the wall time of that wait is the stage's. This serialises the
//!   step (slower, and each time includes one submission), but works on
//!   every adapter.
//!
//! Inside the crate, `Laps` marks the stage boundaries of one sub-step for
//! either way, and `StageTimer::finish_step` writes the sums over the
//! step's sub-steps into `StepTimings`.

use std::time::Instant;

use trample::StepTimings;

use crate::error::GpuError;
use crate::readback::read_buffer;

/// The device features the timestamp way needs: timestamp queries, written
/// between passes of a command encoder. Request them (where the adapter
/// offers them) when creating a device for profiling; without them the
/// profiling mode measures wall time.
pub const TIMESTAMP_FEATURES: wgpu::Features =
    wgpu::Features::TIMESTAMP_QUERY.union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);

/// Timestamps resolved and read back at once, at most: wgpu's limit on a
/// query set (`QUERY_SET_MAX_QUERIES`). A step whose sub-steps need more
/// (7 a sub-step: over 585 sub-steps) is read back once per this many.
pub const MAX_QUERIES: u32 = wgpu::QUERY_SET_MAX_QUERIES;

/// Timestamps one sub-step writes at most: its start and one after each
/// lap (`GpuSimulation::step` laps ten times: deformation thrice, around
/// the contact response and the billboards).
const PER_SUBSTEP: u32 = 12;

/// How the profiling mode measures stage times (see the module docs), as
/// `summary.json` names it ([`StageTiming::name`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StageTiming {
    /// Timestamp queries in the command stream, read back once per step.
    Timestamp,
    /// Each stage submitted and waited for; the wall time of the wait.
    Wall,
}

impl StageTiming {
    /// `"timestamp"` or `"wall"`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Timestamp => "timestamp",
            Self::Wall => "wall",
        }
    }

    /// The way `device` allows: [`StageTiming::Timestamp`] when it was
    /// created with [`TIMESTAMP_FEATURES`], else [`StageTiming::Wall`].
    #[must_use]
    pub fn for_device(device: &wgpu::Device) -> Self {
        if device.features().contains(TIMESTAMP_FEATURES) {
            Self::Timestamp
        } else {
            Self::Wall
        }
    }
}

/// The stages of a GPU sub-step, as `StepTimings` names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stage {
    /// `lod_ms`: counter reset and LOD per cell.
    Lod,
    /// `broad_ms`: the broad phase's patch lists.
    Broad,
    /// `narrow_ms`: narrow phase with EqF, every object.
    Narrow,
    /// `propagation_ms`: the generation passes.
    Propagation,
    /// `deformation_ms`: blades and billboards.
    Deformation,
    /// `contact_ms`: the contact response.
    Contact,
    /// `transitions_ms`.
    Transitions,
    /// `recovery_ms`: blades and billboard slopes.
    Recovery,
}

const STAGES: usize = 8;

fn field(t: &mut StepTimings, stage: Stage) -> &mut f64 {
    match stage {
        Stage::Lod => &mut t.lod_ms,
        Stage::Broad => &mut t.broad_ms,
        Stage::Narrow => &mut t.narrow_ms,
        Stage::Propagation => &mut t.propagation_ms,
        Stage::Deformation => &mut t.deformation_ms,
        Stage::Contact => &mut t.contact_ms,
        Stage::Transitions => &mut t.transitions_ms,
        Stage::Recovery => &mut t.recovery_ms,
    }
}

/// The query set and its buffers, grown on demand up to [`MAX_QUERIES`].
struct Queries {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    capacity: u32,
}

impl Queries {
    fn new(device: &wgpu::Device, capacity: u32) -> Self {
        Self {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("trample-gpu stage timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: capacity,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu stage timestamps"),
                size: u64::from(capacity) * u64::from(wgpu::QUERY_SIZE),
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            capacity,
        }
    }
}

/// Stage times of the current step. One per `GpuSimulation`.
pub(crate) struct StageTimer {
    method: StageTiming,
    queries: Option<Queries>,
    /// Per timestamp written this round: the stage it ends, `None` for the
    /// start of a sub-step.
    written: Vec<Option<Stage>>,
    /// Sums over the step so far, ms, indexed by `Stage as usize`.
    sums: [f64; STAGES],
}

impl StageTimer {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        Self {
            method: StageTiming::for_device(device),
            queries: None,
            written: Vec::new(),
            sums: [0.0; STAGES],
        }
    }

    pub(crate) fn method(&self) -> StageTiming {
        self.method
    }

    /// Starts a step of `substeps` sub-steps: clears the sums and, for
    /// timestamps, makes room for the step's queries (up to [`MAX_QUERIES`]).
    pub(crate) fn begin_step(&mut self, device: &wgpu::Device, profiling: bool, substeps: u32) {
        self.sums = [0.0; STAGES];
        self.written.clear();
        if !profiling || self.method != StageTiming::Timestamp {
            return;
        }
        let wanted = substeps
            .saturating_mul(PER_SUBSTEP)
            .clamp(PER_SUBSTEP, MAX_QUERIES);
        if self.queries.as_ref().is_none_or(|q| q.capacity < wanted) {
            self.queries = Some(Queries::new(device, wanted));
        }
    }

    /// The laps of one sub-step recorded into `encoder` (fresh, nothing
    /// recorded yet). With timestamps and a full query set, first reads
    /// back what the earlier sub-steps wrote (they are submitted).
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when that read-back fails.
    pub(crate) fn laps(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        profiling: bool,
    ) -> Result<Laps<'_>, GpuError> {
        let stamps = profiling && self.method == StageTiming::Timestamp;
        if stamps {
            let capacity = self.queries.as_ref().map_or(0, |q| q.capacity) as usize;
            if self.written.len() + PER_SUBSTEP as usize > capacity {
                self.read_back(device, queue)?;
            }
            self.stamp(encoder, None);
        }
        Ok(Laps {
            timer: self,
            profiling,
            stamps,
            clock: Instant::now(),
        })
    }

    fn stamp(&mut self, encoder: &mut wgpu::CommandEncoder, ends: Option<Stage>) {
        if let Some(q) = &self.queries {
            let index = self.written.len() as u32;
            if index < q.capacity {
                encoder.write_timestamp(&q.set, index);
                self.written.push(ends);
            }
        }
    }

    /// Resolves and reads back the timestamps written since the last read,
    /// and adds each stage's intervals to the sums. Needs the sub-steps
    /// that wrote them submitted.
    fn read_back(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<(), GpuError> {
        let (Some(q), n) = (&self.queries, self.written.len() as u32) else {
            return Ok(());
        };
        if n == 0 {
            return Ok(());
        }
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("trample-gpu resolve timestamps"),
        });
        encoder.resolve_query_set(&q.set, 0..n, &q.resolve, 0);
        queue.submit([encoder.finish()]);
        let ticks: Vec<u64> = read_buffer(device, queue, &q.resolve, "stage timestamps")?;
        let ms_per_tick = f64::from(queue.get_timestamp_period()) * 1e-6;
        for (k, ends) in self.written.iter().enumerate().skip(1) {
            if let Some(stage) = ends {
                // Signed: a clock that runs backwards shows, it is not hidden.
                let delta = ticks[k].wrapping_sub(ticks[k - 1]) as i64;
                self.sums[*stage as usize] += delta as f64 * ms_per_tick;
            }
        }
        self.written.clear();
        Ok(())
    }

    /// Ends the step: reads back the remaining timestamps (when profiling
    /// with them) and writes the stage sums into `t`'s `lod_ms`,
    /// `broad_ms`, `narrow_ms`, `propagation_ms`, `deformation_ms`,
    /// `contact_ms`, `transitions_ms` and `recovery_ms`. Needs every sub-step submitted.
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when the read-back fails (device lost).
    pub(crate) fn finish_step(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        t: &mut StepTimings,
    ) -> Result<(), GpuError> {
        self.read_back(device, queue)?;
        for stage in [
            Stage::Lod,
            Stage::Broad,
            Stage::Narrow,
            Stage::Propagation,
            Stage::Deformation,
            Stage::Contact,
            Stage::Transitions,
            Stage::Recovery,
        ] {
            *field(t, stage) = self.sums[stage as usize];
        }
        Ok(())
    }
}

/// Marks the stage boundaries of one sub-step's command stream.
pub(crate) struct Laps<'a> {
    timer: &'a mut StageTimer,
    profiling: bool,
    stamps: bool,
    clock: Instant,
}

impl Laps<'_> {
    /// `stage` ends here. Timestamps: writes one into `encoder`. Wall time:
    /// submits what `encoder` holds, waits for the GPU, adds the time since
    /// the last lap to the stage and gives `encoder` a fresh encoder. Not
    /// profiling: nothing.
    pub(crate) fn lap(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        stage: Stage,
    ) {
        if !self.profiling {
            return;
        }
        if self.stamps {
            self.timer.stamp(encoder, Some(stage));
            return;
        }
        let done = std::mem::replace(encoder, new_encoder(device));
        queue.submit([done.finish()]);
        // A failed wait (device lost) shows up in the next read-back.
        let _ = device.poll(wgpu::PollType::wait_indefinitely());
        self.timer.sums[stage as usize] += self.clock.elapsed().as_secs_f64() * 1e3;
        self.clock = Instant::now();
    }
}

/// A command encoder for one sub-step.
pub(crate) fn new_encoder(device: &wgpu::Device) -> wgpu::CommandEncoder {
    device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("trample-gpu sub-step"),
    })
}
