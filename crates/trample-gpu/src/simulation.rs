//! `GpuSimulation::step`: the sub-steps of DESIGN §7 on the GPU, each one
//! submission of named passes in a fixed order (narrow phase + EqF per
//! object → propagation generations → bending → recovery), with no
//! read-back. The blade buffers stay on the GPU across steps.
//!
//! The wrapped [`Simulation`] supplies what is still computed on the CPU:
//! the passes and their sub-steps (`Simulation::begin_step`, shared with
//! the core) and the poses
//! (`Motion::pose_at`, a pure function of time, a few floats per object).
//! Its own blade arrays are **not** updated by [`GpuSimulation::step`]:
//! read the field back with [`GpuField::read_positions`].
//!
//! Fields over one storage binding run in chunks of patches
//! ([`crate::chunk`]); the narrow phase runs over the patches the broad
//! phase lists ([`crate::broad_phase`]); per-stage times come from
//! timestamp queries where the device has them ([`crate::profile`]).

use trample::Simulation;
use trample::deform::bend::weights;
use trample::field::generate::GROUND_CLEARANCE_M;
use trample::field::{Lod, Terrain};
use trample::force::propagation::GENERATION_CAP;
use wgpu::util::DeviceExt;

use crate::active_patches::ActivePatches;
use crate::bend::Bend;
use crate::broad_phase::BroadPhase;
use crate::cells::{Cells, GpuWorldObb};
use crate::contact::Contact;
use crate::draw_lists::{DrawLists, GpuDrawParams};
use crate::error::GpuError;
use crate::field::GpuField;
use crate::kernel::grid;
use crate::narrow_phase::NarrowPhase;
use crate::object::{GpuObjects, TableLayout};
use crate::profile::{Stage, StageTimer, StageTiming, new_encoder};
use crate::propagation::Propagation;
use crate::readback::read_buffer;
use crate::recovery::Recovery;
use crate::step_params::{GpuCounters, GpuStepParams};
use crate::track_owners::TrackOwners;

/// One collider as the object table holds it: its body, its tree (where it
/// lies, its node and triangle counts, whether it has an inside grid) and,
/// for a body whose tree is not refitted every sub-step, its root box's
/// bits, so that a mesh swapped in place (`Simulation::body_mut`) is seen.
#[derive(Clone, Debug, PartialEq, Eq)]
struct ColliderKey {
    body: trample::BodyId,
    tree: usize,
    nodes: usize,
    triangles: usize,
    grid: bool,
    root: Option<[u32; 6]>,
}

/// The object table's [`ColliderKey`]s for `sim`'s bodies now.
fn collider_keys(sim: &Simulation) -> Vec<ColliderKey> {
    sim.bodies
        .iter()
        .flat_map(|b| {
            let animated = b.deforms();
            b.colliders().map(move |c| {
                let t = c.tree;
                let root = t.nodes.first().filter(|_| !animated).map(|n| {
                    let (c, h) = (n.obb.center, n.obb.half);
                    [c.x, c.y, c.z, h.x, h.y, h.z].map(f32::to_bits)
                });
                ColliderKey {
                    body: b.id,
                    tree: std::ptr::from_ref(t) as usize,
                    nodes: t.nodes.len(),
                    triangles: t.triangles.len(),
                    grid: t.inside.is_some(),
                    root,
                }
            })
        })
        .collect()
}

