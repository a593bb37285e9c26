//! Broad phase on the GPU (paper §4 stage 2, DESIGN §4.1): dispatches
//! `broad_phase.wgsl`. As on the CPU (`trample::collision::patches_under`),
//! each object's world root box gives the rectangle of patches under it by
//! a grid lookup (`trample::collision::patch_rect`, on the CPU with the
//! poses, a few numbers per object uploaded each sub-step); one thread per
//! (object, patch of its rectangle) tests the patch's AABB against the box
//! (`trample::collision::obb_overlaps_aabb`, with twice its slack, so the
//! GPU's list holds every patch the CPU's does). The cost follows what the
//! objects cover, not patches × objects (issue 16). A hit patch is listed
//! once per chunk (a per-patch mark dedups objects that share it), and a
//! second pass writes each chunk's indirect dispatch for the narrow phase,
//! which then runs only over the blades of listed patches (no read-back).
//! The narrow phase's root-box test and the CPU's reach-rectangle filter
//! are both conservative, so the hits are the same as the CPU's.

use bytemuck::{Pod, Zeroable};
use trample::collision::patch_rect;
use trample::field::FieldLayout;
use trample::obb::Obb;
use wgpu::util::DeviceExt;

use crate::active_patches::{List, region_words};
use crate::field::GpuField;
use crate::kernel::{Kernel, Slot, grid};

/// The WGSL source as compiled.
#[must_use]
pub fn source() -> String {
    format!(
        "{}\n{}",
        include_str!("broad_params.wgsl"),
        include_str!("broad_phase.wgsl")
    )
}

/// The broad phase's uniform. Layout-compatible with `BroadParams` in
/// `broad_params.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct GpuBroadParams {
    /// Patches, patches per chunk (all but the last), chunks, patches along x.
    pub counts: [u32; 4],
    /// Blades per patch, max workgroups per dimension, mask words per
    /// patch ([`BroadPhase::mask_layout`]), unused.
    pub dispatch: [u32; 4],
}

/// The compiled broad phase and the lists it fills, for one field.
pub struct BroadPhase {
    kernel: Kernel,
    /// Its uniform ([`GpuBroadParams`]; propagation's `seed` reads it too).
    pub(crate) params: wgpu::Buffer,
    patch_aabbs: wgpu::Buffer,
    /// Per sub-step: the candidate count and each object's patch rectangle
    /// (see [`GpuPatchRect`]).
    rects: wgpu::Buffer,
    /// The per-chunk patch lists, then the per-chunk counts, then a mark
    /// per patch (see the WGSL).
    pub(crate) lists: wgpu::Buffer,
    /// Per chunk: the narrow phase's indirect dispatch (x, y, z); then one
    /// per active-patch list ([`BroadPhase::list_args_offset`]).
    pub(crate) args: wgpu::Buffer,
    chunks: u32,
    patches: u32,
    per_chunk: u32,
    /// Blades per patch.
    per_patch: u32,
    /// Patches along x.
    row: u32,
    /// Objects the rectangles, lists and masks have room for.
    objects: u32,
}

/// The broad phase's buffers whose size follows the number of objects.
struct Sized {
    params: wgpu::Buffer,
    rects: wgpu::Buffer,
    lists: wgpu::Buffer,
}

impl Sized {
    /// `counts`: patches, patches per chunk, chunks, patches along x.
    fn new(
        device: &wgpu::Device,
        counts: [u32; 4],
        per_patch: u32,
        objects: u32,
    ) -> Result<Self, crate::GpuError> {
        let [patches, _, chunks, _] = counts;
        let limit = device.limits().max_storage_buffer_binding_size;
        let bytes = lists_words(patches, chunks, objects) * 4;
        if bytes > limit {
            return Err(crate::GpuError::TooLarge {
                what: "the broad phase's patch lists and per-patch object masks \
                       (4 bytes a patch per 32 objects)",
                bytes,
                limit,
            });
        }
        let first = active_first(patches, chunks, objects);
        let params = GpuBroadParams {
            counts,
            dispatch: [
                per_patch,
                device.limits().max_compute_workgroups_per_dimension,
                mask_words(objects),
                first as u32,
            ],
        };
        // Every patch starts dirty and kept: the first sub-step visits the
        // whole field once (a table made again, for more objects, too).
        let mut words = vec![0u32; lists_words(patches, chunks, objects) as usize];
        words[first as usize..(first + 2 * u64::from(patches)) as usize].fill(1);
        use wgpu::BufferUsages as U;
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        Ok(Self {
            params: init(
                "trample-gpu broad phase params",
                bytemuck::bytes_of(&params),
                U::UNIFORM,
            ),
            rects: init(
                "trample-gpu broad phase rectangles",
                bytemuck::cast_slice(&vec![GpuPatchRect::default(); objects as usize + 1]),
                U::STORAGE | U::COPY_DST,
            ),
            lists: init(
                "trample-gpu broad phase lists",
                bytemuck::cast_slice(&words),
                U::STORAGE | U::COPY_DST | U::COPY_SRC,
            ),
        })
    }
}

