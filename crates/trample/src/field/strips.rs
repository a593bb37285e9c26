//! Strips of patches: a coarse level above patches, so that per-step work
//! over the whole field (level of detail, frustum culling) costs what the
//! distance bands and the frustum's sides cross, not what the field holds
//! (issue 16, item 1).
//!
//! A strip is a run of up to [`STRIP_PATCHES`] consecutive patches of one
//! row of patches (same `pz`). Because patches are stored row by row, a
//! strip's patches — and their cells and blades — are one contiguous range
//! in storage order, so a pass can hand each strip a slice; the strips of a
//! row are in storage order, the last one shorter when the row's length is
//! not a multiple of [`STRIP_PATCHES`].
//!
//! A strip's bounds are the component-wise min/max of its patches' bounds.
//! That makes the coarse tests exact, not only conservative: the distance
//! from a point to a box and a plane's signed distance of a box's corner are
//! monotone in the box's coordinates in floating point as in exact
//! arithmetic (each rounded step is monotone), so when a strip passes or
//! fails a test as a whole, every one of its patches would have given the
//! same answer on its own (tested against the per-patch passes).

use glam::Vec3;
use std::ops::Range;

/// Patches per strip. 16 patches of the default 3.2 m are 51 m: on a
/// 128 × 128-patch field that is 1,024 strips, so a settled step looks at
/// 1,024 boxes instead of 16,384, and a strip that a distance band or a
/// frustum plane cuts costs at most 16 patch tests.
pub const STRIP_PATCHES: usize = 16;

/// Strips in a row of `patches_x` patches.
#[must_use]
pub fn strips_per_row(patches_x: u32) -> usize {
    (patches_x as usize).div_ceil(STRIP_PATCHES)
}

/// The patch ranges of every strip of a field of `patches` (x, z) patches,
/// in storage order: row by row, left to right.
pub fn strip_ranges(patches: [u32; 2]) -> impl Iterator<Item = Range<usize>> {
    let (nx, nz) = (patches[0] as usize, patches[1] as usize);
    (0..nz).flat_map(move |z| {
        (0..nx)
            .step_by(STRIP_PATCHES)
            .map(move |x| z * nx + x..z * nx + (x + STRIP_PATCHES).min(nx))
    })
}

/// Bounds of every strip: the component-wise min/max of `bounds(p)` over its
/// patches `p` (see the module doc for why they are exactly that).
#[must_use]
pub fn strip_bounds(
    patches: [u32; 2],
    bounds: impl Fn(usize) -> (Vec3, Vec3),
) -> Vec<(Vec3, Vec3)> {
    strip_ranges(patches)
        .map(|r| {
            r.map(&bounds)
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), (a, b)| {
                    (lo.min(a), hi.max(b))
                })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_cover_every_patch_once_in_storage_order() {
        for patches in [[1, 1], [16, 2], [17, 3], [40, 5], [128, 2]] {
            let ranges: Vec<_> = strip_ranges(patches).collect();
            assert_eq!(
                ranges.len(),
                strips_per_row(patches[0]) * patches[1] as usize
            );
            let flat: Vec<usize> = ranges.iter().flat_map(Clone::clone).collect();
            let all: Vec<usize> = (0..(patches[0] * patches[1]) as usize).collect();
            assert_eq!(flat, all, "{patches:?}");
            assert!(
                ranges
                    .iter()
                    .all(|r| !r.is_empty() && r.len() <= STRIP_PATCHES)
            );
            // No strip crosses a row.
            let nx = patches[0] as usize;
            assert!(ranges.iter().all(|r| r.start / nx == (r.end - 1) / nx));
        }
    }
}
