//! Seeded generation of the field (DESIGN §2): blade roots jittered in their
//! cell slots on the terrain, height/width/lean jitter, a gently curved rest
//! shape, the neighbour table of Definition 6, patch boxes and cell state.

use super::blades::{BladeVertex, Blades, MAX_SEGMENTS};
use super::cells::Cells;
use super::field::Field;
use super::layout::{FieldLayout, NO_NEIGHBOUR, Patch};
use super::lod::Lod;
use super::maps::GrassMaps;
use super::params::{FieldError, FieldParams};
use super::rng::unit;
use super::terrain::Terrain;
use glam::{Vec3, Vec3A};
use rayon::prelude::*;

/// Height above the terrain kept by every vertex (the ground guard), metres.
pub const GROUND_CLEARANCE_M: f32 = 0.002;

/// Random stream of the density test (streams 0–6 are the shape's).
const DENSITY_STREAM: u64 = 7;

/// Per-blade shape parameters drawn from the seed.
#[derive(Clone, Copy)]
struct BladeShape {
    root: Vec3,
    seg_len: f32,
    lean: f32,
    azimuth: f32,
}

impl Field {
    /// Generates the field of `params` on `terrain` without grass maps
    /// (grass everywhere; see [`Field::generate_with_maps`]). Same
    /// parameters → same field, bit for bit, on any number of threads.
    pub fn generate(params: &FieldParams, terrain: Terrain) -> Result<Field, FieldError> {
        Field::generate_with_maps(params, terrain, &GrassMaps::default())
    }

    /// Generates the field of `params` on `terrain`, with `maps` deciding
    /// where blades grow, how tall and their tint ([`super::maps`]). Same
    /// parameters and maps → same field, bit for bit, on any number of
    /// threads; with the default maps, the same field as
    /// [`Field::generate`].
    pub fn generate_with_maps(
        params: &FieldParams,
        terrain: Terrain,
        maps: &GrassMaps,
    ) -> Result<Field, FieldError> {
        params.validate()?;
        let layout = make_layout(params);
        let count = layout.blade_count();
        let n = params.segments as usize;

        let shapes: Vec<BladeShape> = (0..count)
            .into_par_iter()
            .map(|b| draw_shape(params, &layout, &terrain, maps, b))
            .collect();

        let mut pos = vec![BladeVertex::default(); count * (n + 1)];
        pos.par_chunks_mut(count).enumerate().for_each(|(k, out)| {
            for (b, v) in out.iter_mut().enumerate() {
                *v = vertex(&shapes[b], k, n).into();
            }
        });
        let seg_len: Vec<f32> = shapes.iter().map(|s| s.seg_len).collect();
        let width = (0..count)
            .into_par_iter()
            .map(|b| {
                if seg_len[b] > 0.0 {
                    params.blade_width_m
                        * (1.0 + params.width_jitter * (2.0 * unit(params.seed, b as u64, 5) - 1.0))
                } else {
                    0.0
                }
            })
            .collect();
        let tint = (0..count)
            .into_par_iter()
            .map(|b| {
                let root = shapes[b].root;
                maps.tint_at(root.x, root.z)
                    .unwrap_or_else(|| unit(params.seed, b as u64, 6))
            })
            .collect();
        // The shapes (24 bytes a blade: 0.4 GB on the 16.8 M-blade herd)
        // are not needed past here: freed before `Blades::new` copies the
        // rest vertices, so that the build's peak is lower by their size.
        drop(shapes);
        let blades = Blades::new(n, pos, seg_len, width, tint);

        let mut layout = layout;
        layout.neighbours = neighbour_table(&layout, &blades);
        let patches = patch_boxes(&layout, &blades);
        layout.set_patches(patches);
        let cells = rest_cells(&layout, &blades, &terrain);
        let max_blade_length = blades.seg_len.iter().fold(0.0f32, |m, &l| m.max(l)) * n as f32;
        let absent_blades = (0..count).filter(|&b| !blades.is_present(b)).count() as u64;
        Ok(Field {
            params: params.clone(),
            layout,
            terrain,
            blades,
            cells,
            max_blade_length,
            absent_blades,
        })
    }
}

/// How many blades of `params` grow under `maps` (every one without a
/// density or height map that leaves some out): the count the memory
/// estimate needs, computed without generating the field (the same roots
/// and draws as [`Field::generate_with_maps`]).
#[must_use]
pub fn growing_blades(params: &FieldParams, maps: &GrassMaps) -> u64 {
    if maps.grows_everywhere() && maps.height.is_constant(1.0) {
        return params.blade_count();
    }
    let layout = make_layout(params);
    (0..layout.blade_count())
        .into_par_iter()
        .filter(|&b| {
            let (x, z) = root_xz(params, &layout, b);
            grows(params, maps, b, x, z) && maps.height_at(x, z) > 0.0
        })
        .count() as u64
}

