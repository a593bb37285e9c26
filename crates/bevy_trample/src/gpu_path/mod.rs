//! The field stepped on the GPU path (feature `gpu`, DESIGN §7 and §11):
//! trample's GPU path (`trample-gpu`'s sources, built against Bevy's wgpu
//! by `trample-gpu-wgpu29`) on Bevy's own device and queue, the draws
//! reading its buffers in place (blade vertices, and instance lists and
//! indirect draws the GPU builds), so the blades never travel back to the
//! CPU; the cells' flatness does, for the track on the ground ([`track`]).
//!
//! Bevy puts its [`RenderDevice`] and [`RenderQueue`] in the main world as
//! well as the render world, so the step stays where it is on the CPU path
//! (`FixedUpdate`, [`crate::step::step_field`]): the bodies are posed on
//! [`TrampleField::sim`] as before (its CPU side: bodies, poses, time,
//! culling, levels' distances), and the step is recorded into one command
//! encoder with the draw lists and submitted on Bevy's queue. Submissions
//! run in order on the GPU, so the render world's draws see whole steps.
//!
//! Until Bevy's device exists (it is made asynchronously at start-up, and
//! never in an app without a renderer) the field steps on the CPU path; the
//! first step with a device hands the simulation over as it is (the GPU
//! path takes a simulation mid-run). A field the GPU path cannot take
//! (the device's limits, [`GpuSimulation::supports`]) stays on the CPU
//! path, and [`TrampleField::gpu_refused`] says why (logged once). A field
//! whose blade vertices pass one storage binding is in chunks of patches,
//! drawn one indirect draw a chunk.

pub mod track;

use crate::field::TrampleField;
use crate::render::extract::WIDTH_OVER_CELL;
use crate::render::look::GrassLook;
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy::render::renderer::{RenderDevice, RenderQueue};
use trample::{Simulation, StepTimings};
use trample_gpu::draw_lists::GpuDrawParams;
use trample_gpu::{GpuSimulation, wgpu};

/// The main world's handles to Bevy's device and queue (absent until the
/// renderer has made them) and the grass's look (the draw lists' drawn
/// copies and near blend band).
#[derive(SystemParam)]
pub struct GpuContext<'w> {
    device: Option<Res<'w, RenderDevice>>,
    queue: Option<Res<'w, RenderQueue>>,
    look: Option<Res<'w, GrassLook>>,
}

impl GpuContext<'_> {
    /// Bevy's device and queue, once made.
    fn handles(&self) -> Option<(&wgpu::Device, &wgpu::Queue)> {
        let device = self.device.as_deref()?;
        let queue = self.queue.as_deref()?;
        Some((device.wgpu_device(), &queue.0))
    }

    /// The look the draw lists are made for.
    fn look(&self) -> GrassLook {
        self.look.as_deref().copied().unwrap_or_default()
    }
}

/// A field on the GPU path.
pub struct GpuPath {
    /// The GPU simulation. Between steps its `sim` is a one-cell stand-in:
    /// the real one is [`TrampleField::sim`], lent to it for each step.
    pub(crate) gpu: GpuSimulation,
    /// Which GPU field this is (the draws make new bind groups for a new one).
    pub(crate) made: u64,
    /// The look the last draw lists were made for.
    look: Option<GrassLook>,
    /// The cells' flatness copied back for the ground's track.
    track: track::TrackReadback,
}

/// What the draws read of the GPU path this frame (wgpu handles: cloning
/// one clones a reference).
#[derive(Clone, Debug)]
pub struct GpuDrawBuffers {
    /// Which GPU field these belong to (each hand-over makes a new one).
    pub made: u64,
    /// Per chunk of patches: its blade vertices (the core's layout over
    /// the chunk's blades), its first blade and its blade count. The
    /// blades' indirect draw of chunk k is at `16 k` of `args`.
    pub chunks: Vec<(wgpu::Buffer, u32, u32)>,
    /// Blade instances, `(blade, debug colour)` pairs.
    pub instances: wgpu::Buffer,
    /// Billboard instances (48 bytes, as the CPU path's).
    pub billboards: wgpu::Buffer,
    /// Indirect draws: the blades' at 0, the billboards' at
    /// [`GpuDrawBuffers::billboard_args`].
    pub args: wgpu::Buffer,
    /// Byte offset of the billboards' indirect draw in `args`.
    pub billboard_args: u64,
}

