//! Level of detail per cell (paper §3.1, Fig. 1; DESIGN §2).

use serde::{Deserialize, Serialize};

/// Distances that choose each cell's representation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LodParams {
    /// Cells nearer than this (metres, from the viewpoint to the cell centre)
    /// are geometric blades. Default 12: close enough that a 2-core CPU can
    /// simulate them, far enough to see the track form.
    pub geometry_m: f32,
    /// Cells nearer than this (and not geometric) are billboards; beyond, the
    /// ground texture. Default 30.
    pub billboard_m: f32,
}

impl Default for LodParams {
    fn default() -> Self {
        Self {
            geometry_m: 12.0,
            billboard_m: 30.0,
        }
    }
}

/// A `[lod]` value out of range. The message names the key.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LodError {
    /// `geometry_m` negative, NaN or infinite.
    #[error("lod.geometry_m = {geometry_m}: must be a finite distance >= 0 metres")]
    Geometry {
        /// The value given.
        geometry_m: f32,
    },
    /// `billboard_m` NaN.
    #[error(
        "lod.billboard_m = NaN: must be a distance >= lod.geometry_m = {geometry_m} metres (inf allowed)"
    )]
    BillboardNaN {
        /// `geometry_m`, the least it may be.
        geometry_m: f32,
    },
    /// `billboard_m` below `geometry_m`.
    #[error(
        "lod.billboard_m = {billboard_m} is less than lod.geometry_m = {geometry_m}: LOD distances must not decrease"
    )]
    Decreasing {
        /// The value given.
        billboard_m: f32,
        /// `geometry_m`.
        geometry_m: f32,
    },
}

impl LodParams {
    /// Checks both distances: `0 ≤ geometry_m ≤ billboard_m`, `geometry_m`
    /// finite (`billboard_m` may be infinite: billboards to the horizon).
    ///
    /// # Errors
    /// [`LodError`] naming the key.
    pub fn validate(&self) -> Result<(), LodError> {
        let (geometry_m, billboard_m) = (self.geometry_m, self.billboard_m);
        if !(geometry_m.is_finite() && geometry_m >= 0.0) {
            return Err(LodError::Geometry { geometry_m });
        }
        if billboard_m.is_nan() {
            return Err(LodError::BillboardNaN { geometry_m });
        }
        if billboard_m < geometry_m {
            return Err(LodError::Decreasing {
                billboard_m,
                geometry_m,
            });
        }
        Ok(())
    }

    /// The blend bands a renderer draws between these levels of detail
    /// (ours, DESIGN §8 "blend in a band"), metres: `[near, far]` for the
    /// asked widths `near_m` (past `geometry_m`: the blades of
    /// Billboard-LOD cells thin out as the billboards fade in) and `far_m`
    /// (before `billboard_m`: the billboards thin out over the ground).
    /// Each is at most half the billboard band (`billboard_m −
    /// geometry_m`), so the two never overlap; a non-finite or negative
    /// width gives 0 (no band: the paper's hard switch). trample-render
    /// and bevy_trample both draw with these.
    #[must_use]
    pub fn blend_bands(&self, near_m: f32, far_m: f32) -> [f32; 2] {
        let room = if self.billboard_m.is_finite() {
            0.5 * (self.billboard_m - self.geometry_m).max(0.0)
        } else {
            f32::INFINITY
        };
        let clean = |m: f32| {
            if m.is_finite() && m > 0.0 {
                m.min(room)
            } else {
                0.0
            }
        };
        [clean(near_m), clean(far_m)]
    }
}

/// Representation of a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum Lod {
    /// Geometric blades (DBG/PBG can happen here).
    Geometry = 0,
    /// One billboard (BBG).
    Billboard = 1,
    /// Ground texture only: no animation.
    Texture = 2,
}

use super::cells::Cells;
use super::changes::ChangeSet;
use super::layout::FieldLayout;
use super::strips::{STRIP_PATCHES, strips_per_row};
use glam::Vec3;
use rayon::prelude::*;

