//! The field's blades and cells on the GPU, in the CPU's layout (DESIGN §2,
//! Eq. 1): `pos[k * count + b]` is vertex k of blade b, blades patch-major,
//! the blades of a cell contiguous. The buffers stay on the GPU across
//! steps; reading back is for tests and dumps only.
//!
//! The vertex arrays are split into chunks of whole patches, each within
//! one storage binding ([`crate::chunk`]): `chunks[i].pos[k * blades + l]`
//! is vertex k of blade `first_blade + l`. The other per-blade arrays are
//! whole-field.

use bytemuck::{Pod, Zeroable};
use trample::field::{Blades, Field, Lod};
use wgpu::util::DeviceExt;

use crate::chunk::{GpuChunk, plan_chunks};
use crate::error::GpuError;
use crate::readback::read_buffer;

/// Per-blade output of the narrow phase: Σ EqF (Eq. 2) over the blade's hit
/// segments and all objects in xyz; in w Eq. 5's `num`: the hit count
/// (saturating at 255) for the paper's hit flags (`collide`), the contact
/// weight for the simulation (`collide_listed`). Layout-compatible with
/// `force` in `narrow_phase.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GpuForce {
    /// Σ EqF, world frame.
    pub force: [f32; 3],
    /// Eq. 5's `num`: a hit count (exact up to 255) or a contact weight.
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
    /// Blades per patch when the chunks are whole patches
    /// ([`GpuField::from_field`]); 0 for a field made by [`GpuField::new`].
    pub patch_blades: u32,
    /// Vertex and rest positions, in chunks of whole patches (one chunk
    /// when the field fits one storage binding): draw from `chunks[i].pos`.
    pub chunks: Vec<GpuChunk>,
    pub(crate) neighbours: wgpu::Buffer,
    /// Cells.
    pub cell_count: u32,
    /// Per cell: bits 0–1 level of detail, 2–3 level before this sub-step's
    /// change (3: none), bit 4 billboard bent, bit 5 cell computed at rest
    /// (track everywhere; see `cell.wgsl`).
    pub cell_state: wgpu::Buffer,
    /// Per cell: (base, billboard height), (slope_origin_b, 0).
    pub(crate) cell_rest: wgpu::Buffer,
    /// Per cell: current billboard slope `slope_b` (Eq. 8, 12), xyz.
    pub slope: wgpu::Buffer,
    /// Per cell: how flattened its blades are, in [0, 1]
    /// (`trample::field::Cells::flatness`, `follow.wgsl`), `f32`.
    pub flatness: wgpu::Buffer,
    pub(crate) force: wgpu::Buffer,
    /// Per blade, this sub-step: segment mask, the firmest single-object
    /// contact weight's bits, its owner, moved by contact (see
    /// `narrow_phase.wgsl`); `[u32; 4]`.
    pub(crate) touch: wgpu::Buffer,
    /// Per blade, between propagation's gather and commit passes
    /// (`propagation.wgsl`); `[u32; 4]`.
    pub(crate) next: wgpu::Buffer,
    /// Propagation's candidate lists (`propagation.wgsl`, `frontier`): two
    /// lengths and two unused words, two bits a blade, two lists of blade
    /// indices; `u32`, 12 bytes a blade.
    pub(crate) frontier: wgpu::Buffer,
    /// Generation per blade this sub-step (0 = DBG, 1… = PBG, 255 = none).
    pub generation: wgpu::Buffer,
    /// Per blade, as `u32`: bits 0–1 its `BladeClass` (0 untouched, 1 DBG,
    /// 2 PBG), bits 8–15 its track owner (`Simulation::track_owner`).
    pub class: wgpu::Buffer,
    /// 1 where a blade is away from rest (recovery works on those).
    pub(crate) displaced: wgpu::Buffer,
    /// The terrain's table for the ground guard ([`crate::terrain`]); flat
    /// at 0 for a field made by [`GpuField::new`].
    pub(crate) ground: wgpu::Buffer,
    /// The cells of one chunk coming back to geometry in a transitions pass
    /// (`transitions.wgsl`): their count, then their indices; `u32`, one
    /// word more than the largest chunk's cells (chunks take turns).
    pub(crate) back_cells: wgpu::Buffer,
    /// The blades of one chunk's listed patches that may touch an object in
    /// a narrow phase (`narrow_phase.wgsl`'s `list_blades`), then, in the
    /// contact response, those touched (`contact.wgsl`'s `list_touched`),
    /// and the blades the bend and the recovery work on
    /// (`active_list.wgsl`): their count, then their indices; `u32`, one
    /// word more than the largest chunk's blades (stages and chunks take
    /// turns, each list cleared first).
    pub(crate) near_blades: wgpu::Buffer,
}