/// How many GPU fields were made (each gets the next number).
static MADE: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

/// One step of `dt` on the GPU path when the field asks for it and can
/// take it; `None` when the CPU path is to step it (not asked, no device
/// yet, refused).
pub(crate) fn step(
    field: &mut TrampleField,
    ctx: &GpuContext,
    dt: f32,
) -> Option<Result<StepTimings, String>> {
    if !field.wants_gpu() {
        return None;
    }
    let (device, queue) = ctx.handles()?;
    if field.gpu.is_none() {
        start(field, device, queue).ok()?;
    }
    let look = ctx.look();
    let mut path = field.gpu.take()?;
    path.track.take(device, field);
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("bevy_trample step"),
    });
    std::mem::swap(&mut field.sim, &mut path.gpu.sim);
    let stepped = path.gpu.record_step(device, queue, &mut encoder, dt);
    let mut copied = None;
    if stepped.is_ok() {
        record_lists(&mut path, device, queue, &mut encoder, look);
        copied = path.track.record(&mut encoder, &path.gpu.field.flatness);
    }
    std::mem::swap(&mut field.sim, &mut path.gpu.sim);
    queue.submit([encoder.finish()]);
    if let Some(k) = copied {
        path.track.map(k);
    }
    field.gpu = Some(path);
    Some(
        stepped
            .map(|_| field.sim.timings.clone())
            .map_err(|e| e.to_string()),
    )
}

/// Hands the field to the GPU path as soon as Bevy's device is in the
/// main world (before any step, so that the first frames draw), and makes
/// the draw lists again when none were made or the look changed since
/// the last step (a paused game whose look is changed).
pub(crate) fn refresh_lists(field: &mut TrampleField, ctx: &GpuContext) {
    let Some((device, queue)) = ctx.handles() else {
        return;
    };
    if field.wants_gpu() && field.gpu.is_none() && start(field, device, queue).is_err() {
        return;
    }
    let look = ctx.look();
    let Some(mut path) = field.gpu.take() else {
        return;
    };
    path.track.take(device, field);
    if path.look == Some(look) {
        field.gpu = Some(path);
        return;
    }
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("bevy_trample draw lists"),
    });
    std::mem::swap(&mut field.sim, &mut path.gpu.sim);
    record_lists(&mut path, device, queue, &mut encoder, look);
    std::mem::swap(&mut field.sim, &mut path.gpu.sim);
    queue.submit([encoder.finish()]);
    field.gpu = Some(path);
}