/// A cell whose level of detail changed this step (input of the transitions, Eq. 9–13).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LodChange {
    /// Cell index (storage order).
    pub cell: u32,
    /// Level before.
    pub from: Lod,
    /// Level now.
    pub to: Lod,
}

/// How many cells are at each level.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct LodCounts {
    /// Cells drawn as geometric blades.
    pub geometry: u32,
    /// Cells drawn as billboards.
    pub billboard: u32,
    /// Cells drawn as ground texture.
    pub texture: u32,
}

impl LodParams {
    /// Level of a cell whose centre is `distance` metres from the viewpoint.
    #[must_use]
    pub fn level(&self, distance: f32) -> Lod {
        self.level_squared(distance * distance)
    }

    /// [`Self::level`] from the squared distance (no square root per cell).
    #[must_use]
    pub fn level_squared(&self, distance_sq: f32) -> Lod {
        if distance_sq < self.geometry_m * self.geometry_m {
            Lod::Geometry
        } else if distance_sq < self.billboard_m * self.billboard_m {
            Lod::Billboard
        } else {
            Lod::Texture
        }
    }
}

/// Sets every cell's level from its centre's distance to `viewpoint`
/// (paper Fig. 1) and appends the cells that changed level to `changes`, in
/// storage order. Strips of patches ([`super::strips`]) and patches wholly
/// inside one distance band are settled without visiting their cells, so
/// the cost follows the band edges, not the field size: on a 128 × 128-patch
/// field a settled step looks at 1,024 strip boxes. The same viewpoint and
/// distances as the last call cost nothing (`Cells::last_classified`). The
/// result is the same, bit for bit, as [`classify_cells_by_patch`]'s, which
/// visits every patch (tested).
pub fn classify_cells(
    layout: &FieldLayout,
    cells: &mut Cells,
    viewpoint: Vec3,
    params: &LodParams,
    changes: &mut Vec<LodChange>,
) -> LodCounts {
    if let Some((v, p, counts)) = &cells.last_classified
        && *v == viewpoint
        && p == params
    {
        return *counts;
    }
    let per_patch = layout.cells_in_patch();
    let row_patches = layout.patches[0] as usize;
    let row_strips = strips_per_row(layout.patches[0]);
    let strip_cells = STRIP_PATCHES * per_patch;
    let Cells {
        lod,
        base,
        patch_lod,
        patch_bounds,
        strip_lod,
        strip_bounds,
        ..
    } = cells;
    // Parallel over rows of patches, each a contiguous range of cells;
    // within a row, strip by strip.
    let results: Vec<(LodCounts, Vec<LodChange>)> = lod
        .par_chunks_mut(row_patches * per_patch)
        .zip(base.par_chunks(row_patches * per_patch))
        .zip(patch_lod.par_chunks_mut(row_patches))
        .zip(patch_bounds.par_chunks(row_patches))
        .zip(strip_lod.par_chunks_mut(row_strips))
        .zip(strip_bounds.par_chunks(row_strips))
        .enumerate()
        .map(
            |(row, (((((lod, base), uniform), bounds), s_uniform), s_bounds))| {
                let mut counts = LodCounts::default();
                let mut local = Vec::new();
                let strips = lod
                    .chunks_mut(strip_cells)
                    .zip(base.chunks(strip_cells))
                    .zip(uniform.chunks_mut(STRIP_PATCHES))
                    .zip(bounds.chunks(STRIP_PATCHES))
                    .zip(s_uniform.iter_mut().zip(s_bounds));
                for (s, ((((lod, base), uniform), bounds), (s_uniform, &s_bounds))) in
                    strips.enumerate()
                {
                    let band = band_of(viewpoint, s_bounds, params);
                    if let Some(level) = band.filter(|l| *s_uniform == Some(*l)) {
                        add(&mut counts, level, lod.len() as u32);
                        continue;
                    }
                    let first_patch = row * row_patches + s * STRIP_PATCHES;
                    let patches = lod
                        .chunks_mut(per_patch)
                        .zip(base.chunks(per_patch))
                        .zip(uniform.iter_mut().zip(bounds));
                    for (i, ((lod, base), (uniform, &bounds))) in patches.enumerate() {
                        let first = (first_patch + i) * per_patch;
                        let patch = PatchCells {
                            lod,
                            base,
                            uniform,
                            bounds,
                            first,
                        };
                        classify_patch(patch, viewpoint, params, &mut counts, &mut local);
                    }
                    let shared = uniform[0];
                    *s_uniform = shared.filter(|_| uniform.iter().all(|u| *u == shared));
                }
                (counts, local)
            },
        )
        .collect();
    let counts = merge(results, &mut cells.changed, changes);
    cells.last_classified = Some((viewpoint, params.clone(), counts));
    counts
}