fn make_layout(p: &FieldParams) -> FieldLayout {
    let [ex, ez] = p.extent_m();
    FieldLayout {
        patches: p.patches,
        cells_per_patch: p.cells_per_patch,
        blades_per_cell: p.blades_per_cell,
        cell_size: p.cell_size_m,
        origin: [-ex * 0.5, -ez * 0.5],
        patch_list: Vec::new(),
        patch_overhang_m: 0.0,
        strip_aabbs: Vec::new(),
        neighbours: Vec::new(),
    }
}

/// World (x, z) of blade `b`'s root: its slot in its cell, jittered.
fn root_xz(p: &FieldParams, layout: &FieldLayout, b: usize) -> (f32, f32) {
    let id = b as u64;
    let bpc = p.blades_per_cell as usize;
    let (cell, slot) = (b / bpc, b % bpc);
    let [gx, gz] = layout.cell_coord(cell);
    // Slots of a cell form a k×k grid; each blade is jittered inside its slot.
    let k = (bpc as f32).sqrt().ceil() as usize;
    let slot_size = p.cell_size_m / k as f32;
    let (sx, sz) = ((slot % k) as f32 + 0.5, (slot / k) as f32 + 0.5);
    let x = layout.origin[0]
        + gx as f32 * p.cell_size_m
        + sx * slot_size
        + p.position_jitter * slot_size * (unit(p.seed, id, 0) - 0.5);
    let z = layout.origin[1]
        + gz as f32 * p.cell_size_m
        + sz * slot_size
        + p.position_jitter * slot_size * (unit(p.seed, id, 1) - 0.5);
    (x, z)
}

/// Whether blade `b`, rooted at (x, z), passes the density test.
fn grows(p: &FieldParams, maps: &GrassMaps, b: usize, x: f32, z: f32) -> bool {
    unit(p.seed, b as u64, DENSITY_STREAM) < maps.density_at(x, z)
}

/// Root, length and lean of blade `b`; a blade that does not grow (density
/// test failed, or height factor 0) has length 0.
fn draw_shape(
    p: &FieldParams,
    layout: &FieldLayout,
    terrain: &Terrain,
    maps: &GrassMaps,
    b: usize,
) -> BladeShape {
    let id = b as u64;
    let (x, z) = root_xz(p, layout, b);
    let root = Vec3::new(x, terrain.height_at(x, z), z);
    let length = if grows(p, maps, b, x, z) {
        p.blade_height_m
            * maps.height_at(x, z)
            * (1.0 + p.height_jitter * (2.0 * unit(p.seed, id, 2) - 1.0))
    } else {
        0.0
    };
    let n = p.segments as usize;
    let mut shape = BladeShape {
        root,
        seg_len: length / n as f32,
        lean: p.lean_jitter_rad * unit(p.seed, id, 3),
        azimuth: std::f32::consts::TAU * unit(p.seed, id, 4),
    };
    if shape.seg_len <= 0.0 {
        shape.seg_len = 0.0;
        return shape;
    }
    // Ground guard at rest: on steep terrain, straighten the blade until every
    // vertex is above the ground.
    for _ in 0..8 {
        let ok = (1..=n).all(|i| {
            let v = vertex(&shape, i, n);
            v.y >= terrain.height_at(v.x, v.z) + GROUND_CLEARANCE_M
        });
        if ok {
            break;
        }
        shape.lean *= 0.5;
    }
    shape
}

/// Vertex `k` of a blade at rest: segment i leans `lean · i / n` from
/// vertical, so the blade curves a little more towards the tip.
fn vertex(s: &BladeShape, k: usize, n: usize) -> Vec3A {
    debug_assert!(n <= MAX_SEGMENTS);
    let (sin_az, cos_az) = s.azimuth.sin_cos();
    let mut v = s.root;
    for i in 1..=k {
        let (sa, ca) = (s.lean * i as f32 / n as f32).sin_cos();
        v += s.seg_len * Vec3::new(sa * cos_az, ca, sa * sin_az);
    }
    v.into()
}

