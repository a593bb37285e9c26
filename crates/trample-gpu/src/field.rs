//! The field's blades and cells on the GPU, in the CPU's layout (DESIGN §2,
//! Eq. 1): `pos[k * count + b]` is vertex k of blade b, blades patch-major,
//! the blades of a cell contiguous. The buffers stay on the GPU across
//! steps; reading back is for tests and dumps only.
//!
//! Not yet done: fields over one storage binding (128 MiB on the software
//! drivers, ≈ 1.6 M blades of 5 vertices) are refused with
//! [`GpuError::TooLarge`] instead of being split into chunks of patches.

use bytemuck::{Pod, Zeroable};
use trample::field::{Blades, Field, Lod};
use wgpu::util::DeviceExt;

use crate::error::GpuError;
use crate::readback::read_buffer;

/// Per-blade output of the narrow phase: Σ EqF (Eq. 2) over the blade's hit
/// segments and all objects in xyz, `num` (hit count, saturating at 255) in
/// w. Layout-compatible with `force` in `narrow_phase.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GpuForce {
    /// Σ EqF, world frame.
    pub force: [f32; 3],
    /// Eq. 5's `num`, as a float (exact up to 255).
    pub num: f32,
}
const _: () = assert!(std::mem::size_of::<GpuForce>() == 16);

/// Blade and cell buffers of one field.
pub struct GpuField {
    /// Blades.
    pub count: u32,
    /// Segments per blade.
    pub segments: u32,
    /// Blades per cell.
    pub blades_per_cell: u32,
    /// Vertex positions, vertex-major, `vec4<f32>` (w unused). Usable as a
    /// vertex or storage buffer by a renderer.
    pub pos: wgpu::Buffer,
    /// Rest positions, same layout as `pos`.
    pub rest: wgpu::Buffer,
    pub(crate) seg_len: wgpu::Buffer,
    pub(crate) neighbours: wgpu::Buffer,
    /// Cells.
    pub cell_count: u32,
    /// Per cell: bits 0–1 level of detail, 2–3 level before this sub-step's
    /// change (3: none), bit 4 billboard bent (see `cells.wgsl`).
    pub cell_state: wgpu::Buffer,
    /// Per cell: (base, billboard height), (slope_origin_b, 0).
    pub(crate) cell_rest: wgpu::Buffer,
    /// Per cell: current billboard slope `slope_b` (Eq. 8, 12), xyz.
    pub slope: wgpu::Buffer,
    pub(crate) force: wgpu::Buffer,
    pub(crate) hit_mask: wgpu::Buffer,
    /// Generation per blade this sub-step (0 = DBG, 1… = PBG, 255 = none).
    pub generation: wgpu::Buffer,
    /// `BladeClass` per blade (0 untouched, 1 DBG, 2 PBG), as `u32`.
    pub class: wgpu::Buffer,
    /// 1 where a blade is away from rest (recovery works on those).
    pub(crate) displaced: wgpu::Buffer,
}

impl GpuField {
    /// Uploads `field` (blades, cells with their levels, billboards and
    /// slopes, neighbour table).
    ///
    /// # Errors
    /// As [`GpuField::new`].
    pub fn from_field(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        field: &Field,
    ) -> Result<Self, GpuError> {
        let out = Self::new(
            device,
            &field.blades,
            &field.cells.lod,
            field.layout.blades_per_cell,
            &field.layout.neighbours,
        )?;
        let cells = &field.cells;
        let rest: Vec<[f32; 4]> = (0..cells.lod.len())
            .flat_map(|c| {
                let (b, o) = (cells.base[c], cells.slope_origin[c]);
                let coords = crate::cells::packed_cell_coords(&field.layout, c);
                [[b.x, b.y, b.z, cells.height[c]], [o.x, o.y, o.z, coords]]
            })
            .collect();
        let slope: Vec<[f32; 4]> = cells.slope.iter().map(|s| [s.x, s.y, s.z, 0.0]).collect();
        let state: Vec<u32> = (0..cells.lod.len())
            .map(|c| cell_state(cells.lod[c], !cells.slope_at_rest(c)))
            .collect();
        queue.write_buffer(&out.cell_rest, 0, bytemuck::cast_slice(&rest));
        queue.write_buffer(&out.slope, 0, bytemuck::cast_slice(&slope));
        queue.write_buffer(&out.cell_state, 0, bytemuck::cast_slice(&state));
        Ok(out)
    }

