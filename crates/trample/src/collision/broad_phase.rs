//! The broad phase: which patches an object may touch (paper §4 stage 2:
//! "Perform intersection tests between dynamic object and patches. Only
//! patches that intersect with object are taken into account"; DESIGN §4.1).
//!
//! The object's root OBB, moved to the world, against each patch's AABB
//! (which includes the blades' maximum height), by the separating axis
//! theorem on the 15 candidate axes (Gottschalk et al., *OBBTree*, 1996;
//! C. Ericson, *Real-Time Collision Detection*, 2005, §4.4.1).
//!
//! Which patches to test is a grid lookup (issue 16, item 1): the root box's
//! world extent in x and z, widened by how far a patch's box reaches beyond
//! its square, is a rectangle of patches ([`patch_rect`]); only those meet
//! the SAT test ([`patches_under`]). The cost follows what the objects
//! cover, not patches × objects. [`patches_hit`], which tests every patch,
//! is the reference the lookup is tested against (same lists, bit for bit).

use glam::{Quat, Vec3};

use crate::field::{FieldLayout, Patch};
use crate::obb::Obb;
use crate::object::Pose;

/// Added to every `|R_ij|` of the SAT (Ericson §4.4.1): when an OBB edge is
/// parallel to an AABB edge their cross product is ~0 and, unpadded, its
/// rounding could report a false separation.
pub const PARALLEL_PAD: f32 = 1e-6;

/// Relative slack of every SAT comparison (of the sum of projected radii),
/// so that boxes that touch, or overlap by a rounding error, count as
/// overlapping: the broad phase must be conservative.
pub const REL_SLACK: f32 = 1e-5;

/// The object-local box `local` moved to the world by `pose` (rotation and
/// translation; the half extents are unchanged). A rotation that is not unit
/// length is normalised first; one that cannot be (zero, non-finite) is
/// taken as the identity.
#[must_use]
#[inline]
pub fn world_obb(local: &Obb, pose: &Pose) -> Obb {
    let len = pose.rotation.length();
    let rotation = if len > 0.0 && len.is_finite() {
        pose.rotation / len
    } else {
        Quat::IDENTITY
    };
    Obb {
        center: pose.position + rotation * local.center,
        axes: local.axes.map(|a| rotation * a),
        half: local.half,
    }
}

/// True when `obb` and the axis-aligned box `min..max` overlap or touch
/// (world frame): no separating axis among the 3 AABB axes, the 3 OBB axes
/// and their 9 cross products. Conservative: parallel edges are padded
/// (`PARALLEL_PAD`) and each comparison has a relative slack
/// (`REL_SLACK`). An inverted AABB (`min > max` on some axis) or a
/// non-finite input gives `false`.
#[must_use]
pub fn obb_overlaps_aabb(obb: &Obb, min: Vec3, max: Vec3) -> bool {
    obb_aabb_sat(obb, min, max, true)
}

/// [`obb_overlaps_aabb`] on the six face axes only (the 3 AABB axes and
/// the 3 OBB axes, not their 9 cross products): cheaper and looser — it
/// may report an overlap the full test separates on an edge axis, never a
/// separation the full test would not find. For pruning, where a false
/// "overlap" only costs work (the narrow phase's tile test).
#[must_use]
pub fn obb_may_overlap_aabb(obb: &Obb, min: Vec3, max: Vec3) -> bool {
    obb_aabb_sat(obb, min, max, false)
}

/// The face axes of the separating-axis test: no separation along the 3
/// AABB axes and the 3 OBB axes (`axes`) between a box of half extents `b`
/// along `axes` and an AABB of half extents `a`, the OBB's centre at `t`
/// from the AABB's. With padding and slack (see [`obb_overlaps_aabb`]); a
/// NaN anywhere separates nothing.
#[inline]
fn face_axes_overlap(axes: &[Vec3; 3], b: Vec3, a: Vec3, t: Vec3) -> bool {
    let separated = |dist: f32, ra: f32, rb: f32| dist.abs() > (ra + rb) * (1.0 + REL_SLACK);
    // Three at a time: the OBB axes' absolute components (padded), `|B_j| +
    // pad`, component i being `|e_i · B_j| + pad`.
    let [u, v, w] = *axes;
    let pad = Vec3::splat(PARALLEL_PAD);
    let abs_axes = [u.abs() + pad, v.abs() + pad, w.abs() + pad];
    // AABB axes e_i: the OBB's radius along each, summed over j in order.
    let rb = abs_axes[0] * b.x + abs_axes[1] * b.y + abs_axes[2] * b.z;
    if t.abs().cmpgt((a + rb) * (1.0 + REL_SLACK)).any() {
        return false;
    }
    // OBB axes B_j.
    for (j, axis) in axes.iter().enumerate() {
        if separated(t.dot(*axis), a.dot(abs_axes[j]), b[j]) {
            return false;
        }
    }
    true
}