impl GpuField {
    /// Uploads `field` (blades, cells with their levels, billboards and
    /// slopes, neighbour table), in chunks of whole patches as large as one
    /// storage binding allows.
    ///
    /// # Errors
    /// As [`GpuField::new`].
    pub fn from_field(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        field: &Field,
    ) -> Result<Self, GpuError> {
        Self::from_field_chunked(device, queue, field, None)
    }

    /// As [`GpuField::from_field`], each chunk's positions within
    /// `max_chunk_bytes` when given (and within the device's binding limit
    /// always): tests use it to chunk small fields.
    ///
    /// # Errors
    /// As [`GpuField::new`].
    pub fn from_field_chunked(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        field: &Field,
        max_chunk_bytes: Option<u64>,
    ) -> Result<Self, GpuError> {
        // Patches are contiguous and of one size: chunks are whole patches.
        let patch_blades = field.layout.cells_in_patch() as u32 * field.layout.blades_per_cell;
        let whole_patches = field
            .layout
            .patch_list
            .iter()
            .enumerate()
            .all(|(i, p)| p.first_blade == i as u32 * patch_blades && p.blades == patch_blades);
        if !whole_patches {
            return Err(GpuError::Layout(
                "patches of different sizes or out of order: chunks need whole patches".into(),
            ));
        }
        let mut out = Self::new_chunked(
            device,
            &field.blades,
            &field.cells.lod,
            field.layout.blades_per_cell,
            &field.layout.neighbours,
            patch_blades,
            max_chunk_bytes,
        )?;
        out.patch_blades = patch_blades;
        let ground = crate::terrain::table(
            &field.terrain,
            &field.layout,
            field.max_blade_length,
            Self::binding_limit(device),
        )?;
        out.ground = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("trample-gpu terrain"),
            contents: bytemuck::cast_slice(&ground),
            usage: wgpu::BufferUsages::STORAGE,
        });
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
    /// Chunks are cut between cells.
    ///
    /// # Errors
    /// [`GpuError::Layout`] when the cells do not cover the blades;
    /// [`GpuError::TooLarge`] when a whole-field array exceeds one storage
    /// binding.
    pub fn new(
        device: &wgpu::Device,
        blades: &Blades,
        lod: &[Lod],
        blades_per_cell: u32,
        neighbours: &[[u32; 4]],
    ) -> Result<Self, GpuError> {
        Self::new_chunked(
            device,
            blades,
            lod,
            blades_per_cell,
            neighbours,
            blades_per_cell,
            None,
        )
    }

    /// The largest of the step's arrays over the whole field (not chunked)
    /// for `blades` blades in `cells` cells, bytes, and what it is: the
    /// per-blade forces, contacts and propagation's next generation (16
    /// bytes a blade), the propagation's candidates (12 bytes a blade and
    /// 16), the cells' rest boxes (32 bytes a cell, the largest with one
    /// blade a cell).
    #[must_use]
    pub fn whole_field_binding(blades: u64, cells: u64) -> (u64, &'static str) {
        [
            (
                blades * 16,
                "the per-blade forces, contacts and next generation (16 bytes a blade, not chunked)",
            ),
            (
                12 * blades + 16,
                "the propagation's candidates (12 bytes a blade, not chunked)",
            ),
            (
                cells * 32,
                "the cells' rest boxes (32 bytes a cell, not chunked)",
            ),
        ]
        .into_iter()
        .max_by_key(|&(bytes, _)| bytes)
        .unwrap_or((0, ""))
    }

    /// The largest chunk of positions `device` can bind, bytes.
    #[must_use]
    pub fn binding_limit(device: &wgpu::Device) -> u64 {
        let l = device.limits();
        l.max_storage_buffer_binding_size.min(l.max_buffer_size)
    }

    /// As [`GpuField::new`], chunks cut at multiples of `unit` blades (a
    /// patch, or a cell) and each within `max_chunk_bytes` when given.
    ///
    /// # Errors
    /// As [`GpuField::new`]; [`GpuError::TooLarge`] also when one unit's
    /// positions exceed the chunk size.
    pub fn new_chunked(
        device: &wgpu::Device,
        blades: &Blades,
        lod: &[Lod],
        blades_per_cell: u32,
        neighbours: &[[u32; 4]],
        unit: u32,
        max_chunk_bytes: Option<u64>,
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
        let limit = Self::binding_limit(device);
        let (bytes, what) = Self::whole_field_binding(blades.count as u64, lod.len() as u64);
        if bytes > limit {
            return Err(GpuError::TooLarge { what, bytes, limit });
        }
        let verts = blades.segments as u32 + 1;
        let plan = plan_chunks(
            blades.count as u32,
            verts,
            unit,
            max_chunk_bytes.map_or(limit, |m| m.min(limit)),
        )?;
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
        };
        use wgpu::BufferUsages as U;
        let state: Vec<u32> = lod.iter().map(|&l| cell_state(l, false)).collect();
        let max_groups = device.limits().max_compute_workgroups_per_dimension;
        let units = blades.count as u32 / unit.max(1);
        let chunks: Vec<GpuChunk> = plan
            .into_iter()
            .enumerate()
            .map(|(i, r)| {
                let (params, groups, cell_groups) = GpuChunk::params(
                    r.start,
                    r.end - r.start,
                    blades_per_cell,
                    max_groups,
                    units + i as u32,
                    unit,
                );
                // Vertex 0 (the root, never moved) of `pos` and of `rest`
                // carries the blade's segment length in w (the stages read it
                // there: one storage binding fewer).
                let mut rest = chunk_vec4(&blades.rest, blades.count, verts, r.clone());
                let mut pos = chunk_vec4(&blades.pos, blades.count, verts, r.clone());
                for ((x, p), &l) in rest
                    .iter_mut()
                    .zip(pos.iter_mut())
                    .zip(&blades.seg_len[r.start as usize..r.end as usize])
                {
                    x[3] = l;
                    p[3] = l;
                }
                GpuChunk {
                    first_blade: r.start,
                    blades: r.end - r.start,
                    first_cell: params.range[2],
                    cells: params.range[3],
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
                    uniform: init("trample-gpu chunk", bytemuck::bytes_of(&params), U::UNIFORM),
                    groups,
                    cell_groups,
                }
            })
            .collect();
        let cells = lod.len() as u64;
        let chunk_cells = chunks.iter().map(|c| c.cells).max().unwrap_or(0);
        let chunk_blades = chunks.iter().map(|c| c.blades).max().unwrap_or(0);
        Ok(Self {
            near_blades: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu blades near an object"),
                size: (1 + u64::from(chunk_blades)) * 4,
                usage: U::STORAGE | U::COPY_DST,
                mapped_at_creation: false,
            }),
            back_cells: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu cells coming back to geometry"),
                size: (1 + u64::from(chunk_cells)) * 4,
                usage: U::STORAGE | U::COPY_DST,
                mapped_at_creation: false,
            }),
            count: blades.count as u32,
            segments: blades.segments as u32,
            blades_per_cell,
            patch_blades: 0,
            chunks,
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
                U::STORAGE | U::COPY_SRC | U::COPY_DST,
            ),
            // A blade away from rest is displaced: recovery works on it.
            displaced: init(
                "trample-gpu displaced flags",
                bytemuck::cast_slice(
                    &(0..blades.count)
                        .map(|b| u32::from(!blades.is_at_rest(b)))
                        .collect::<Vec<u32>>(),
                ),
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
            flatness: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu cell flatness"),
                size: cells * 4,
                usage: U::STORAGE | U::COPY_DST | U::COPY_SRC,
                mapped_at_creation: false,
            }),
            force: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu blade forces"),
                size: blades.count as u64 * 16,
                usage: U::STORAGE | U::COPY_SRC | U::COPY_DST,
                mapped_at_creation: false,
            }),
            ground: init(
                "trample-gpu terrain",
                bytemuck::cast_slice(&[0.0f32; 16]),
                U::STORAGE,
            ),
            touch: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu blade contacts"),
                size: blades.count as u64 * 16,
                usage: U::STORAGE | U::COPY_SRC | U::COPY_DST,
                mapped_at_creation: false,
            }),
            next: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu propagation next"),
                size: blades.count as u64 * 16,
                usage: U::STORAGE | U::COPY_DST,
                mapped_at_creation: false,
            }),
            frontier: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("trample-gpu propagation candidates"),
                size: (4 + 3 * blades.count as u64) * 4,
                usage: U::STORAGE,
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
    /// hit, or touched, one of the objects).
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when mapping fails.
    pub fn read_hit_masks(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<u32>, GpuError> {
        let touch: Vec<[u32; 4]> = read_buffer(device, queue, &self.touch, "contacts")?;
        Ok(touch.iter().map(|t| t[0]).collect())
    }

    /// Reads back the cells' flatness (`follow.wgsl`).
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when mapping fails.
    pub fn read_flatness(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<f32>, GpuError> {
        read_buffer(device, queue, &self.flatness, "flatness")
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

    /// Reads back the vertex positions of every chunk into the CPU's
    /// whole-field vertex-major layout (`[k * count + b]`, xyz; w as stored).
    ///
    /// # Errors
    /// [`GpuError::ReadBack`] when mapping fails.
    pub fn read_positions(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<[f32; 4]>, GpuError> {
        let count = self.count as usize;
        let verts = self.segments as usize + 1;
        let mut out = vec![[0.0; 4]; count * verts];
        for c in &self.chunks {
            let part: Vec<[f32; 4]> = read_buffer(device, queue, &c.pos, "positions")?;
            let (first, n) = (c.first_blade as usize, c.blades as usize);
            for k in 0..verts {
                out[k * count + first..k * count + first + n]
                    .copy_from_slice(&part[k * n..(k + 1) * n]);
            }
        }
        Ok(out)
    }
}

/// The packed per-cell state of `cells.wgsl`: level, no change, bent flag.
fn cell_state(lod: Lod, bent: bool) -> u32 {
    lod as u32 | (3 << 2) | (u32::from(bent) << 4)
}

/// The vertices of blades `range` of a whole-field vertex-major array
/// (`count` blades of `verts` vertices) as one chunk's vertex-major
/// `[x, y, z, 0]`s.
fn chunk_vec4(
    v: &[trample::field::BladeVertex],
    count: usize,
    verts: u32,
    range: std::ops::Range<u32>,
) -> Vec<[f32; 4]> {
    let (a, b) = (range.start as usize, range.end as usize);
    (0..verts as usize)
        .flat_map(|k| &v[k * count + a..k * count + b])
        .map(|p| [p.pos[0], p.pos[1], p.pos[2], 0.0])
        .collect()
}