/// Stand-ins for a broad phase's uniform and lists, bound by the stages that
/// read them where none is given (the stage tests): a zero uniform (no
/// patches: every blade is visited, nothing is marked) and a small buffer.
pub(crate) struct NoBroad {
    pub(crate) params: wgpu::Buffer,
    pub(crate) lists: wgpu::Buffer,
}

impl NoBroad {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        Self {
            params: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu no broad phase"),
                size: std::mem::size_of::<GpuBroadParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM,
                mapped_at_creation: false,
            }),
            lists: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu no patch lists"),
                size: 16,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            }),
        }
    }

    /// `broad`'s uniform and lists, or these stand-ins.
    pub(crate) fn or<'a>(
        &'a self,
        broad: Option<&'a BroadPhase>,
    ) -> (&'a wgpu::Buffer, &'a wgpu::Buffer) {
        broad.map_or((&self.params, &self.lists), |b| (&b.params, &b.lists))
    }
}

/// 32-bit words of one patch's object mask for `objects` objects (≥ 1).
#[must_use]
pub fn mask_words(objects: u32) -> u32 {
    objects.div_ceil(32).max(1)
}

/// Words of the lists buffer: the lists, the per-chunk counts, a mark per
/// patch, an object mask per patch (see `broad_phase.wgsl`), then the
/// active patches' region ([`crate::active_patches`]).
#[must_use]
pub fn lists_words(patches: u32, chunks: u32, objects: u32) -> u64 {
    active_first(patches, chunks, objects) + region_words(patches, chunks)
}

/// The first word of the active patches' region of the lists: after the
/// broad phase's own lists, counts, marks and masks.
fn active_first(patches: u32, chunks: u32, objects: u32) -> u64 {
    u64::from(chunks) + u64::from(patches) * (2 + u64::from(mask_words(objects)))
}

const CANDIDATES: usize = 0;
const DISPATCH_ARGS: usize = 1;

/// One object's rectangle of candidate patches, as `broad_phase.wgsl`
/// reads it: first column and row, width in patches, and the index of its
/// first candidate among all objects' (a prefix sum). Entry 0 of the buffer
/// is the header: (candidates of all objects, objects, 0, 0). An object off
/// the field has no candidates (width 1, the next object's first).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq, Eq)]
pub struct GpuPatchRect {
    /// x0, z0, width, first candidate.
    pub rect: [u32; 4],
}
const _: () = assert!(std::mem::size_of::<GpuPatchRect>() == 16);

/// The header and the rectangles of `roots` (world root boxes, one per
/// object) for `broad_phase.wgsl`, and the total candidate count.
#[must_use]
pub fn patch_rects(layout: &FieldLayout, roots: &[Obb]) -> (Vec<GpuPatchRect>, u32) {
    let mut out = vec![GpuPatchRect::default()];
    let mut first = 0u32;
    for root in roots {
        let rect = patch_rect(layout, root);
        let (x0, z0, width) = rect.map_or((0, 0, 1), |r| (r.x[0], r.z[0], r.x[1] - r.x[0] + 1));
        out.push(GpuPatchRect {
            rect: [x0, z0, width, first],
        });
        first += rect.map_or(0, |r| r.patch_count() as u32);
    }
    out[0].rect = [first, roots.len() as u32, 0, 0];
    (out, first)
}