/// A buffer for `colliders` world root boxes (at least one).
fn world_roots_buffer(device: &wgpu::Device, colliders: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("trample-gpu world root boxes"),
        size: (colliders.max(1) * std::mem::size_of::<GpuWorldObb>()) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A simulation whose blades live and move on the GPU.
pub struct GpuSimulation {
    /// CPU side: parameters, bodies and their poses, time, frame. Its blade
    /// arrays keep their state from creation (see the module docs).
    pub sim: Simulation,
    /// The field on the GPU: draw from the chunks' `pos` ([`GpuField::chunks`]).
    pub field: GpuField,
    objects: GpuObjects,
    /// What `objects` was made from ([`ColliderKey`], one per collider):
    /// bodies added, removed or given another mesh since make it again.
    colliders: Vec<ColliderKey>,
    /// The bodies' ids, in order, when `objects` was made (for the track
    /// owners' renumbering when bodies leave).
    body_ids: Vec<trample::BodyId>,
    /// Colliders `world_roots` has room for.
    roots_capacity: usize,
    /// Made when a body first leaves ([`TrackOwners`]).
    track_owners: Option<TrackOwners>,
    broad: BroadPhase,
    /// The patches the field-wide passes visit ([`ActivePatches`]).
    active: ActivePatches,
    /// Narrow-phase and contact dispatches recorded in the last sub-step.
    object_dispatches: u32,
    /// Per-sub-step uploads in order with the passes ([`crate::upload`]).
    uploads: crate::upload::Uploads,
    narrow: NarrowPhase,
    contact: Contact,
    propagation: Propagation,
    bend: Bend,
    recovery: Recovery,
    cells: Cells,
    world_roots: wgpu::Buffer,
    params: wgpu::Buffer,
    state: wgpu::Buffer,
    ground: f32,
    /// Profiling mode (see [`GpuSimulation::set_profiling`]).
    profiling: bool,
    /// Whether a main sub-step's viewpoint asks for the cells' levels again.
    lod_settle: crate::lod_settle::LodSettle,
    /// Made by the first [`GpuSimulation::record_draw_lists`].
    draw_lists: Option<DrawLists>,
    timer: StageTimer,
}

impl GpuSimulation {
    /// Profiling mode: each stage's GPU time goes into `sim.timings`
    /// (`lod_ms`, `broad_ms`, `narrow_ms` (with EqF), `propagation_ms`,
    /// `deformation_ms` (blades and billboards), `transitions_ms`,
    /// `recovery_ms`), measured the way [`GpuSimulation::stage_timing`]
    /// says: timestamp queries read back once per step (the step waits for
    /// the GPU at its end, and `total_ms` includes that wait), or, on a
    /// device without [`crate::TIMESTAMP_FEATURES`], each stage submitted
    /// and waited for on its own (slower). Off by default, when
    /// `sim.timings` holds only `total_ms` (recording time, the GPU runs on
    /// asynchronously), the sub-step counts and, after
    /// [`GpuSimulation::sync_to_cpu`], the counters.
    pub fn set_profiling(&mut self, on: bool) {
        self.profiling = on;
    }

    /// Narrow-phase and contact-response dispatches recorded in the last
    /// sub-step: three each per chunk of patches (the list of the blades
    /// to work on, its size, the work), however many objects (issue 16
    /// item 3; it was one each per object and chunk).
    #[must_use]
    pub fn object_dispatches(&self) -> u32 {
        self.object_dispatches
    }

    /// How the profiling mode measures stage times on this device.
    #[must_use]
    pub fn stage_timing(&self) -> StageTiming {
        self.timer.method()
    }

    /// Whether the GPU path can run `sim` on `device`: the storage buffers
    /// a shader stage of the step binds
    /// ([`crate::limits::storage_buffers_per_stage`]), the terrain's table within one binding, one patch's vertices within one storage binding (fields are split into
    /// chunks of patches), and the whole-field per-blade arrays (16 bytes a
    /// blade) within one binding. Checks before anything is allocated.
    ///
    /// # Errors
    /// [`GpuError::Unsupported`] or [`GpuError::TooLarge`], saying why.
    pub fn supports(device: &wgpu::Device, sim: &Simulation) -> Result<(), GpuError> {
        Self::supports_with(device, sim, &TableLayout::of_simulation(sim))
    }

    /// Whether `device` can also hold the draw lists
    /// ([`GpuSimulation::record_draw_lists`]) of this field: their largest
    /// binding ([`crate::draw_lists::largest_binding`]) within one storage
    /// binding. A host that draws from the GPU's buffers asks before its
    /// first lists (wgpu would fail them otherwise).
    ///
    /// # Errors
    /// [`GpuError::TooLarge`], naming the list.
    pub fn supports_draw_lists(&self, device: &wgpu::Device) -> Result<(), GpuError> {
        let (bytes, what) = crate::draw_lists::largest_binding(
            u64::from(self.field.count),
            u64::from(self.field.cell_count),
        );
        let limit = GpuField::binding_limit(device);
        if bytes > limit {
            return Err(GpuError::TooLarge { what, bytes, limit });
        }
        Ok(())
    }

    /// [`GpuSimulation::supports`] with the object table's layout already
    /// made (it is then uploaded, not made again).
    fn supports_with(
        device: &wgpu::Device,
        sim: &Simulation,
        objects: &TableLayout,
    ) -> Result<(), GpuError> {
        let needed = crate::limits::storage_buffers_per_stage(false);
        let has = device.limits().max_storage_buffers_per_shader_stage;
        if has < needed {
            return Err(GpuError::Limit(format!(
                "the step's stages bind up to {needed} storage buffers in one shader stage, \
                 the device allows {has}: create it with trample_gpu::required_limits(&sim)"
            )));
        }
        let limit = GpuField::binding_limit(device);
        let blades = &sim.field.blades;
        let (bytes, what) =
            GpuField::whole_field_binding(blades.count as u64, sim.field.cells.lod.len() as u64);
        if bytes > limit {
            return Err(GpuError::TooLarge { what, bytes, limit });
        }
        let layout = &sim.field.layout;
        let patch = layout.cells_in_patch() as u32 * layout.blades_per_cell;
        let verts = blades.segments as u32 + 1;
        crate::chunk::plan_chunks(blades.count as u32, verts, patch, limit)?;
        crate::terrain::table(
            &sim.field.terrain,
            layout,
            sim.field.max_blade_length,
            limit,
        )?;
        objects.check(device)
    }

    /// Uploads `sim`'s field and objects to `device`.
    ///
    /// # Errors
    /// As [`GpuSimulation::supports`]; [`GpuError::TooLarge`] /
    /// [`GpuError::Layout`] from the uploads.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: Simulation,
    ) -> Result<Self, GpuError> {
        Self::new_chunked(device, queue, sim, None)
    }

    /// As [`GpuSimulation::new`], each chunk of patches within
    /// `max_chunk_bytes` of positions when given (tests chunk small fields
    /// with it; by default a chunk is as large as one storage binding).
    ///
    /// # Errors
    /// As [`GpuSimulation::new`].
    pub fn new_chunked(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: Simulation,
        max_chunk_bytes: Option<u64>,
    ) -> Result<Self, GpuError> {
        Self::try_new_chunked(device, queue, sim, max_chunk_bytes).map_err(|(e, _)| e)
    }

    /// As [`GpuSimulation::new`], but a simulation the GPU path cannot take
    /// comes back with the error, unharmed, to go on on the CPU path (a
    /// host that falls back loses no work).
    ///
    /// # Errors
    /// As [`GpuSimulation::new`], with `sim`.
    pub fn try_new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: Simulation,
    ) -> Result<Self, (GpuError, Box<Simulation>)> {
        Self::try_new_chunked(device, queue, sim, None)
    }

    /// [`GpuSimulation::new_chunked`], giving `sim` back with an error.
    fn try_new_chunked(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: Simulation,
        max_chunk_bytes: Option<u64>,
    ) -> Result<Self, (GpuError, Box<Simulation>)> {
        let up = match Uploaded::new(device, queue, &sim, max_chunk_bytes) {
            Ok(up) => up,
            Err(e) => return Err((e, Box::new(sim))),
        };
        let Uploaded {
            field,
            ground,
            colliders,
            world_roots,
            broad,
            objects,
            params,
            state,
        } = up;
        Ok(Self {
            colliders: collider_keys(&sim),
            body_ids: sim.bodies.iter().map(|b| b.id).collect(),
            roots_capacity: colliders.max(1),
            track_owners: None,
            broad,
            active: ActivePatches::new(device),
            cells: Cells::new(device),
            world_roots,
            sim,
            field,
            objects,
            object_dispatches: 0,
            uploads: crate::upload::Uploads::new(),
            narrow: NarrowPhase::new(device),
            contact: Contact::new(device),
            propagation: Propagation::new(device),
            bend: Bend::new(device),
            recovery: Recovery::new(device),
            params,
            state,
            ground,
            profiling: false,
            lod_settle: crate::lod_settle::LodSettle::default(),
            draw_lists: None,
            timer: StageTimer::new(device),
        })
    }

    /// The step uniform for a sub-step of `h` seconds; `recovery_on`: some
    /// track owner recovers ([`Recovery::write_owners`]).
    fn step_params(&self, h: f32, groups_x: u32, recovery_on: bool) -> GpuStepParams {
        let p = &self.sim.params;
        let n = self.field.segments as usize;
        let w = weights(n, p.weight_a, p.weight_b);
        let mut packed = [[0.0; 4]; 4];
        for (i, wi) in w.iter().enumerate() {
            packed[i / 4][i % 4] = *wi;
        }
        let att = if p.att.is_nan() {
            0.0
        } else {
            p.att.clamp(0.0, 1.0)
        };
        let sim_recovers = p.recovery_s.is_finite();
        GpuStepParams {
            a: [h, att, p.threshold, self.ground],
            b: [
                GROUND_CLEARANCE_M,
                if sim_recovers { p.recovery_s } else { 0.0 },
                p.trail,
                if recovery_on { 1.0 } else { 0.0 },
            ],
            weights: packed,
            counts: [
                self.field.count,
                self.field.segments,
                p.max_generations.min(GENERATION_CAP),
                groups_x,
            ],
            eye: self.sim.eye().extend(self.sim.lod.geometry_m).to_array(),
            lod: [
                self.sim.lod.billboard_m,
                trample::force::propagation::THRESHOLD_FADE,
                trample::step::stages::HOLD_WEIGHT,
                0.0,
            ],
            cells: [
                self.field.cell_count,
                self.field.blades_per_cell,
                self.objects.len() as u32,
                u32::from(p.track_everywhere),
            ],
            far: [
                0,
                1,
                if p.recovery_stride_m > 0.0 {
                    p.recovery_stride_m
                } else {
                    0.0
                }
                .to_bits(),
                0,
            ],
        }
    }

    /// Advances the simulation by `dt` seconds: the same passes, sub-steps
    /// and poses as `Simulation::step` (the outer loop is the core's:
    /// `begin_step` plans the passes and their sub-steps and counts a
    /// clamp, `Pass::substep_time`, `end_step`), every stage on the GPU, one
    /// submission per sub-step, nothing read back (in profiling mode: the
    /// stage times, see [`GpuSimulation::set_profiling`]). Returns the
    /// number of sub-steps, every pass's.
    ///
    /// # Errors
    /// `dt` must be positive and finite ([`GpuError::Layout`] otherwise);
    /// [`GpuError::ReadBack`] when profiling and the timestamps cannot be
    /// read back (device lost).
    pub fn step(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        dt: f32,
    ) -> Result<u32, GpuError> {
        self.advance(device, queue, dt, Target::Submit)
    }

    /// Records the step of `dt` seconds into the host's `encoder`, all
    /// sub-steps, nothing submitted (the host submits it): the same
    /// sub-steps, poses and passes as [`GpuSimulation::step`], whose CPU
    /// side (time, frame, poses, culling) advances at once. The step's
    /// uploads (step uniform, object poses, root boxes, broad-phase
    /// rectangles) go through `queue` into a staging buffer and are copied
    /// in order with the passes ([`crate::upload`]): **submit the encoder
    /// before recording the next step.** The profiling mode does not apply
    /// (its stage times need submissions of its own): `sim.timings` holds
    /// the sub-step counts and the recording time. Returns the number of
    /// sub-steps.
    ///
    /// # Errors
    /// `dt` must be positive and finite ([`GpuError::Layout`] otherwise).
    pub fn record_step(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        dt: f32,
    ) -> Result<u32, GpuError> {
        self.advance(device, queue, dt, Target::Host(encoder))
    }

    /// The step's outer loop, shared by [`GpuSimulation::step`] (one
    /// submission per sub-step, profiling as set) and
    /// [`GpuSimulation::record_step`] (into the host's encoder).
    fn advance(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        dt: f32,
        mut target: Target<'_>,
    ) -> Result<u32, GpuError> {
        let profiling = self.profiling && matches!(target, Target::Submit);
        let start = std::time::Instant::now();
        self.follow_bodies(device, queue, &mut target)?;
        let passes = self
            .sim
            .begin_step(dt)
            .map_err(|e| GpuError::Layout(e.to_string()))?;
        self.sim.timings = trample::StepTimings::default();
        // Every pass's sub-steps (`trample::step::passes`: the main pass,
        // the near passes of faster bodies, then far bodies' passes when
        // `sim.far_every > 1`).
        let substeps: u32 = passes.iter().map(|p| p.plan.substeps).sum();
        let max = device.limits().max_compute_workgroups_per_dimension;
        let groups = grid(self.field.count, max);
        self.timer.begin_step(device, profiling, substeps);
        // Wall-time laps submit the encoder between a sub-step's uploads.
        self.uploads
            .write_at_once(profiling && self.timer.method() == StageTiming::Wall);
        let cell_groups = self.cells.bind(
            device,
            &self.field,
            &self.params,
            &self.state,
            &self.world_roots,
            &self.broad,
        );
        let recovery_on = self.recovery.write_owners(queue, &self.sim);
        let p = self.sim.params.clone();
        self.recovery
            .ensure_clock(device, self.field.count, p.recovery_stride_m > 0.0);
        // An animated body's refitted tree is uploaded every sub-step.
        let trees: u64 = self
            .sim
            .bodies
            .iter()
            .filter(|b| b.deforms())
            .map(|b| GpuObjects::tree_bytes(&b.tree))
            .sum();
        let per_substep = (std::mem::size_of::<GpuStepParams>()
            + self.objects.len() * (std::mem::size_of::<GpuWorldObb>() + 16)
            + 16) as u64
            + self.objects.params_bytes()
            + trees
            + 64;
        let turns_bytes = self
            .sim
            .recovery_scale()
            .map_or(0, |s| std::mem::size_of_val(s) as u64 + 16);
        self.uploads
            .begin(device, per_substep * u64::from(substeps) + turns_bytes);
        // Far patches' blades recover in turns this step
        // (`trample::step::recovery_turns`): the table goes up once, before
        // the main pass's first recovery.
        let in_turns = recovery_on && self.sim.recovery_scale().is_some();
        for (pass, i) in passes
            .iter()
            .flat_map(|p| (1..=p.plan.substeps).map(move |i| (p, i)))
        {
            let t = pass.substep_time(i);
            let h = pass.h();
            // Poses and the viewpoint: on the CPU (pure functions of time;
            // an animated body's skin posed and its tree refitted there).
            // One object per collider, pressing for its body; a collider
            // not in the pass is nowhere (no patch listed for it).
            let mut roots = Vec::with_capacity(self.objects.len().max(1));
            let mut obbs = Vec::with_capacity(self.objects.len());
            let mut refitted = Vec::new();
            let mut k = 0;
            for (index, body) in self.sim.bodies.iter_mut().enumerate() {
                let on = pass.has(index);
                body.pose_for_pass(t, pass.main, on);
                for c in body.colliders() {
                    if k >= self.objects.len() {
                        break;
                    }
                    if on && body.deforms() && std::ptr::eq(c.tree, &*body.tree) {
                        refitted.push((k, index));
                    }
                    let root = if on {
                        *c.world_root
                    } else {
                        nowhere(c.world_root)
                    };
                    self.objects.set_pose(k, c.pose);
                    self.objects.set_contact(
                        k,
                        h,
                        p.contact_shell_m,
                        body.object.track.press,
                        p.track_everywhere,
                    );
                    self.objects.set_owner(k, index);
                    roots.push(GpuWorldObb::new(
                        &root,
                        &self.sim.field.layout,
                        self.sim.field.max_blade_length,
                    ));
                    obbs.push(root);
                    k += 1;
                }
            }
            if pass.main {
                self.sim.update_view(t);
            }
            let mut params = self.step_params(h, groups.0, recovery_on);
            if in_turns {
                // Far patches' blades recover in turns (`recovery.wgsl`).
                params.b[3] = 2.0;
            }
            // Levels of detail (and the transitions they start) only where
            // the viewpoint or the distances changed (`lod_settle.rs`).
            let classify = pass.main && self.lod_settle.needs_classify(&params);
            if !classify {
                params.lod[3] = 1.0;
            }
            // How the sub-step's counts join the step's (the CPU's).
            params.far[0] = u32::from(!pass.main);
            params.far[1] = u32::from(pass.main && i == 1);
            let mut own = None;
            let encoder = match &mut target {
                Target::Submit => own.insert(new_encoder(device)),
                Target::Host(e) => &mut **e,
            };
            if in_turns && pass.main && i == 1 {
                self.recovery.write_turns(
                    device,
                    queue,
                    &mut self.uploads,
                    encoder,
                    self.sim.recovery_scale(),
                );
            }
            self.uploads.upload(
                device,
                queue,
                encoder,
                &self.params,
                0,
                bytemuck::bytes_of(&params),
            );
            if !roots.is_empty() {
                self.uploads.upload(
                    device,
                    queue,
                    encoder,
                    &self.world_roots,
                    0,
                    bytemuck::cast_slice(&roots),
                );
            }
            for &(k, index) in &refitted {
                self.objects.write_tree(
                    k,
                    &self.sim.bodies[index].tree,
                    device,
                    queue,
                    &mut self.uploads,
                    encoder,
                );
            }
            let mut laps = self.timer.laps(device, queue, encoder, self.profiling)?;
            self.propagation
                .record_reset(device, encoder, &self.field, &self.params, &self.state);
            if classify {
                self.cells.record_classify(encoder, &cell_groups);
            }
            laps.lap(device, queue, encoder, Stage::Lod);
            // The broad phase, with no object too (it then lists nothing),
            // and the active patches: the patches touched before and not
            // listed now tidied (once the last body has left, every one of
            // them: no force of its holds a blade any more), those near the
            // listed ones to seed.
            self.broad.record(
                device,
                queue,
                &mut self.uploads,
                encoder,
                &self.world_roots,
                &self.sim.field.layout,
                &obbs,
            );
            self.active.record_seed(device, encoder, &self.broad);
            self.propagation.record_tidy(
                device,
                encoder,
                &self.field,
                &self.params,
                &self.state,
                &self.broad,
            );
            laps.lap(device, queue, encoder, Stage::Broad);
            if !self.objects.is_empty() {
                self.object_dispatches = self.narrow.record(
                    device,
                    queue,
                    &mut self.uploads,
                    encoder,
                    &self.field,
                    &mut self.objects,
                    p.precision,
                    Some(&self.broad),
                );
                laps.lap(device, queue, encoder, Stage::Narrow);
                self.propagation.record(
                    device,
                    encoder,
                    &self.field,
                    &self.params,
                    &self.state,
                    groups,
                    params.counts[2],
                    Some(&self.broad),
                );
                laps.lap(device, queue, encoder, Stage::Propagation);
                // Bend's and recover's lists (every patch propagation
                // reached is dirty now).
                self.active
                    .record_lists(device, encoder, &self.broad, pass.main);
                self.bend.record(
                    device,
                    encoder,
                    &self.field,
                    &self.params,
                    &self.state,
                    Some(&self.broad),
                );
                laps.lap(device, queue, encoder, Stage::Deformation);
                if p.contact {
                    self.object_dispatches += self.contact.record(
                        device,
                        encoder,
                        &self.field,
                        &self.params,
                        &self.state,
                        &self.objects,
                        &self.broad,
                    );
                }
                laps.lap(device, queue, encoder, Stage::Contact);
            }
            if !p.track_everywhere {
                self.cells.record_billboards(encoder, &cell_groups);
            }
            laps.lap(device, queue, encoder, Stage::Deformation);
            if classify {
                self.cells.record_transitions(encoder, &cell_groups);
            }
            laps.lap(device, queue, encoder, Stage::Transitions);
            if pass.main {
                if self.objects.is_empty() {
                    // Recover's lists were not made above (no object:
                    // no propagation, no bend).
                    self.active.record_lists(device, encoder, &self.broad, true);
                }
                self.recovery.record(
                    device,
                    encoder,
                    &self.field,
                    &self.params,
                    &self.state,
                    Some(&self.broad),
                );
                if !p.track_everywhere {
                    self.cells.record_recover_slopes(encoder, &cell_groups);
                }
            }
            laps.lap(device, queue, encoder, Stage::Recovery);
            if p.track_everywhere {
                self.cells.record_follow(encoder, &cell_groups, &self.broad);
            }
            laps.lap(device, queue, encoder, Stage::Deformation);
            // The sub-step's uploads written before its commands are
            // submitted (here or by the host after `record_step`).
            self.uploads.flush();
            if let Some(e) = own {
                queue.submit([e.finish()]);
            }
        }
        if profiling {
            self.timer
                .finish_step(device, queue, &mut self.sim.timings)?;
        }
        self.sim.timings.visible_patches = self.sim.end_step(dt);
        let tm = &mut self.sim.timings;
        (tm.substeps, tm.substeps_needed) = trample::step::passes::near_substeps(&passes);
        tm.far_bodies = trample::step::passes::far_bodies(&passes);
        tm.total_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(substeps)
    }

    /// Follows the bodies the host added, removed or gave another mesh
    /// since the object table was made (issue 14: bodies at any time, on
    /// both paths): the table, the broad phase's room and the world root
    /// boxes made again for the colliders there are now, and, when bodies
    /// left, the blades' track owners renumbered on the GPU as the CPU's
    /// `remove_body` renumbered its own ([`TrackOwners`]). Nothing to do
    /// (one comparison a collider) when the bodies are the same.
    ///
    /// # Errors
    /// [`GpuError::TooLarge`] when the new table or lists exceed one
    /// storage binding; the simulation is left as it was (the next step
    /// tries again).
    fn follow_bodies(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &mut Target<'_>,
    ) -> Result<(), GpuError> {
        let keys = collider_keys(&self.sim);
        if keys == self.colliders {
            return Ok(());
        }
        let layout = TableLayout::of_simulation(&self.sim);
        layout.check(device)?;
        self.broad.reserve(device, keys.len() as u32)?;
        self.objects = GpuObjects::from_layout(device, layout, self.broad.mask_layout())?;
        if keys.len() > self.roots_capacity {
            self.roots_capacity = keys.len().max(2 * self.roots_capacity);
            self.world_roots = world_roots_buffer(device, self.roots_capacity);
        }
        let ids: Vec<trample::BodyId> = self.sim.bodies.iter().map(|b| b.id).collect();
        let table = trample::step::bodies::renumbered_owners(&self.body_ids, &ids);
        let renumbers = table
            .iter()
            .enumerate()
            .take(self.body_ids.len().min(255) + 1)
            .any(|(o, &n)| usize::from(n) != o);
        if renumbers {
            let kernel = self
                .track_owners
                .get_or_insert_with(|| TrackOwners::new(device));
            match target {
                Target::Submit => {
                    let mut encoder = new_encoder(device);
                    kernel.record(device, &mut encoder, &self.field, &table);
                    queue.submit([encoder.finish()]);
                }
                Target::Host(encoder) => kernel.record(device, encoder, &self.field, &table),
            }
        }
        self.colliders = keys;
        self.body_ids = ids;
        Ok(())
    }

    /// Records into `encoder` the instance lists and indirect draws of the
    /// current state for a renderer drawing straight from the GPU buffers
    /// ([`crate::draw_lists`]): blades of the geometric cells and billboards
    /// of the billboard cells of the patches visible from `sim.view` (culled
    /// on the CPU by the last step). `draw` carries the renderer's own
    /// numbers; its `counts` are filled here.
    pub fn record_draw_lists(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        draw: GpuDrawParams,
    ) {
        let layout = &self.sim.field.layout;
        let lists = self
            .draw_lists
            .get_or_insert_with(|| DrawLists::new(device, &self.field, layout.patch_list.len()));
        lists.record(
            device,
            queue,
            encoder,
            &self.field,
            &self.params,
            layout.cells_in_patch() as u32,
            &self.sim.visible,
            draw,
        );
    }

    /// The active patches' marks and lists after the last step, beside the
    /// blades' state ([`crate::active_patches::ActiveState`]; tests).
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when mapping fails.
    pub fn read_active_patches(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<crate::active_patches::ActiveState, GpuError> {
        crate::active_patches::ActiveState::read(device, queue, &self.broad, &self.field)
    }

    /// The draw lists of the last [`GpuSimulation::record_draw_lists`].
    #[must_use]
    pub fn draw_lists(&self) -> Option<&DrawLists> {
        self.draw_lists.as_ref()
    }

    /// Copies the GPU state back into [`GpuSimulation::sim`], ready to go on
    /// on the CPU path: blade positions (and the sets of displaced blades and
    /// bent billboards), classes and generations, cell levels and billboard slopes,
    /// and the step's counters into `sim.timings` (DBG, PBG,
    /// generations, displaced blades, cells per level, contact blades:
    /// [`GpuSimulation::sync_counters`]). For dumps and summaries at the end of
    /// a run, not per frame.
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when mapping fails (device lost).
    pub fn sync_to_cpu(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<(), GpuError> {
        let pos = self.field.read_positions(device, queue)?;
        for (p, q) in self.sim.field.blades.pos.iter_mut().zip(&pos) {
            *p = glam::Vec3A::new(q[0], q[1], q[2]).into();
        }
        let class = self.field.read_u32(device, queue, &self.field.class)?;
        for ((c, o), &k) in self
            .sim
            .class
            .iter_mut()
            .zip(self.sim.track_owner.iter_mut())
            .zip(&class)
        {
            *c = trample::step::BladeClass::from_u32(k & 0xff);
            *o = (k >> 8 & 0xff) as u8;
        }
        let flatness = self.field.read_flatness(device, queue)?;
        self.sim.field.cells.flatness.copy_from_slice(&flatness);
        let generation = self.field.read_u32(device, queue, &self.field.generation)?;
        for (g, &k) in self.sim.generation.iter_mut().zip(&generation) {
            *g = k.min(255) as u8;
        }
        let state = self.field.read_u32(device, queue, &self.field.cell_state)?;
        let slopes: Vec<[f32; 4]> = read_buffer(device, queue, &self.field.slope, "slopes")?;
        let cells = &mut self.sim.field.cells;
        for (c, &s) in state.iter().enumerate().take(cells.lod.len()) {
            cells.lod[c] = match s & 3 {
                0 => Lod::Geometry,
                1 => Lod::Billboard,
                _ => Lod::Texture,
            };
            cells.slope[c] = glam::Vec3::new(slopes[c][0], slopes[c][1], slopes[c][2]);
        }
        // The levels were written here, not by `classify_cells`.
        cells.levels_written(&self.sim.field.layout);
        self.sync_counters(device, queue)?;
        // The CPU step recovers only the blades and billboards it knows are
        // away from rest: rebuild those sets from the field read back.
        self.sim.rescan_displaced();
        Ok(())
    }

    /// Reads back the step's counters (52 bytes: DBG, PBG, generations,
    /// displaced blades, transitions, cells per level, contact blades,
    /// counted as the CPU's `StepTimings` counts them, far passes
    /// included: [`GpuCounters`]) into `sim.timings`; the field stays on
    /// the GPU. Cheap enough for
    /// every frame of a viewer, but it waits for the step to finish.
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when mapping fails.
    pub fn sync_counters(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<GpuCounters, GpuError> {
        let k = self.read_counters(device, queue)?;
        k.apply_to(&mut self.sim.timings);
        Ok(k)
    }

    /// Reads back the step's counters ([`GpuCounters`]: DBG, PBG,
    /// generations, displaced blades, …). For tests and summaries; not per
    /// frame.
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when mapping fails.
    pub fn read_counters(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<GpuCounters, GpuError> {
        Ok(read_buffer::<GpuCounters>(device, queue, &self.state, "counters")?[0])
    }
}

/// What [`GpuSimulation`] uploads of a simulation before it takes it:
/// everything that can fail, so that a simulation refused is given back.
struct Uploaded {
    field: GpuField,
    ground: f32,
    colliders: usize,
    world_roots: wgpu::Buffer,
    broad: BroadPhase,
    objects: GpuObjects,
    params: wgpu::Buffer,
    state: wgpu::Buffer,
}

impl Uploaded {
    /// Checks that the GPU path can run `sim` ([`GpuSimulation::supports`])
    /// and uploads its field and objects.
    fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        sim: &Simulation,
        max_chunk_bytes: Option<u64>,
    ) -> Result<Self, GpuError> {
        let object_layout = TableLayout::of_simulation(sim);
        GpuSimulation::supports_with(device, sim, &object_layout)?;
        let colliders: usize = sim.bodies.iter().map(trample::Body::collider_count).sum();
        // The step uniform's ground height (the shaders read the terrain table).
        let ground = match sim.field.terrain {
            Terrain::Flat(h) => h,
            _ => 0.0,
        };
        let field = GpuField::from_field_chunked(device, queue, &sim.field, max_chunk_bytes)?;
        // The blades' classes and track owners so far, the cells' flatness
        // (a simulation handed over mid-run).
        let class: Vec<u32> = sim
            .class
            .iter()
            .zip(&sim.track_owner)
            .map(|(&c, &o)| u32::from(c) | u32::from(o) << 8)
            .collect();
        queue.write_buffer(&field.class, 0, bytemuck::cast_slice(&class));
        queue.write_buffer(
            &field.flatness,
            0,
            bytemuck::cast_slice(&sim.field.cells.flatness),
        );
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("trample-gpu step params"),
            size: std::mem::size_of::<GpuStepParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let state = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("trample-gpu counters"),
            contents: bytemuck::bytes_of(&GpuCounters::default()),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let world_roots = world_roots_buffer(device, colliders);
        let broad = BroadPhase::new(device, &field, &sim.field.layout, colliders as u32)?;
        // One object per collider (a body's own mesh, then its parts).
        let objects = GpuObjects::from_layout(device, object_layout, broad.mask_layout())?;
        Ok(Self {
            field,
            ground,
            colliders,
            world_roots,
            broad,
            objects,
            params,
            state,
        })
    }
}

/// Where [`GpuSimulation`]'s step goes: a fresh encoder per sub-step,
/// submitted ([`GpuSimulation::step`]), or the host's encoder
/// ([`GpuSimulation::record_step`]).
enum Target<'a> {
    Submit,
    Host(&'a mut wgpu::CommandEncoder),
}

/// A collider's root box moved nowhere (a NaN centre): what a collider
/// that takes no part in a pass of the step ([`trample::step::Pass`])
/// gives the broad phase, which lists no patch for a box that is not
/// finite, and the billboards' cell rectangle, which is then empty.
fn nowhere(root: &trample::obb::Obb) -> trample::obb::Obb {
    trample::obb::Obb {
        center: glam::Vec3::NAN,
        ..*root
    }
}