/// An axis-aligned box made ready for [`obb_may_overlap_aabb`] against many
/// boxes (a walk down a tree): checked once, its centre and half extents
/// computed once.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AabbFaces {
    mid: Vec3,
    half: Vec3,
}

impl AabbFaces {
    /// `None` for a non-finite or inverted box (no overlap with anything).
    pub(crate) fn new(min: Vec3, max: Vec3) -> Option<Self> {
        (min.is_finite() && max.is_finite() && !min.cmpgt(max).any()).then(|| Self {
            mid: (min + max) * 0.5,
            half: (max - min) * 0.5,
        })
    }

    /// [`obb_may_overlap_aabb`] of `obb` grown by `grow` on each half
    /// extent, for a finite `obb` (the same answer bit for bit); a
    /// non-finite `obb` may be called overlapping, which only costs a
    /// walk work.
    #[inline]
    pub(crate) fn may_overlap(&self, obb: &Obb, grow: f32) -> bool {
        face_axes_overlap(
            &obb.axes,
            obb.half + Vec3::splat(grow),
            self.half,
            obb.center - self.mid,
        )
    }
}

/// The separating-axis test of [`obb_overlaps_aabb`]; the 9 edge axes
/// only when `edges`.
fn obb_aabb_sat(obb: &Obb, min: Vec3, max: Vec3, edges: bool) -> bool {
    let finite = obb.center.is_finite()
        && obb.half.is_finite()
        && obb.axes.iter().all(|a| a.is_finite())
        && min.is_finite()
        && max.is_finite();
    if !finite || min.cmpgt(max).any() {
        return false;
    }
    let a = (max - min) * 0.5; // AABB half extents
    let b = obb.half;
    let t = obb.center - (min + max) * 0.5; // in the AABB (= world) frame
    let separated = |dist: f32, ra: f32, rb: f32| dist.abs() > (ra + rb) * (1.0 + REL_SLACK);
    if !face_axes_overlap(&obb.axes, b, a, t) {
        return false;
    }
    if !edges {
        return true;
    }
    // r[i][j] = e_i · B_j, the OBB axes in the AABB frame.
    let r: [[f32; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| obb.axes[j][i]));
    let ar: [[f32; 3]; 3] = r.map(|row| row.map(|x| x.abs() + PARALLEL_PAD));
    // Cross products e_i × B_j.
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let ra = a[i1] * ar[i2][j] + a[i2] * ar[i1][j];
            let rb = b[j1] * ar[i][j2] + b[j2] * ar[i][j1];
            let dist = t[i2] * r[i1][j] - t[i1] * r[i2][j];
            if separated(dist, ra, rb) {
                return false;
            }
        }
    }
    true
}

/// Writes to `out` (cleared first) the indices, ascending, of the patches
/// whose AABB overlaps `world_root`, the object's root OBB in the world
/// frame ([`world_obb`]): paper §4 stage 2, DESIGN §4.1. Reuses `out`'s
/// allocation. Tests every patch: the reference of [`patches_under`],
/// which finds the same list at the cost of the patches under the box.
pub fn patches_hit(patches: &[Patch], world_root: &Obb, out: &mut Vec<u32>) {
    out.clear();
    out.extend(
        patches
            .iter()
            .enumerate()
            .filter(|(_, p)| obb_overlaps_aabb(world_root, p.aabb_min, p.aabb_max))
            .map(|(i, _)| i as u32),
    );
}

/// A rectangle of patches, inclusive: `x[0] ..= x[1]` by `z[0] ..= z[1]`
/// (patch coordinates).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PatchRect {
    /// First and last patch column.
    pub x: [u32; 2],
    /// First and last patch row.
    pub z: [u32; 2],
}

impl PatchRect {
    /// Number of patches in the rectangle (≥ 1: an empty one is `None` in
    /// [`patch_rect`]).
    #[must_use]
    pub fn patch_count(&self) -> usize {
        (self.x[1] - self.x[0] + 1) as usize * (self.z[1] - self.z[0] + 1) as usize
    }

    /// The patch indices of the rectangle, ascending (storage order).
    pub fn patches(&self, patches_x: u32) -> impl Iterator<Item = u32> + '_ {
        (self.z[0]..=self.z[1])
            .flat_map(move |z| (self.x[0]..=self.x[1]).map(move |x| z * patches_x + x))
    }
}