impl BroadPhase {
    /// Compiles the kernels and uploads `layout`'s patch boxes for `field`
    /// (whose chunks are whole patches) and up to `objects` objects.
    ///
    /// # Errors
    /// [`crate::GpuError::Layout`] when a chunk is not a whole number of
    /// patches or the chunks hold different numbers of patches (but the
    /// last); [`crate::GpuError::TooLarge`] when the lists and masks exceed
    /// one storage binding.
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
        let sized = Sized::new(
            device,
            [patches, per_chunk, chunks, layout.patches[0]],
            per_patch,
            objects,
        )?;
        use Slot::{Read, ReadWrite, Uniform};
        Ok(Self {
            kernel: Kernel::new(
                device,
                "trample-gpu broad phase",
                &source(),
                &[Uniform, Read, Read, ReadWrite, ReadWrite, Read],
                &["candidates", "dispatch_args"],
            ),
            params: sized.params,
            patch_aabbs: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("trample-gpu patch boxes"),
                contents: bytemuck::cast_slice(&aabbs),
                usage: wgpu::BufferUsages::STORAGE,
            }),
            rects: sized.rects,
            lists: sized.lists,
            args: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("trample-gpu narrow phase dispatch"),
                // The narrow phase's per chunk, then the active patches'
                // lists': tidy, seed, bend's and recover's per chunk.
                contents: bytemuck::cast_slice(&vec![0u32; 3 * (3 * chunks + 2) as usize]),
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::INDIRECT
                    | wgpu::BufferUsages::COPY_SRC,
            }),
            chunks,
            patches,
            per_chunk,
            per_patch,
            row: layout.patches[0],
            objects,
        })
    }

    /// Objects the lists and masks have room for ([`BroadPhase::new`],
    /// [`BroadPhase::reserve`]).
    #[must_use]
    pub fn capacity(&self) -> u32 {
        self.objects
    }

    /// Makes room for `objects` objects (bodies added to a running
    /// simulation): when there is not, the rectangles, lists and masks are
    /// made again for twice as many as before, or `objects` if more (the
    /// kernel is kept). The mask layout ([`BroadPhase::mask_layout`])
    /// changes with it: the object table must be made again after a
    /// `true` (made again).
    ///
    /// # Errors
    /// [`crate::GpuError::TooLarge`] as [`BroadPhase::new`].
    pub fn reserve(
        &mut self,
        device: &wgpu::Device,
        objects: u32,
    ) -> Result<bool, crate::GpuError> {
        if objects <= self.objects {
            return Ok(false);
        }
        let objects = objects.max(self.objects.saturating_mul(2));
        let sized = Sized::new(
            device,
            [self.patches, self.per_chunk, self.chunks, self.row],
            self.per_patch,
            objects,
        )?;
        self.params = sized.params;
        self.rects = sized.rects;
        self.lists = sized.lists;
        self.objects = objects;
        Ok(true)
    }

    /// Patches of the field.
    #[must_use]
    pub fn patch_count(&self) -> u32 {
        self.patches
    }

    /// Chunks of the field.
    #[must_use]
    pub fn chunk_count(&self) -> u32 {
        self.chunks
    }

    /// The first word of the active patches' region of `lists`.
    pub(crate) fn active_first(&self) -> u64 {
        active_first(self.patches, self.chunks, self.objects)
    }

    /// The byte offset in `lists` of `list`'s count, and the bytes of the
    /// counts from there to the end of the active patches' region.
    pub(crate) fn active_counts(&self, list: List) -> (u64, u64) {
        let first =
            active_first(self.patches, self.chunks, self.objects) + 6 * u64::from(self.patches);
        let all = region_words(self.patches, self.chunks) - 6 * u64::from(self.patches);
        let i = u64::from(list.index(self.chunks));
        ((first + i) * 4, (all - i) * 4)
    }

    /// The byte offset in `args` of `list`'s indirect dispatch (written by
    /// the active patches' `list_args`).
    #[must_use]
    pub fn list_args_offset(&self, list: List) -> u64 {
        u64::from(3 * (self.chunks + list.index(self.chunks))) * 4
    }

    /// Where the per-patch object masks lie in `BroadPhase::lists`:
    /// (words per patch, first word), as the object table's header carries
    /// them to the narrow phase and the contact response
    /// ([`crate::object::GpuObjects::new`]).
    #[must_use]
    pub fn mask_layout(&self) -> (u32, u32) {
        (mask_words(self.objects), 2 * self.patches + self.chunks)
    }

    /// Records the broad phase against the objects' world root boxes:
    /// `roots` on the CPU, the same as `world_roots` on the GPU (written for
    /// this sub-step). Uploads the objects' patch rectangles
    /// ([`patch_rects`]), clears the counts and marks, lists the hit
    /// patches, writes the dispatches. Objects past the number
    /// [`BroadPhase::new`] was given are ignored. The rectangles go through
    /// `uploads`, in order with the encoder's commands.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        uploads: &mut crate::upload::Uploads,
        encoder: &mut wgpu::CommandEncoder,
        world_roots: &wgpu::Buffer,
        layout: &FieldLayout,
        roots: &[Obb],
    ) {
        let roots = &roots[..roots.len().min(self.objects as usize)];
        let (rects, candidates) = patch_rects(layout, roots);
        uploads.upload(
            device,
            queue,
            encoder,
            &self.rects,
            0,
            bytemuck::cast_slice(&rects),
        );
        // The counts, marks and masks (not the active patches' region).
        let first = u64::from(self.patches) * 4;
        let end = active_first(self.patches, self.chunks, self.objects) * 4;
        encoder.clear_buffer(&self.lists, first, Some(end - first));
        let group = self.kernel.bind(
            device,
            &[
                &self.params,
                world_roots,
                &self.patch_aabbs,
                &self.lists,
                &self.args,
                &self.rects,
            ],
        );
        let max = device.limits().max_compute_workgroups_per_dimension;
        if candidates > 0 {
            self.kernel
                .dispatch(encoder, CANDIDATES, &group, grid(candidates, max));
        }
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
        let (lists, rest) = all.split_at(self.patches as usize);
        let counts = &rest[..self.chunks as usize];
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

    /// Reads back, per object, the patches whose mask holds it, ascending
    /// (tests: the per-object lists the narrow phase reads).
    ///
    /// # Errors
    /// [`crate::GpuError::ReadBack`] when mapping fails.
    pub fn read_object_patches(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<Vec<u32>>, crate::GpuError> {
        let all: Vec<u32> =
            crate::readback::read_buffer(device, queue, &self.lists, "object masks")?;
        let (words, first) = self.mask_layout();
        let mut out = vec![Vec::new(); self.objects as usize];
        for p in 0..self.patches {
            for (o, list) in out.iter_mut().enumerate() {
                let word = all[(first + p * words) as usize + o / 32];
                if word & (1 << (o % 32)) != 0 {
                    list.push(p);
                }
            }
        }
        Ok(out)
    }
}
