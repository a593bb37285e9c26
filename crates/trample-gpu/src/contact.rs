//! The contact response on the GPU (ours, DESIGN §5 "Contact"): dispatches
//! `contact.wgsl`, one thread per touched blade of the patches the broad
//! phase listed (listed first by `list_touched`), per chunk of patches for
//! all objects (each thread applies the objects marked for its patch, in
//! object order), all in the caller's encoder: `trample::step::deform::resolve_contacts`, which runs
//! the same sets (the blades some object touched this sub-step, in the
//! patches listed for each object, from the lowest segment touched).

use crate::broad_phase::BroadPhase;
use crate::field::GpuField;
use crate::kernel::{BindCache, args_buffer, begin_pass, compute_pipeline};
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
    /// `list_touched`, `touched_args`, `contact_listed` (`contact.wgsl`
    /// says why in two dispatches).
    list_touched: wgpu::ComputePipeline,
    touched_args: wgpu::ComputePipeline,
    pipeline: wgpu::ComputePipeline,
    /// `contact_listed`'s indirect dispatch (written by `touched_args`).
    touched_dispatch: wgpu::Buffer,
    /// Bound in `touched_dispatch`'s slot while `contact_listed` reads it.
    unused_args: wgpu::Buffer,
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
                storage_entry(8, false),
                storage_entry(9, false),
            ],
        });
        let object_layout = crate::narrow_phase::object_layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("trample-gpu contact"),
            bind_group_layouts: &[Some(&field_layout), Some(&object_layout)],
            immediate_size: 0,
        });
        let pipeline = |entry: &str| compute_pipeline(device, &layout, &module, entry);
        let args = |label, usage| args_buffer(device, label, usage);
        use wgpu::BufferUsages as U;
        Self {
            list_touched: pipeline("list_touched"),
            touched_args: pipeline("touched_args"),
            pipeline: pipeline("contact_listed"),
            touched_dispatch: args("trample-gpu contact dispatch", U::STORAGE | U::INDIRECT),
            unused_args: args("trample-gpu contact dispatch (unused)", U::STORAGE),
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
    /// Returns the number of dispatches recorded: three per chunk of
    /// patches (the touched blades listed, the list's size, the response).
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
        for (c, chunk) in field.chunks.iter().enumerate() {
            let group = |args| {
                self.field_groups.bind(
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
                        &field.near_blades,
                        args,
                    ],
                    2 * field.chunks.len(),
                )
            };
            encoder.clear_buffer(&field.near_blades, 0, Some(4));
            let mut pass = begin_pass(encoder);
            pass.set_bind_group(1, &object_group, &[]);
            pass.set_bind_group(0, &group(&self.touched_dispatch), &[]);
            pass.set_pipeline(&self.list_touched);
            pass.dispatch_workgroups_indirect(&broad.args, c as u64 * 12);
            pass.set_pipeline(&self.touched_args);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_bind_group(0, &group(&self.unused_args), &[]);
            pass.set_pipeline(&self.pipeline);
            pass.dispatch_workgroups_indirect(&self.touched_dispatch, 0);
        }
        3 * field.chunks.len() as u32
    }
}

#[cfg(test)]
mod tests {
    /// `contact.wgsl`'s and `narrow_phase.wgsl`'s rule constants are the
    /// CPU's, bit for bit (a drift would show in the parity tests only as
    /// a small error, or not at all on their scenes).
    #[test]
    fn the_shaders_contact_constants_are_the_cpus() {
        use trample::collision::narrow_phase::AGREED;
        use trample::deform::contact::{FLAT_FLOOR, FLAT_LEAN, FLAT_OUT, PIN_HEIGHT, PIN_REACH};
        let value = crate::wgsl_f32_const;
        let contact = include_str!("contact.wgsl");
        for (name, want) in [
            ("PIN_HEIGHT", PIN_HEIGHT),
            ("FLAT_LEAN", FLAT_LEAN),
            ("FLAT_OUT", FLAT_OUT),
            ("FLAT_FLOOR", FLAT_FLOOR),
            ("PIN_REACH", PIN_REACH),
        ] {
            assert_eq!(value(contact, name).to_bits(), want.to_bits(), "{name}");
        }
        let narrow = include_str!("narrow_phase.wgsl");
        assert_eq!(value(narrow, "AGREED").to_bits(), AGREED.to_bits());
    }
}
