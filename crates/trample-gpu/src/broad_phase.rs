//! Broad phase on the GPU (paper §4 stage 2, DESIGN §4.1): dispatches
//! `broad_phase.wgsl`. One thread per patch tests its AABB against every
//! object's root box (`trample::collision::obb_overlaps_aabb`, with twice
//! its slack, so the GPU's list holds every patch the CPU's does); hit
//! patches are listed per chunk, and a second pass writes each chunk's
//! indirect dispatch for the narrow phase, which then runs only over the
//! blades of listed patches (no read-back). The narrow phase's root-box test
//! and the CPU's reach-rectangle filter are both conservative, so the hits
//! are the same as the CPU's.

use bytemuck::{Pod, Zeroable};
use trample::field::FieldLayout;
use wgpu::util::DeviceExt;

use crate::field::GpuField;
use crate::kernel::{Kernel, Slot, grid};

/// The WGSL source as compiled.
#[must_use]
pub fn source() -> String {
    include_str!("broad_phase.wgsl").to_string()
}

/// The broad phase's uniform. Layout-compatible with `BroadParams` in
/// `broad_phase.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct GpuBroadParams {
    /// Patches, patches per chunk (all but the last), chunks, objects.
    pub counts: [u32; 4],
    /// Blades per patch, max workgroups per dimension, unused ×2.
    pub dispatch: [u32; 4],
}

/// The compiled broad phase and the lists it fills, for one field.
pub struct BroadPhase {
    kernel: Kernel,
    params: wgpu::Buffer,
    patch_aabbs: wgpu::Buffer,
    /// The per-chunk patch lists, then the per-chunk counts (see the WGSL).
    pub(crate) lists: wgpu::Buffer,
    /// Per chunk: the narrow phase's indirect dispatch (x, y, z).
    pub(crate) args: wgpu::Buffer,
    chunks: u32,
    patches: u32,
    per_chunk: u32,
}

const PATCHES: usize = 0;
const DISPATCH_ARGS: usize = 1;

impl BroadPhase {
    /// Compiles the kernels and uploads `layout`'s patch boxes for `field`
    /// (whose chunks are whole patches) and `objects` objects.
    ///
    /// # Errors
    /// [`crate::GpuError::Layout`] when a chunk is not a whole number of
    /// patches or the chunks hold different numbers of patches (but the last).
    pub fn new(
        device: &wgpu::Device,
        field: &GpuField,
        layout: &FieldLayout,
        objects: u32,
    ) -> Result<Self, crate::GpuError> {
        let patches = layout.patch_list.len() as u32;
        let per_patch = field.patch_blades;
        let per_chunk = field
            .chunks
            .first()
            .map_or(0, |c| c.blades / per_patch.max(1));
        let chunked_by_patch = per_patch > 0
            && field.chunks.iter().enumerate().all(|(i, c)| {
                c.first_blade == i as u32 * per_chunk * per_patch
                    && c.blades.is_multiple_of(per_patch)
                    && (c.blades == per_chunk * per_patch || i + 1 == field.chunks.len())
            });
        if !chunked_by_patch || patches * per_patch != field.count {
            return Err(crate::GpuError::Layout(format!(
                "the broad phase needs chunks of whole patches of {per_patch} blades"
            )));
        }
        let aabbs: Vec<[f32; 4]> = layout
            .patch_list
            .iter()
            .flat_map(|p| {
                let (a, b) = (p.aabb_min, p.aabb_max);
                [[a.x, a.y, a.z, 0.0], [b.x, b.y, b.z, 0.0]]
            })
            .collect();
        let chunks = field.chunks.len() as u32;
        let params = GpuBroadParams {
            counts: [patches, per_chunk, chunks, objects],
            dispatch: [
                per_patch,
                device.limits().max_compute_workgroups_per_dimension,
                0,
                0,
            ],
        };
        use wgpu::BufferUsages as U;
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        use Slot::{Read, ReadWrite, Uniform};
        Ok(Self {
            kernel: Kernel::new(
                device,
                "trample-gpu broad phase",
                &source(),
                &[Uniform, Read, Read, ReadWrite, ReadWrite],
                &["patches", "dispatch_args"],
            ),
            params: init(
                "trample-gpu broad phase params",
                bytemuck::bytes_of(&params),
                U::UNIFORM,
            ),
            patch_aabbs: init(
                "trample-gpu patch boxes",
                bytemuck::cast_slice(&aabbs),
                U::STORAGE,
            ),
            lists: init(
                "trample-gpu broad phase lists",
                bytemuck::cast_slice(&vec![0u32; (chunks + patches) as usize]),
                U::STORAGE | U::COPY_DST | U::COPY_SRC,
            ),
            args: init(
                "trample-gpu narrow phase dispatch",
                bytemuck::cast_slice(&vec![0u32; 3 * chunks as usize]),
                U::STORAGE | U::INDIRECT | U::COPY_SRC,
            ),
            chunks,
            patches,
            per_chunk,
        })
    }

    /// Records the broad phase against the objects' world root boxes
    /// (`world_roots`, written for this sub-step): clears the lists, lists
    /// the hit patches, writes the dispatches.
    pub fn record(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        world_roots: &wgpu::Buffer,
    ) {
        encoder.clear_buffer(
            &self.lists,
            u64::from(self.patches) * 4,
            Some(u64::from(self.chunks) * 4),
        );
        let group = self.kernel.bind(
            device,
            &[
                &self.params,
                world_roots,
                &self.patch_aabbs,
                &self.lists,
                &self.args,
            ],
        );
        let max = device.limits().max_compute_workgroups_per_dimension;
        self.kernel
            .dispatch(encoder, PATCHES, &group, grid(self.patches, max));
        self.kernel
            .dispatch(encoder, DISPATCH_ARGS, &group, grid(self.chunks, max));
    }

    /// Reads back the listed patches, ascending (tests).
    ///
    /// # Errors
    /// [`crate::GpuError::ReadBack`] when mapping fails.
    pub fn read_patches(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<u32>, crate::GpuError> {
        let all: Vec<u32> =
            crate::readback::read_buffer(device, queue, &self.lists, "patch lists")?;
        let (lists, counts) = all.split_at(self.patches as usize);
        let mut out: Vec<u32> = counts
            .iter()
            .enumerate()
            .flat_map(|(c, &n)| {
                let start = c * self.per_chunk as usize;
                lists[start..start + n as usize].iter().copied()
            })
            .collect();
        out.sort_unstable();
        Ok(out)
    }
}
