//! Narrow phase and DBG forces on the GPU (paper §4.2 and §5.1, Eq. 2;
//! DESIGN §4.2): dispatches `narrow_phase.wgsl`, one thread per blade, one
//! dispatch per chunk of patches for all objects (issue 16 item 3: each
//! thread loops over the objects the broad phase marked for its patch, in
//! object order; the objects in one table, [`GpuObjects`]), all in the
//! caller's encoder (the paper's read-back between tree levels is gone).
//!
//! Without the broad phase (`trample collide`, the stage tests) it matches
//! `trample::collision::narrow_phase::collide_blade` plus its EqF sum; with
//! it (the simulation) `contact_blade` and the weighted sum of
//! `trample::step::collide::narrow_phase`. Differences, by design:
//! - with the broad phase ([`BroadPhase`]) every blade of a listed patch is
//!   tested (the CPU also drops the cells outside the box's reach
//!   rectangle): the root-box test (the first test of the walk) rejects the
//!   far ones, and both filters are conservative, so the hits are the same.
//!   Without it (`trample collide`, stage tests) every blade of the field.
//! - the inside test's ray cast (boundary voxels only) uses f32 triangle
//!   tests where the CPU uses f64: the two differ only for a ray passing
//!   within rounding of a triangle edge.
//! - a non-finite vertex: WGSL does not promise IEEE NaN comparisons, so the
//!   CPU's "NaN is a miss" is not guaranteed here (blades are finite by
//!   construction).

use crate::broad_phase::BroadPhase;
use crate::field::GpuField;
use crate::kernel::{BindCache, args_buffer, begin_pass, compute_pipeline};
use crate::object::GpuObjects;

/// The WGSL source as compiled (`segment_obb.wgsl` and `chunk.wgsl` prepended).
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}\n{}\n{}",
        crate::SEGMENT_OBB_WGSL,
        crate::CHUNK_WGSL,
        crate::OBJECT_WGSL,
        include_str!("narrow_phase.wgsl")
    )
}

/// The compiled narrow-phase pipeline; kept apart from the buffers it runs on.
pub struct NarrowPhase {
    pipeline: wgpu::ComputePipeline,
    /// `list_blades`, `near_args`, `collide_listed`: the simulation's
    /// contacts over the broad phase's lists (`narrow_phase.wgsl` says why
    /// in two dispatches).
    list_blades: wgpu::ComputePipeline,
    near_args: wgpu::ComputePipeline,
    listed: wgpu::ComputePipeline,
    /// `collide_listed`'s indirect dispatch (written by `near_args`).
    near_dispatch: wgpu::Buffer,
    /// Bound in `near_dispatch`'s slot while `collide_listed` reads it, and
    /// without a broad phase.
    unused_args: wgpu::Buffer,
    /// Bound as the lists when there is no broad phase.
    no_lists: wgpu::Buffer,
    field_layout: wgpu::BindGroupLayout,
    object_layout: wgpu::BindGroupLayout,
    /// The chunks' and the object table's bind groups, made once.
    field_groups: BindCache,
    object_groups: BindCache,
}

pub(crate) fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