/// Relative widening of the lookup rectangle: ten times the SAT's
/// [`REL_SLACK`] (the GPU path tests with twice it), so that every patch the
/// slack lets through, and every rounding of the lookup's own arithmetic
/// (a few ulps of the coordinates), is inside the rectangle.
pub const LOOKUP_SLACK: f32 = 10.0 * REL_SLACK;

/// The patches whose box may meet `world_root` (world frame), found on the
/// grid without visiting the others: those whose square, grown by
/// `layout.patch_overhang_m`, meets the box's world x–z extent, widened by
/// [`LOOKUP_SLACK`]. A superset of the patches [`obb_overlaps_aabb`]
/// accepts (with up to ten times its slack); `None` when it is empty (the
/// box is off the field) or the box is not finite. Cost O(1).
#[must_use]
pub fn patch_rect(layout: &FieldLayout, world_root: &Obb) -> Option<PatchRect> {
    let o = world_root;
    let finite = o.center.is_finite() && o.half.is_finite() && o.axes.iter().all(|a| a.is_finite());
    if !finite {
        return None;
    }
    // World half extent along x and z, as the SAT's first axes measure it.
    let reach = |i: usize| {
        (0..3)
            .map(|j| o.half[j] * (o.axes[j][i].abs() + PARALLEL_PAD))
            .sum::<f32>()
    };
    let size = layout.patch_size();
    let range = |i: usize, origin: f32, count: u32| -> Option<[u32; 2]> {
        let (c, r) = (o.center[i], reach(i));
        let margin = layout.patch_overhang_m
            + LOOKUP_SLACK * (r + size + layout.patch_overhang_m + c.abs() + origin.abs());
        let lo = ((c - r - margin - origin) / size).floor();
        let hi = ((c + r + margin - origin) / size).floor();
        if !(lo.is_finite() && hi.is_finite()) || hi < 0.0 || lo >= count as f32 {
            return None;
        }
        // In range now, so the casts are exact.
        let last = count.saturating_sub(1) as f32;
        Some([lo.clamp(0.0, last) as u32, hi.clamp(0.0, last) as u32])
    };
    let x = range(0, layout.origin[0], layout.patches[0])?;
    let z = range(2, layout.origin[1], layout.patches[1])?;
    Some(PatchRect { x, z })
}

/// Writes to `out` (cleared first) the indices, ascending, of the patches
/// whose AABB overlaps `world_root`, the object's root OBB in the world
/// frame ([`world_obb`]): paper §4 stage 2, DESIGN §4.1. The same list as
/// [`patches_hit`], found by testing only the patches of [`patch_rect`].
/// Reuses `out`'s allocation.
pub fn patches_under(layout: &FieldLayout, world_root: &Obb, out: &mut Vec<u32>) {
    out.clear();
    let Some(rect) = patch_rect(layout, world_root) else {
        return;
    };
    out.extend(rect.patches(layout.patches[0]).filter(|&p| {
        let patch = &layout.patch_list[p as usize];
        obb_overlaps_aabb(world_root, patch.aabb_min, patch.aabb_max)
    }));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;

    /// The tree walk's prepared test gives `obb_may_overlap_aabb` of the
    /// grown box, for random boxes near each other (about half overlap),
    /// inverted and non-finite AABBs included.
    #[test]
    fn a_prepared_aabb_answers_as_obb_may_overlap_aabb() {
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
        let (mut overlaps, mut total) = (0, 0);
        for k in 0..20_000 {
            let u = rng.vec(-1.0, 1.0).normalize();
            let v = u.any_orthonormal_vector();
            let obb = Obb {
                center: rng.vec(-0.6, 0.6),
                axes: [u, v, u.cross(v)],
                half: rng.vec(0.0, 0.6),
            };
            let mut lo = rng.vec(-1.0, 0.4);
            let mut hi = lo + rng.vec(0.0, 0.6);
            if k % 97 == 0 {
                lo.y = f32::NAN;
            }
            if k % 89 == 0 {
                (lo, hi) = (hi, lo);
            }
            let grow = [0.0, 0.005, 0.02][k % 3];
            let grown = Obb {
                half: obb.half + Vec3::splat(grow),
                ..obb
            };
            let want = obb_may_overlap_aabb(&grown, lo, hi);
            let got = AabbFaces::new(lo, hi).is_some_and(|a| a.may_overlap(&obb, grow));
            assert_eq!(got, want, "{obb:?} {lo} {hi} {grow}");
            overlaps += usize::from(want);
            total += 1;
        }
        assert!(
            overlaps * 5 > total && overlaps * 5 < total * 4,
            "{overlaps} of {total}"
        );
    }
}
