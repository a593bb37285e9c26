//! Seamless transitions between geometric blades and billboards: paper §6.3,
//! Eq. 9–13; DESIGN §6.
//!
//! **Geometry → billboard.** Each blade's slope `slope^g_i = V_n − V_0`
//! (Eq. 9) is compared with its rest slope (Eq. 10); the mean of these
//! offsets over the cell (Eq. 11; ours: per cell, the paper averages per
//! patch, which would blur a 10 cm track over 3 m) moves the billboard's
//! slope (Eq. 12).
//!
//! **Billboard → geometry.** The billboard's offset from its rest slope
//! (Eq. 13) acts as the external force on the last segment of each blade,
//! through Eq. 5 ([`bend_last_segment`]).
//!
//! **Units (ours).** Billboard slopes are dimensionless, per unit height
//! (DESIGN §6). So that Eq. 11–13 mix like quantities, a blade's offset
//! (Eq. 10) is divided by the blade's rest height `|rest V_n − V_0|`: the
//! offsets of a tall and a short blade bent alike are equal, and a billboard
//! slope is their mean direction scaled to unit rest height.

use super::bend::{offset_base, preserve_from, valid_blade};
use crate::field::{Blades, Terrain};
use glam::{Vec3, Vec3A};

/// A blade's offset from its rest slope, per unit rest height (Eq. 9–10,
/// ours: divided by the rest height), dimensionless:
/// `(slope^g_i − slope^g_origin) / |slope^g_origin|`,
/// with `slope^g_i = V_n − V_0` (Eq. 9).
///
/// - `tip_minus_root`: the blade's current `V_n − V_0`, metres.
/// - `rest_tip_minus_root`: its rest `V_n − V_0`, metres.
///
/// Returns [`Vec3::ZERO`] when the rest height is (nearly) zero or an input
/// is not finite.
///
/// See also [`mean_offset`], [`slope_from_offset`].
#[must_use]
pub fn blade_offset(tip_minus_root: Vec3, rest_tip_minus_root: Vec3) -> Vec3 {
    let rest_height = rest_tip_minus_root.length();
    let usable = rest_height.is_finite() && rest_height > 1e-12 && tip_minus_root.is_finite();
    if !usable {
        return Vec3::ZERO;
    }
    (tip_minus_root - rest_tip_minus_root) / rest_height
}

/// The billboard's offset `off^b`: the mean of the blade offsets of a cell
/// (Eq. 11, per cell: DESIGN §6), dimensionless. [`Vec3::ZERO`] for no
/// offsets; non-finite offsets are skipped (they count neither in the sum nor
/// in `K`). Allocation-free.
#[must_use]
pub fn mean_offset(offsets: impl IntoIterator<Item = Vec3>) -> Vec3 {
    let (sum, k) = offsets
        .into_iter()
        .filter(|o| o.is_finite())
        .fold((Vec3::ZERO, 0u32), |(sum, k), o| (sum + o, k + 1));
    if k == 0 { Vec3::ZERO } else { sum / k as f32 }
}

/// A cell's billboard offset `off^b` (Eq. 9–11, the mean of
/// [`blade_offset`] over the cell's blades `blades_of_cell`) and its
/// flatness (ours: the mean over the same blades of `1 − tip height / rest
/// tip height`, clamped to [0, 1]; see [`crate::field::Cells::flatness`]).
/// Blades a grass map left out ([`Blades::is_present`]) do not count.
/// Reads the blades' current and rest vertices; allocates nothing.
#[must_use]
pub fn cell_offset_and_flatness(
    blades: &Blades,
    blades_of_cell: std::ops::Range<usize>,
) -> (Vec3, f32) {
    let n = blades.segments;
    let count = blades_of_cell.len();
    let (mut flat, mut k) = (0.0, 0u32);
    let grown = blades_of_cell.filter(|&b| blades.is_present(b));
    let off = mean_offset(grown.map(|b| {
        let (root, rest_root) = (blades.vertex(b, 0), blades.rest_vertex(b, 0));
        let chord = Vec3::from(blades.vertex(b, n) - root);
        let rest = Vec3::from(blades.rest_vertex(b, n) - rest_root);
        let f = crate::recovery::flatness(chord.y, rest.y);
        if f.is_finite() {
            flat += f;
            k += 1;
        }
        blade_offset(chord, rest)
    }));
    let flatness = if k == 0 || count == 0 {
        0.0
    } else {
        flat / k as f32
    };
    (off, flatness)
}

/// The billboard slope from its offset, Eq. 12 as a direction:
/// `slope^b = slope^b_origin + off^b`, dimensionless. The paper's factor
/// `height_g` is applied when the top edge is placed
/// ([`billboard_top`](super::billboard::billboard_top) normalises the slope
/// and multiplies by the height).
///
/// - `slope_origin_b`: the cell's rest slope: its blades' mean rest
///   `V_n − V_0` divided by their mean rest height (length ≈ 1).
/// - `off_b`: from [`mean_offset`].
///
/// Inverse of [`offset_from_slope`].
#[must_use]
pub fn slope_from_offset(slope_origin_b: Vec3, off_b: Vec3) -> Vec3 {
    slope_origin_b + off_b
}

/// The offset of a billboard's slope from its rest slope, Eq. 13:
/// `off^b = slope^b − slope^b_origin`, dimensionless (per unit height).
///
/// Used for the transition back to geometry ([`bend_last_segment`]). A slope
/// set by Eq. 8 may be long (`R/|t|`); its offset is used only as a force
/// through Eq. 5 and length preservation, so the blade's answer stays
/// bounded. Inverse of [`slope_from_offset`].
#[must_use]
pub fn offset_from_slope(slope_b: Vec3, slope_origin_b: Vec3) -> Vec3 {
    slope_b - slope_origin_b
}

/// Billboard → geometry (paper §6.3 (2)): the billboard's offset acts as the
/// external force on the **last segment** of a blade through Eq. 5, in place.
///
/// `base` = [`offset_base`]`(V_n − V_0, v1, 1.0)` is added to the tip `V_n`
/// alone, then the last segment gets its length back (Fig. 7, with the
/// ground guard of [`preserve_lengths`](super::bend::preserve_lengths)).
/// Vertices `0 ..= n−1` are not touched (bit for bit).
///
/// - `v1`: the displacement to apply, metres. The caller passes
///   `v1 = (off^b − mean blade offset of the cell) · blade rest height`
///   (offsets from [`offset_from_slope`] and [`blade_offset`]): when the
///   blades were at rest (mean offset zero) this is exactly the paper's rule
///   "`off^b` is the external force"; when they still carry a bend, only the
///   difference is applied, so the transition does not bend them twice.
///
/// Leaves the blade unchanged if `v1` is not finite, `seg_len ≤ 0` or not
/// finite, the root or `V_{n−1}` is not finite, or the blade has no segment.
pub fn bend_last_segment(
    verts: &mut [Vec3A],
    seg_len: f32,
    v1: Vec3,
    terrain: &Terrain,
    clearance: f32,
) {
    let n = verts.len().saturating_sub(1);
    if n == 0 || !valid_blade(verts, seg_len) || !v1.is_finite() || !verts[n - 1].is_finite() {
        return;
    }
    let base = Vec3A::from(offset_base((verts[n] - verts[0]).into(), v1, 1.0));
    if base == Vec3A::ZERO {
        return;
    }
    verts[n] += base;
    preserve_from(verts, n, seg_len, terrain, clearance);
}