/// Definition 6: for each blade, the blades in the same slot of the cells
/// immediately −x, +x, −z, +z of its cell (crossing patch borders). Blades
/// a grass map left out are no one's neighbours and have none: force does
/// not propagate across bare ground.
fn neighbour_table(layout: &FieldLayout, blades: &Blades) -> Vec<[u32; 4]> {
    let bpc = layout.blades_per_cell as usize;
    let [gw, gh] = layout.grid_size();
    (0..layout.blade_count())
        .into_par_iter()
        .map(|b| {
            let (cell, slot) = (b / bpc, b % bpc);
            let [gx, gz] = layout.cell_coord(cell);
            let at = |x: i64, z: i64| {
                if x < 0 || z < 0 || x >= i64::from(gw) || z >= i64::from(gh) {
                    return NO_NEIGHBOUR;
                }
                let nb = layout.cell_index(x as u32, z as u32) * bpc + slot;
                if blades.is_present(nb) {
                    nb as u32
                } else {
                    NO_NEIGHBOUR
                }
            };
            if !blades.is_present(b) {
                return [NO_NEIGHBOUR; 4];
            }
            let (x, z) = (i64::from(gx), i64::from(gz));
            [at(x - 1, z), at(x + 1, z), at(x, z - 1), at(x, z + 1)]
        })
        .collect()
}

/// Patch boxes: every blade vertex at rest, plus the length of the longest
/// blade upwards and sideways so a bent blade stays inside too.
fn patch_boxes(layout: &FieldLayout, blades: &Blades) -> Vec<Patch> {
    let per_patch = layout.cells_in_patch() * layout.blades_per_cell as usize;
    let [px, pz] = layout.patches;
    (0..(px * pz) as usize)
        .into_par_iter()
        .map(|p| {
            let first = p * per_patch;
            let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
            let mut longest = 0.0f32;
            for b in first..first + per_patch {
                let root = Vec3::from(blades.rest[b]);
                lo = lo.min(root);
                hi = hi.max(root);
                longest = longest.max(blades.seg_len[b] * blades.segments as f32);
            }
            Patch {
                coord: [p as u32 % px, p as u32 / px],
                aabb_min: lo - Vec3::new(longest, 0.0, longest),
                aabb_max: hi + Vec3::splat(longest),
                first_blade: first as u32,
                blades: per_patch as u32,
                first_cell: (p * layout.cells_in_patch()) as u32,
            }
        })
        .collect()
}