/// [`classify_cells`] visiting every patch (no strips): the reference it is
/// tested against, and what it did before strips (issue 16). Leaves the
/// strips' shared levels as they were: do not mix it with
/// [`classify_cells`] on the same cells.
pub fn classify_cells_by_patch(
    layout: &FieldLayout,
    cells: &mut Cells,
    viewpoint: Vec3,
    params: &LodParams,
    changes: &mut Vec<LodChange>,
) -> LodCounts {
    let per_patch = layout.cells_in_patch();
    cells.last_classified = None;
    let results: Vec<(LodCounts, Vec<LodChange>)> = cells
        .lod
        .par_chunks_mut(per_patch)
        .zip(cells.base.par_chunks(per_patch))
        .zip(cells.patch_lod.par_iter_mut())
        .zip(cells.patch_bounds.par_iter())
        .enumerate()
        .map(|(p, (((lod, base), uniform), &bounds))| {
            let (mut counts, mut local) = (LodCounts::default(), Vec::new());
            let first = p * per_patch;
            let patch = PatchCells {
                lod,
                base,
                uniform,
                bounds,
                first,
            };
            classify_patch(patch, viewpoint, params, &mut counts, &mut local);
            (counts, local)
        })
        .collect();
    merge(results, &mut cells.changed, changes)
}

/// The level of every point of the box `bounds` (min, max) seen from
/// `viewpoint`, if they all share one: the nearest and the farthest point
/// of the box are in the same distance band.
fn band_of(viewpoint: Vec3, (lo, hi): (Vec3, Vec3), params: &LodParams) -> Option<Lod> {
    let near = viewpoint.clamp(lo, hi).distance(viewpoint);
    let far = (viewpoint - lo).abs().max((viewpoint - hi).abs()).length();
    let (l_near, l_far) = (params.level(near), params.level(far));
    (l_near == l_far).then_some(l_near)
}

/// One patch's cells for [`classify_patch`].
struct PatchCells<'a> {
    lod: &'a mut [Lod],
    base: &'a [Vec3],
    /// The level all its cells share, if any.
    uniform: &'a mut Option<Lod>,
    /// Bounds of its cells' base centres.
    bounds: (Vec3, Vec3),
    /// Storage index of its first cell.
    first: usize,
}

/// Levels of one patch's cells: settled without visiting them when the
/// whole patch is in one band and already at that level, else cell by cell.
fn classify_patch(
    patch: PatchCells<'_>,
    viewpoint: Vec3,
    params: &LodParams,
    counts: &mut LodCounts,
    changes: &mut Vec<LodChange>,
) {
    let PatchCells {
        lod,
        base,
        uniform,
        bounds,
        first,
    } = patch;
    let band = band_of(viewpoint, bounds, params);
    if let Some(level) = band.filter(|l| *uniform == Some(*l)) {
        add(counts, level, lod.len() as u32);
        return;
    }
    for (i, (l, b)) in lod.iter_mut().zip(base).enumerate() {
        let new = band.unwrap_or_else(|| params.level_squared(b.distance_squared(viewpoint)));
        if new != *l {
            changes.push(LodChange {
                cell: (first + i) as u32,
                from: *l,
                to: new,
            });
            *l = new;
        }
        add(counts, new, 1);
    }
    *uniform = band;
}

