//! The broad phase: which patches an object may touch (paper §4 stage 2:
//! "Perform intersection tests between dynamic object and patches. Only
//! patches that intersect with object are taken into account"; DESIGN §4.1).
//!
//! The object's root OBB, moved to the world, against each patch's AABB
//! (which includes the blades' maximum height), by the separating axis
//! theorem on the 15 candidate axes (Gottschalk et al., *OBBTree*, 1996;
//! C. Ericson, *Real-Time Collision Detection*, 2005, §4.4.1).

use glam::{Quat, Vec3};

use crate::field::Patch;
use crate::obb::Obb;
use crate::object::Pose;

/// Added to every `|R_ij|` of the SAT (Ericson §4.4.1): when an OBB edge is
/// parallel to an AABB edge their cross product is ~0 and, unpadded, its
/// rounding could report a false separation.
const PARALLEL_PAD: f32 = 1e-6;

/// Relative slack of every SAT comparison (of the sum of projected radii),
/// so that boxes that touch, or overlap by a rounding error, count as
/// overlapping: the broad phase must be conservative.
const REL_SLACK: f32 = 1e-5;

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
    // r[i][j] = e_i · B_j, the OBB axes in the AABB frame.
    let r: [[f32; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| obb.axes[j][i]));
    let ar: [[f32; 3]; 3] = r.map(|row| row.map(|x| x.abs() + PARALLEL_PAD));
    let separated = |dist: f32, ra: f32, rb: f32| dist.abs() > (ra + rb) * (1.0 + REL_SLACK);

    // AABB axes e_i.
    for i in 0..3 {
        let rb = b.x * ar[i][0] + b.y * ar[i][1] + b.z * ar[i][2];
        if separated(t[i], a[i], rb) {
            return false;
        }
    }
    // OBB axes B_j.
    for j in 0..3 {
        let ra = a.x * ar[0][j] + a.y * ar[1][j] + a.z * ar[2][j];
        let dist = t.x * r[0][j] + t.y * r[1][j] + t.z * r[2][j];
        if separated(dist, ra, b[j]) {
            return false;
        }
    }
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
/// allocation.
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