/// Cells at rest: billboard base on the ground at the cell centre, height =
/// mean rest chord |Vn − V0| of its growing blades, rest slope = mean unit
/// chord (a cell without grass: height 0, slope straight up).
fn rest_cells(layout: &FieldLayout, blades: &Blades, terrain: &Terrain) -> Cells {
    let bpc = layout.blades_per_cell as usize;
    let n = blades.segments;
    // Collected straight into the three arrays (no intermediate pairs: a
    // quarter of a GB on the 16.8 M-cell herd, alive beside the rest).
    let (base, (height, slope_origin)): (Vec<Vec3>, (Vec<f32>, Vec<Vec3>)) = (0..layout
        .cell_count())
        .into_par_iter()
        .map(|c| {
            let [gx, gz] = layout.cell_coord(c);
            let [x, z] = layout.cell_centre(gx, gz);
            let (mut h, mut dir, mut k) = (0.0, Vec3::ZERO, 0u32);
            for b in (c * bpc..(c + 1) * bpc).filter(|&b| blades.is_present(b)) {
                let chord = Vec3::from(blades.rest_vertex(b, n) - blades.rest_vertex(b, 0));
                h += chord.length();
                dir += chord.normalize_or(Vec3::Y);
                k += 1;
            }
            let rest = if k == 0 {
                (0.0, Vec3::Y)
            } else {
                (h / k as f32, dir / k as f32)
            };
            (Vec3::new(x, terrain.height_at(x, z), z), rest)
        })
        .collect();
    let patch_bounds: Vec<(Vec3, Vec3)> = base
        .chunks(layout.cells_in_patch())
        .map(|c| {
            c.iter()
                .fold((c[0], c[0]), |(lo, hi), b| (lo.min(*b), hi.max(*b)))
        })
        .collect();
    let strip_bounds = super::strips::strip_bounds(layout.patches, |p| patch_bounds[p]);
    Cells {
        lod: vec![Lod::Texture; layout.cell_count()],
        patch_lod: vec![Some(Lod::Texture); layout.patch_list.len()],
        strip_lod: vec![Some(Lod::Texture); strip_bounds.len()],
        last_classified: None,
        strip_bounds,
        patch_bounds,
        base,
        height,
        slope: slope_origin.clone(),
        slope_origin,
        flatness: vec![0.0; layout.cell_count()],
        changed: super::changes::ChangeSet::new(layout.cell_count()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> FieldParams {
        FieldParams {
            patches: [3, 2],
            cells_per_patch: 4,
            blades_per_cell: 2,
            ..FieldParams::default()
        }
    }

    #[test]
    fn layout_indices_round_trip() {
        let f = Field::generate(&small(), Terrain::Flat(0.0)).unwrap();
        let l = &f.layout;
        for c in 0..l.cell_count() {
            let [gx, gz] = l.cell_coord(c);
            assert_eq!(l.cell_index(gx, gz), c);
        }
        assert_eq!(f.blades.count, 3 * 2 * 16 * 2);
    }

    #[test]
    fn patches_are_contiguous_and_contain_their_blades() {
        let f = Field::generate(
            &small(),
            Terrain::Noise {
                amplitude: 0.3,
                wavelength: 2.0,
                seed: 2,
            },
        )
        .unwrap();
        let mut next = 0;
        for p in &f.layout.patch_list {
            assert_eq!(p.first_blade, next);
            next += p.blades;
            for b in p.first_blade..p.first_blade + p.blades {
                for k in 0..=f.blades.segments {
                    let v = Vec3::from(f.blades.vertex(b as usize, k));
                    assert!(v.cmpge(p.aabb_min).all() && v.cmple(p.aabb_max).all());
                }
            }
        }
        assert_eq!(next as usize, f.blades.count);
    }

    #[test]
    fn cells_overlapping_a_rectangle_are_exactly_those_it_touches() {
        let f = Field::generate(&small(), Terrain::Flat(0.0)).unwrap();
        let l = &f.layout;
        let (min, max) = ([-0.35, -0.12], [0.05, 0.21]);
        for p in 0..l.patch_list.len() {
            let got: Vec<usize> = l.patch_cells_overlapping(p, min, max).collect();
            let want: Vec<usize> = (0..l.cells_in_patch())
                .map(|i| p * l.cells_in_patch() + i)
                .filter(|&c| {
                    let [gx, gz] = l.cell_coord(c);
                    let x0 = l.origin[0] + gx as f32 * l.cell_size;
                    let z0 = l.origin[1] + gz as f32 * l.cell_size;
                    x0 <= max[0]
                        && x0 + l.cell_size >= min[0]
                        && z0 <= max[1]
                        && z0 + l.cell_size >= min[1]
                })
                .collect();
            assert_eq!(got, want, "patch {p}");
        }
        assert_eq!(
            l.patch_cells_overlapping(0, [50.0, 50.0], [60.0, 60.0])
                .count(),
            0
        );
        assert_eq!(
            l.patch_cells_overlapping(0, [f32::NAN; 2], [f32::NAN; 2])
                .count(),
            0
        );
    }

    #[test]
    fn neighbours_cross_patch_borders_and_are_symmetric() {
        let f = Field::generate(&small(), Terrain::Flat(0.0)).unwrap();
        let l = &f.layout;
        // Cell (3, 0) is the last column of patch 0; its +x neighbour is in patch 1.
        let b = l.cell_index(3, 0) * 2 + 1;
        let nb = l.neighbours[b][super::super::layout::POS_X] as usize;
        assert_eq!(nb, l.cell_index(4, 0) * 2 + 1);
        for (b, ns) in l.neighbours.iter().enumerate() {
            for (dir, &nb) in ns.iter().enumerate() {
                if nb != NO_NEIGHBOUR {
                    assert_eq!(
                        l.neighbours[nb as usize][dir ^ 1] as usize,
                        b,
                        "blade {b} dir {dir}"
                    );
                }
            }
        }
        // Border blades have missing neighbours.
        assert_eq!(l.neighbours[0][0], NO_NEIGHBOUR);
    }

    #[test]
    fn rest_shape_lengths_roots_and_ground() {
        let terrain = Terrain::Noise {
            amplitude: 0.5,
            wavelength: 1.5,
            seed: 9,
        };
        let f = Field::generate(&small(), terrain.clone()).unwrap();
        let bl = &f.blades;
        for b in 0..bl.count {
            let root = bl.vertex(b, 0);
            assert!((root.y - terrain.height_at(root.x, root.z)).abs() < 1e-5);
            for k in 1..=bl.segments {
                let (a, c) = (bl.vertex(b, k - 1), bl.vertex(b, k));
                assert!(((c - a).length() - bl.seg_len[b]).abs() < 1e-5 * bl.seg_len[b].max(1.0));
                assert!(c.y >= terrain.height_at(c.x, c.z));
            }
        }
    }

    #[test]
    fn same_seed_same_field_other_seed_other_field() {
        let a = Field::generate(&small(), Terrain::Flat(0.0)).unwrap();
        let b = Field::generate(&small(), Terrain::Flat(0.0)).unwrap();
        assert_eq!(a.blades.pos, b.blades.pos);
        let c = Field::generate(&FieldParams { seed: 2, ..small() }, Terrain::Flat(0.0)).unwrap();
        assert_ne!(a.blades.pos, c.blades.pos);
    }
}
