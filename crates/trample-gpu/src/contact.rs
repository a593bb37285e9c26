//! The contact response on the GPU (ours, DESIGN §5 "Contact"): dispatches
//! `contact.wgsl`, one thread per blade of the patches the broad phase
//! listed, one dispatch per chunk of patches for all objects (each thread
//! applies the objects marked for its patch, in object order), all in the
//! caller's encoder: `trample::step::deform::resolve_contacts`, which runs
//! the same sets (the blades some object touched this sub-step, in the
//! patches listed for each object, from the lowest segment touched).

use crate::broad_phase::BroadPhase;
use crate::field::GpuField;
use crate::kernel::BindCache;
use crate::object::GpuObjects;

/// The WGSL source as compiled (`blade.wgsl`, `guard.wgsl`,
/// `segment_obb.wgsl`, `chunk.wgsl` and `object.wgsl` prepended).
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}\n{}\n{}\n{}\n{}",
        crate::BLADE_WGSL,
        crate::GUARD_WGSL,
        crate::SEGMENT_OBB_WGSL,
        crate::CHUNK_WGSL,
        crate::OBJECT_WGSL,
        include_str!("contact.wgsl")
    )
}

/// The compiled contact pipeline; kept apart from the buffers it runs on.
pub struct Contact {
    pipeline: wgpu::ComputePipeline,
    field_layout: wgpu::BindGroupLayout,
    object_layout: wgpu::BindGroupLayout,
    /// The chunks' and the object table's bind groups, made once.
    field_groups: BindCache,
    object_groups: BindCache,
}

impl Contact {
    /// Compiles the pipeline on `device`.
    #[must_use]
    pub fn new(device: &wgpu::Device) -> Self {
        use crate::narrow_phase::{storage_entry, uniform_entry};
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("trample-gpu contact.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source().into()),
        });
        let field_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("trample-gpu contact: field"),
            entries: &[
                uniform_entry(0),
                storage_entry(1, false),
                storage_entry(2, false),
                storage_entry(3, false),
                uniform_entry(4),
                storage_entry(5, true),
                storage_entry(6, true),
                storage_entry(7, false),
            ],
        });
        let object_layout = crate::narrow_phase::object_layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("trample-gpu contact"),
            bind_group_layouts: &[Some(&field_layout), Some(&object_layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("contact_listed"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("contact_listed"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });
        Self {
            pipeline,
            field_layout,
            object_layout,
            field_groups: BindCache::default(),
            object_groups: BindCache::default(),
        }
    }

    /// Records the contact response of every object in `objects` (in
    /// order; their parameters as the narrow phase of the same sub-step
    /// wrote them) over the patches `broad` listed, after the bending.
    /// Counts the blades it moves (and in a far pass those it moves from
    /// rest) in `state`, the step's counters ([`crate::GpuCounters`]).
    /// Returns the number of dispatches recorded: one per chunk of patches.
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        params: &wgpu::Buffer,
        state: &wgpu::Buffer,
        objects: &GpuObjects,
        broad: &BroadPhase,
    ) -> u32 {
        if objects.is_empty() {
            return 0;
        }
        let object_group = objects.bind(device, &self.object_layout, &self.object_groups);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("trample-gpu contact"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(1, &object_group, &[]);
        for (c, chunk) in field.chunks.iter().enumerate() {
            let group = self.field_groups.bind(
                device,
                &self.field_layout,
                &[
                    params,
                    &chunk.pos,
                    &field.touch,
                    &field.displaced,
                    &chunk.uniform,
                    &field.ground,
                    &broad.lists,
                    state,
                ],
                field.chunks.len(),
            );
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups_indirect(&broad.args, c as u64 * 12);
        }
        field.chunks.len() as u32
    }
}