pub(crate) fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl NarrowPhase {
    /// Compiles the pipeline on `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("trample-gpu narrow_phase.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source().into()),
        });
        let field_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("trample-gpu narrow phase: field"),
            entries: &[
                storage_entry(0, true),
                storage_entry(1, true),
                storage_entry(2, false),
                storage_entry(3, false),
                uniform_entry(4),
                storage_entry(5, true),
                storage_entry(6, false),
                storage_entry(7, false),
            ],
        });
        let object_layout = object_layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("trample-gpu narrow phase"),
            bind_group_layouts: &[Some(&field_layout), Some(&object_layout)],
            immediate_size: 0,
        });
        let pipeline = |entry: &str| compute_pipeline(device, &layout, &module, entry);
        Self {
            pipeline: pipeline("collide"),
            list_blades: pipeline("list_blades"),
            near_args: pipeline("near_args"),
            listed: pipeline("collide_listed"),
            near_dispatch: args_buffer(
                device,
                "trample-gpu narrow phase dispatch",
                wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            ),
            unused_args: args_buffer(
                device,
                "trample-gpu narrow phase dispatch (unused)",
                wgpu::BufferUsages::STORAGE,
            ),
            no_lists: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu no broad phase"),
                size: 16,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            }),
            field_layout,
            object_layout,
            field_groups: BindCache::default(),
            object_groups: BindCache::default(),
        }
    }

    /// Records the narrow phase of every object in `objects` (in order) at
    /// `precision` (root = 1; clamped to 1..=64 as on the CPU) into
    /// `encoder`, writing the objects' parameters first (through `uploads`,
    /// in order with the encoder's commands)
    /// (set their poses, and with `broad` their contact settings
    /// ([`GpuObjects::set_contact`]), before). After the submission
    /// `field`'s forces hold Σ EqF and `num` over all objects (zero for
    /// blades nothing hit); its hit masks the segments any object hit.
    /// With no object nothing is recorded (forces keep their old contents).
    /// Returns the number of dispatches recorded, however many objects: with
    /// `broad` three per chunk of patches (the blades that may touch an
    /// object listed, the list's size, the walks), without it one.
    ///
    /// With `broad` (recorded earlier in `encoder`; `objects` made with its
    /// [`BroadPhase::mask_layout`]): the simulation's weighted contacts;
    /// only the blades of the listed patches are tested, each against the
    /// objects marked for its patch, and only theirs are written (every
    /// blade of a listed patch: nothing touched is zero). Every other
    /// blade's force and contact must be zero already: the active patches'
    /// `tidy` ([`crate::propagation::Propagation::record_tidy`]) clears
    /// those of the patches listed before.
    /// Without it: the paper's hit flags, every blade of the field against
    /// every object.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        uploads: &mut crate::upload::Uploads,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        objects: &mut GpuObjects,
        precision: u32,
        broad: Option<&BroadPhase>,
    ) -> u32 {
        if objects.is_empty() {
            return 0;
        }
        objects.set_walk(
            precision,
            field.count,
            field.segments,
            field.blades_per_cell,
        );
        objects.write(device, queue, uploads, encoder);
        let object_group = objects.bind(device, &self.object_layout, &self.object_groups);
        // One dispatch per chunk of patches (`chunk.wgsl`), one workgroup
        // deep in z: the shader takes gid.z as a 0 the driver cannot fold
        // (`dispatch_args` and `near_args` write z = 1 too). With the broad
        // phase, three: `list_blades`, `near_args`, `collide_listed`.
        for (c, chunk) in field.chunks.iter().enumerate() {
            // Kept for three sets (with the broad phase's lists and either
            // arguments buffer, and without them).
            let group = |lists, args| {
                self.field_groups.bind(
                    device,
                    &self.field_layout,
                    &[
                        &chunk.pos,
                        &field.cell_state,
                        &field.force,
                        &field.touch,
                        &chunk.uniform,
                        lists,
                        &field.near_blades,
                        args,
                    ],
                    3 * field.chunks.len(),
                )
            };
            let Some(b) = broad else {
                let mut pass = begin_pass(encoder);
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(1, &object_group, &[]);
                pass.set_bind_group(0, &group(&self.no_lists, &self.unused_args), &[]);
                pass.dispatch_workgroups(chunk.groups.0, chunk.groups.1, 1);
                continue;
            };
            encoder.clear_buffer(&field.near_blades, 0, Some(4));
            let mut pass = begin_pass(encoder);
            pass.set_bind_group(1, &object_group, &[]);
            pass.set_bind_group(0, &group(&b.lists, &self.near_dispatch), &[]);
            pass.set_pipeline(&self.list_blades);
            pass.dispatch_workgroups_indirect(&b.args, c as u64 * 12);
            pass.set_pipeline(&self.near_args);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_bind_group(0, &group(&b.lists, &self.unused_args), &[]);
            pass.set_pipeline(&self.listed);
            pass.dispatch_workgroups_indirect(&self.near_dispatch, 0);
        }
        field.chunks.len() as u32 * if broad.is_some() { 3 } else { 1 }
    }
}

/// The layout of the object table's bind group (group 1 of the narrow
/// phase and the contact response: `object.wgsl`).
pub(crate) fn object_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("trample-gpu objects"),
        entries: &[storage_entry(0, true)],
    })
}