/// Sums the counts and concatenates the changes of each part, in order;
/// marks the changed cells in `changed` ([`super::Field::changed_cells`]).
fn merge(
    results: Vec<(LodCounts, Vec<LodChange>)>,
    changed: &mut ChangeSet,
    changes: &mut Vec<LodChange>,
) -> LodCounts {
    let mut total = LodCounts::default();
    // One allocation, not a doubling per part: a camera that jumps changes
    // half a million cells at once.
    changes.reserve(results.iter().map(|(_, l)| l.len()).sum());
    for (c, local) in results {
        total.geometry += c.geometry;
        total.billboard += c.billboard;
        total.texture += c.texture;
        changed.mark_all(local.iter().map(|ch| ch.cell as usize));
        changes.extend(local);
    }
    total
}

fn add(c: &mut LodCounts, l: Lod, k: u32) {
    match l {
        Lod::Geometry => c.geometry += k,
        Lod::Billboard => c.billboard += k,
        Lod::Texture => c.texture += k,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::{Field, FieldParams, Terrain};

    #[test]
    fn blend_bands_fit_in_half_the_billboard_band_and_bad_widths_give_none() {
        let lod = LodParams {
            geometry_m: 12.0,
            billboard_m: 30.0,
        };
        assert_eq!(lod.blend_bands(4.0, 6.0), [4.0, 6.0]);
        // Half the billboard band (9 m) at most: the two never overlap.
        assert_eq!(lod.blend_bands(20.0, 12.0), [9.0, 9.0]);
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            assert_eq!(lod.blend_bands(bad, bad), [0.0, 0.0], "{bad}");
        }
        // Billboards to the horizon: any finite width.
        let far = LodParams {
            geometry_m: 12.0,
            billboard_m: f32::INFINITY,
        };
        assert_eq!(far.blend_bands(40.0, 7.0), [40.0, 7.0]);
        // No billboard band: no blend band.
        let none = LodParams {
            geometry_m: 12.0,
            billboard_m: 12.0,
        };
        assert_eq!(none.blend_bands(4.0, 6.0), [0.0, 0.0]);
    }

    #[test]
    fn levels_follow_distance_and_changes_are_reported() {
        let p = FieldParams {
            patches: [4, 4],
            cells_per_patch: 8,
            ..FieldParams::default()
        };
        let mut f = Field::generate(&p, Terrain::Flat(0.0)).unwrap();
        let lod = LodParams {
            geometry_m: 0.5,
            billboard_m: 1.2,
        };
        let mut changes = Vec::new();
        let eye = Vec3::new(0.3, 1.0, -0.4);
        let counts = classify_cells(&f.layout, &mut f.cells, eye, &lod, &mut changes);
        assert_eq!(
            (counts.geometry + counts.billboard + counts.texture) as usize,
            f.layout.cell_count()
        );
        for c in 0..f.layout.cell_count() {
            assert_eq!(
                f.cells.lod[c],
                lod.level(f.cells.base[c].distance(eye)),
                "cell {c}"
            );
        }
        // Everything started as texture: the changes are exactly the non-texture cells.
        assert_eq!(changes.len() as u32, counts.geometry + counts.billboard);
        assert!(changes.windows(2).all(|w| w[0].cell < w[1].cell));
        // Same viewpoint again: nothing changes.
        changes.clear();
        let again = classify_cells(&f.layout, &mut f.cells, eye, &lod, &mut changes);
        assert_eq!(again, counts);
        assert!(changes.is_empty());
        // Move away: every cell becomes texture, and each change is reported once.
        let far = Vec3::new(100.0, 0.0, 0.0);
        classify_cells(&f.layout, &mut f.cells, far, &lod, &mut changes);
        assert_eq!(changes.len() as u32, counts.geometry + counts.billboard);
        assert!(
            changes
                .iter()
                .all(|c| c.to == Lod::Texture && c.from != Lod::Texture)
        );
    }
}
