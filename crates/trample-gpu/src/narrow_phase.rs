//! Narrow phase and DBG forces on the GPU (paper §4.2 and §5.1, Eq. 2;
//! DESIGN §4.2): dispatches `narrow_phase.wgsl`, one thread per blade, one
//! dispatch per object, all in the caller's encoder (one submission; the
//! paper's read-back between tree levels is gone).
//!
//! Matches `trample::collision::narrow_phase::collide_blade` plus the EqF sum
//! of `trample::step::stages::narrow_phase`. Differences, by design:
//! - no broad phase by patch yet: every blade of a geometric cell is tested,
//!   and the root-box test (the first test of the walk) rejects the far ones.
//!   The CPU's patch and reach-rectangle filters are conservative, so the
//!   hits are the same; only the cost differs (≈ one box test per blade).
//! - the inside test's ray cast (boundary voxels only) uses f32 triangle
//!   tests where the CPU uses f64: the two differ only for a ray passing
//!   within rounding of a triangle edge.
//! - a non-finite vertex: WGSL does not promise IEEE NaN comparisons, so the
//!   CPU's "NaN is a miss" is not guaranteed here (blades are finite by
//!   construction).

use crate::field::GpuField;
use crate::object::{GpuObject, GpuObjectParams};

/// The WGSL source as compiled (`segment_obb.wgsl` prepended).
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}",
        crate::SEGMENT_OBB_WGSL,
        include_str!("narrow_phase.wgsl")
    )
}

/// Threads per workgroup (`@workgroup_size` in the WGSL).
const WORKGROUP: u32 = 64;

/// The compiled narrow-phase pipeline; kept apart from the buffers it runs on.
pub struct NarrowPhase {
    pipeline: wgpu::ComputePipeline,
    field_layout: wgpu::BindGroupLayout,
    object_layout: wgpu::BindGroupLayout,
}

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
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
            ],
        });
        let object_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("trample-gpu narrow phase: object"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage_entry(1, true),
                storage_entry(2, true),
                storage_entry(3, true),
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("trample-gpu narrow phase"),
            bind_group_layouts: &[Some(&field_layout), Some(&object_layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("trample-gpu narrow phase"),
            layout: Some(&layout),
            module: &module,
            entry_point: Some("collide"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: None,
        });
        Self {
            pipeline,
            field_layout,
            object_layout,
        }
    }

    /// Records the narrow phase of every object in `objects` (in order) at
    /// `precision` (root = 1; clamped to 1..=64 as on the CPU) into
    /// `encoder`, writing each object's uniform through `queue` first. After
    /// the submission `field`'s forces hold Σ EqF and `num` over all objects
    /// (zero for blades nothing hit); its hit masks the segments any object hit.
    /// With no object nothing is recorded (forces keep their old contents).
    pub fn record(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        field: &GpuField,
        objects: &mut [GpuObject],
        precision: u32,
    ) {
        let field_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("trample-gpu narrow phase: field"),
            layout: &self.field_layout,
            entries: &[
                entry(0, &field.pos),
                entry(1, &field.cell_state),
                entry(2, &field.force),
                entry(3, &field.hit_mask),
            ],
        });
        let groups = field.count.div_ceil(WORKGROUP);
        let max = device.limits().max_compute_workgroups_per_dimension.max(1);
        let (gx, gy) = (groups.min(max), groups.div_ceil(max));
        for (i, obj) in objects.iter_mut().enumerate() {
            let p: &mut GpuObjectParams = &mut obj.params;
            p.tree[2] = precision.clamp(1, trample::obb::MAX_TREE_DEPTH);
            p.tree[3] = u32::from(i == 0);
            p.field[0] = field.count;
            p.field[1] = field.segments;
            p.field[2] = field.blades_per_cell;
            queue.write_buffer(&obj.uniform, 0, bytemuck::bytes_of(p));
            let object_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("trample-gpu narrow phase: object"),
                layout: &self.object_layout,
                entries: &[
                    entry(0, &obj.uniform),
                    entry(1, &obj.nodes),
                    entry(2, &obj.triangles),
                    entry(3, &obj.voxels),
                ],
            });
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("trample-gpu narrow phase"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &field_group, &[]);
            pass.set_bind_group(1, &object_group, &[]);
            // The shader computes the blade as x + y · (groups in x · 64),
            // and takes gid.z as a 0 the driver cannot fold (z stays 1).
            pass.dispatch_workgroups(gx, gy, 1);
        }
    }
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}