    /// Uploads `blades`, the cells' levels of detail (`lod.len()` cells of
    /// `blades_per_cell` blades each) and the blades' neighbour table
    /// (Definition 6, order −x, +x, −z, +z; one entry per blade).
    ///
    /// # Errors
    /// [`GpuError::Layout`] when the cells do not cover the blades;
    /// [`GpuError::TooLarge`] when the positions exceed one storage binding.
    pub fn new(
        device: &wgpu::Device,
        blades: &Blades,
        lod: &[Lod],
        blades_per_cell: u32,
        neighbours: &[[u32; 4]],
    ) -> Result<Self, GpuError> {
        if neighbours.len() != blades.count {
            return Err(GpuError::Layout(format!(
                "{} neighbour entries for {} blades",
                neighbours.len(),
                blades.count
            )));
        }
        if blades.count == 0
            || blades_per_cell == 0
            || lod.len() * blades_per_cell as usize != blades.count
        {
            return Err(GpuError::Layout(format!(
                "{} cells of {blades_per_cell} blades do not make {} blades",
                lod.len(),
                blades.count
            )));
        }
        let limit = device.limits().max_storage_buffer_binding_size;
        let pos = to_vec4(&blades.pos);
        let bytes = (pos.len() * 16) as u64;
        if bytes > limit {
            return Err(GpuError::TooLarge {
                what: "blade positions",
                bytes,
                limit,
            });
        }
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        use wgpu::BufferUsages as U;
        let state: Vec<u32> = lod.iter().map(|&l| cell_state(l, false)).collect();
        // Vertex 0 of `rest` carries the segment length in w (cells.wgsl).
        let mut rest = to_vec4(&blades.rest);
        for (r, &l) in rest.iter_mut().zip(&blades.seg_len) {
            r[3] = l;
        }
        let cells = lod.len() as u64;
        Ok(Self {
            count: blades.count as u32,
            segments: blades.segments as u32,
            blades_per_cell,
            pos: init(
                "trample-gpu blade positions",
                bytemuck::cast_slice(&pos),
                U::STORAGE | U::VERTEX | U::COPY_DST | U::COPY_SRC,
            ),
            rest: init(
                "trample-gpu blade rest positions",
                bytemuck::cast_slice(&rest),
                U::STORAGE | U::COPY_SRC,
            ),
            seg_len: init(
                "trample-gpu segment lengths",
                bytemuck::cast_slice(&blades.seg_len),
                U::STORAGE,
            ),
            neighbours: init(
                "trample-gpu neighbours",
                bytemuck::cast_slice(neighbours),
                U::STORAGE,
            ),
            generation: init(
                "trample-gpu generations",
                bytemuck::cast_slice(&vec![255u32; blades.count]),
                U::STORAGE | U::COPY_SRC,
            ),
            class: init(
                "trample-gpu blade classes",
                bytemuck::cast_slice(&vec![0u32; blades.count]),
                U::STORAGE | U::COPY_SRC,
            ),
            displaced: init(
                "trample-gpu displaced flags",
                bytemuck::cast_slice(&vec![0u32; blades.count]),
                U::STORAGE | U::COPY_SRC,
            ),
            cell_count: lod.len() as u32,
            cell_state: init(
                "trample-gpu cell state",
                bytemuck::cast_slice(&state),
                U::STORAGE | U::COPY_DST | U::COPY_SRC,
            ),
            cell_rest: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu cell rest"),
                size: cells * 32,
                usage: U::STORAGE | U::COPY_DST,
                mapped_at_creation: false,
            }),
            slope: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu billboard slopes"),
                size: cells * 16,
                usage: U::STORAGE | U::COPY_DST | U::COPY_SRC,
                mapped_at_creation: false,
            }),
            force: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu blade forces"),
                size: blades.count as u64 * 16,
                usage: U::STORAGE | U::COPY_SRC | U::COPY_DST,
                mapped_at_creation: false,
            }),
            hit_mask: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu hit masks"),
                size: blades.count as u64 * 4,
                usage: U::STORAGE | U::COPY_SRC,
                mapped_at_creation: false,
            }),
        })
    }

    /// Overwrites the per-blade forces (Σ EqF in xyz, `num` in w), e.g. to
    /// run propagation or bending on forces of one's own (stage tests).
    pub fn write_forces(&self, queue: &wgpu::Queue, forces: &[GpuForce]) {
        queue.write_buffer(&self.force, 0, bytemuck::cast_slice(forces));
    }

    /// Reads back the per-blade forces of the last narrow phase.
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when mapping fails.
    pub fn read_forces(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<GpuForce>, GpuError> {
        read_buffer(device, queue, &self.force, "forces")
    }

    /// Reads back the hit masks of the last narrow phase (bit k: segment k
    /// hit one of the objects).
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when mapping fails.
    pub fn read_hit_masks(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<u32>, GpuError> {
        read_buffer(device, queue, &self.hit_mask, "hit masks")
    }

    /// Reads back a `u32` per blade: [`GpuField::class`] or [`GpuField::generation`].
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when mapping fails.
    pub fn read_u32(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        buffer: &wgpu::Buffer,
    ) -> Result<Vec<u32>, GpuError> {
        read_buffer(device, queue, buffer, "per-blade u32")
    }

    /// Reads back the vertex positions (vertex-major, xyz).
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when mapping fails.
    pub fn read_positions(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        read_buffer(device, queue, &self.pos, "positions")
    }
}

/// The packed per-cell state of `cells.wgsl`: level, no change, bent flag.
fn cell_state(lod: Lod, bent: bool) -> u32 {
    lod as u32 | (3 << 2) | (u32::from(bent) << 4)
}

/// `Vec3A`s as `[x, y, z, 0]`.
fn to_vec4(v: &[glam::Vec3A]) -> Vec<[f32; 4]> {
    v.iter().map(|p| [p.x, p.y, p.z, 0.0]).collect()
}