/// Hands the field's simulation to the GPU path; on a refusal it stays on
/// the CPU path and [`TrampleField::gpu_refused`] says why.
fn start(field: &mut TrampleField, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<(), ()> {
    let refuse = |field: &mut TrampleField, why: String| {
        warn!("bevy_trample: the field stays on the CPU path: {why}");
        field.gpu_refused = Some(why);
    };
    let Some(stand_in) = stand_in() else {
        refuse(
            field,
            "the one-cell stand-in simulation could not be built".into(),
        );
        return Err(());
    };
    let sim = std::mem::replace(&mut field.sim, stand_in);
    match GpuSimulation::try_new(device, queue, sim) {
        Ok(mut gpu) => {
            // The real simulation back to the field, the stand-in to the GPU's.
            std::mem::swap(&mut field.sim, &mut gpu.sim);
            if let Err(e) = gpu.supports_draw_lists(device) {
                refuse(field, e.to_string());
                return Err(());
            }
            info!(
                "bevy_trample: the field ({} blades) steps on the GPU path from simulated time {:.3} s",
                field.sim.field.blades.count, field.sim.time
            );
            let track = track::TrackReadback::new(device, u64::from(gpu.field.cell_count));
            field.gpu = Some(GpuPath {
                gpu,
                made: MADE.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
                look: None,
                track,
            });
            Ok(())
        }
        Err((e, sim)) => {
            field.sim = *sim;
            refuse(field, e.to_string());
            Err(())
        }
    }
}

/// The smallest simulation (one cell, no bodies): what the GPU simulation
/// holds between steps while the real one is [`TrampleField::sim`].
fn stand_in() -> Option<Simulation> {
    let text = "[field]\npatches = [1, 1]\ncells_per_patch = 1\n";
    trample::scene::Scene::parse(text, "bevy_trample stand-in", std::path::Path::new("."))
        .ok()?
        .build()
        .ok()
}

/// Records the draw lists of the state the step left (or of the state as
/// it is), made for `look`.
fn record_lists(
    path: &mut GpuPath,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    encoder: &mut wgpu::CommandEncoder,
    look: GrassLook,
) {
    let params = draw_params(&path.gpu.sim, &look);
    path.gpu.record_draw_lists(device, queue, encoder, params);
    path.look = Some(look);
}

/// The draw lists' parameters for `sim` drawn with `look`, as the CPU
/// path's draws list them ([`crate::render::extract`]): blades of
/// `6 · segments` vertices (two triangles a segment), billboards of 12
/// (two crossed quads) `WIDTH_OVER_CELL` cells wide, the drawn copies of
/// each blade, and the near blend band's Billboard-LOD cells listing their
/// blades too. No debug colours.
#[must_use]
pub fn draw_params(sim: &Simulation, look: &GrassLook) -> GpuDrawParams {
    let [near_band, _] = sim.lod.blend_bands(look.lod_blend_m, look.texture_blend_m);
    GpuDrawParams {
        counts: [0; 4],
        draw: [6 * sim.field.blades.segments as u32, 12, 0, 0],
        size: [
            0.5 * WIDTH_OVER_CELL * sim.field.layout.cell_size,
            look.copies() as f32,
            near_band,
            0.0,
        ],
        palette: [0; 4],
        pbg: [0.0; 4],
    }
}

impl TrampleField {
    /// What the draws read of the GPU path, when the field is on it and
    /// its draw lists were made.
    #[must_use]
    pub fn gpu_draw_buffers(&self) -> Option<GpuDrawBuffers> {
        let path = self.gpu.as_ref()?;
        let lists = path.gpu.draw_lists()?;
        Some(GpuDrawBuffers {
            made: path.made,
            chunks: path
                .gpu
                .field
                .chunks
                .iter()
                .map(|c| (c.pos.clone(), c.first_blade, c.blades))
                .collect(),
            instances: lists.blade_instances.clone(),
            billboards: lists.billboards.clone(),
            args: lists.args.clone(),
            billboard_args: trample_gpu::draw_lists::DRAW_ARGS_BYTES
                * path.gpu.field.chunks.len() as u64,
        })
    }

    /// Copies the GPU path's state into [`TrampleField::sim`] (blade
    /// positions, classes, cells' levels, slopes and flatness, the step's
    /// counters), as the CPU path would have left it: for a save, a test
    /// or a dump, not every frame (it waits for the GPU). Nothing to do on
    /// the CPU path.
    ///
    /// # Errors
    /// The GPU path's read-back error (a lost device).
    pub fn read_back_gpu(
        &mut self,
        device: &RenderDevice,
        queue: &RenderQueue,
    ) -> Result<(), crate::TrampleError> {
        let Some(path) = self.gpu.as_mut() else {
            return Ok(());
        };
        std::mem::swap(&mut self.sim, &mut path.gpu.sim);
        let read = path.gpu.sync_to_cpu(device.wgpu_device(), &queue.0);
        std::mem::swap(&mut self.sim, &mut path.gpu.sim);
        read.map_err(|e| crate::TrampleError::Gpu(e.to_string()))
    }
}
