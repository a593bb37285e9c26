//! Segment vs oriented box: the "intersection test between linear object and
//! oriented bounding box" of paper §4.2, ref. \[16\] (P. Schneider, D. Eberly,
//! *Geometric Tools for Computer Graphics*, 2003: linear components and
//! boxes; the same test is in Eberly's `IntrSegment3Box3`).
//!
//! In the box frame, with the segment written as centre `c` plus or minus
//! half-vector `h`, the segment misses the box iff one of six axes separates
//! them: the three face normals (`|c_i| > e_i + |h_i|`, the slab test) and
//! the three cross products `h × e_i` (`|(c × h)_i| > e_j |h_k| + e_k |h_j|`).
//! This is the slab test written without divisions, so a segment parallel to
//! a slab needs no special case, and without branches: every axis is
//! evaluated and the results are combined with `&`.
//!
//! Conventions: touching counts as a hit (`≤` everywhere); a zero-length
//! segment is a point-in-box test; a non-finite endpoint is a miss (with NaN
//! every comparison is false, and written as "separated if >" a NaN segment
//! would count as a hit, see PLATFORM.md).

use glam::{Mat3A, Vec3, Vec3A};

use crate::obb::Obb;

/// True when segment `p0–p1` meets `obb` (both in the same frame); touching
/// counts. Non-finite endpoints give `false`. ≈ 10 ns (SSE through glam's
/// `Vec3A`), no branch, no allocation.
///
/// See also [`segment_hits_box_local`] for a segment already in the box frame.
#[must_use]
#[inline]
pub fn segment_hits_obb(p0: Vec3, p1: Vec3, obb: &Obb) -> bool {
    let (centre, half) = centred(p0, p1);
    segment_hits_obb_centred(centre, half, obb)
}

/// True when segment `a–b`, given in the frame of a box centred at the origin
/// with half extents `half` along x, y, z, meets the box; touching counts.
/// Non-finite endpoints give `false`.
///
/// See also [`segment_hits_obb`].
#[must_use]
#[inline]
pub fn segment_hits_box_local(a: Vec3, b: Vec3, half: Vec3) -> bool {
    let (c, h) = centred(a, b);
    hits_centred_local(c, h, Vec3A::from(half))
}

/// Segment `p0–p1` as centre and half-vector, for
/// [`segment_hits_obb_centred`]. A non-finite endpoint makes the centre NaN
/// (`x − x` is 0 for finite `x`, NaN otherwise), which every test then
/// rejects: the finiteness check without a branch.
#[must_use]
#[inline]
#[allow(clippy::eq_op)] // `x - x` is the point: 0, or NaN for a non-finite x
pub(crate) fn centred(p0: Vec3, p1: Vec3) -> (Vec3A, Vec3A) {
    let (a, b) = (Vec3A::from(p0), Vec3A::from(p1));
    let poison = (a - a) + (b - b);
    ((a + b) * 0.5 + poison, (b - a) * 0.5)
}

/// [`segment_hits_obb`] for a segment given by [`centred`], in the box's
/// parent frame: lets a traversal convert the segment once.
#[must_use]
#[inline]
pub(crate) fn segment_hits_obb_centred(centre: Vec3A, half: Vec3A, obb: &Obb) -> bool {
    let (c, h) = to_box_frame(centre, half, obb);
    hits_centred_local(c, h, Vec3A::from(obb.half))
}

/// [`segment_hits_obb_centred`] against `obb` grown by `shell` metres on
/// every side (the contact shell of the simulation, DESIGN §5 "Contact":
/// a blade has a width, so its centre line touches an object `shell`
/// before the surface). `shell = 0` is [`segment_hits_obb_centred`].
#[must_use]
#[inline]
pub(crate) fn segment_hits_obb_inflated(centre: Vec3A, half: Vec3A, obb: &Obb, shell: f32) -> bool {
    let (c, h) = to_box_frame(centre, half, obb);
    hits_centred_local(c, h, Vec3A::from(obb.half) + shell)
}

/// How deep segment `centre ± half` (parent frame) reaches into `obb` grown
/// by `shell`: the largest, over the points of the segment, of the distance
/// from the point to the grown box's boundary, metres; negative when the
/// segment misses the box (then minus the gap, along the worst axis, at the
/// segment's closest approach in that sense). See [`max_depth_local`].
#[must_use]
#[inline]
pub(crate) fn segment_depth_in_obb(centre: Vec3A, half: Vec3A, obb: &Obb, shell: f32) -> f32 {
    let (c, h) = to_box_frame(centre, half, obb);
    max_depth_local(c, h, Vec3A::from(obb.half) + shell)
}

/// Segment `c ± h` moved into the frame of `obb` (rows u, v, w of the
/// box's axes: multiplying by them takes a vector into the box frame).
#[inline]
pub(crate) fn to_box_frame(centre: Vec3A, half: Vec3A, obb: &Obb) -> (Vec3A, Vec3A) {
    let to_box =
        Mat3A::from_cols(obb.axes[0].into(), obb.axes[1].into(), obb.axes[2].into()).transpose();
    (to_box * (centre - Vec3A::from(obb.center)), to_box * half)
}

/// `max over s in [-1, 1] of min_i (e_i - |c_i + s h_i|)`: how far the
/// segment `c ± h` (box frame) reaches into the box of half extents `e`
/// (ours, DESIGN §5 "a continuous response").
///
/// The depth of a point is a minimum of six linear functions of `s` (two
/// per axis), so along the segment it is concave and piecewise linear, and
/// its maximum lies at an end (`s = ±1`) or where two of the six lines
/// cross: the peak of an axis (`c_i + s h_i = 0`) or the crossing of two
/// axes' lines (12 sign combinations). All 17 candidates are evaluated in a
/// fixed order (the GPU twin `segment_depth` in `segment_obb.wgsl` does the
/// same), so the result is exact up to rounding and continuous in the
/// segment and the box: a segment grazing the box gives a depth near 0,
/// never a jump. NaN input gives NaN (callers test `depth > 0`).
#[must_use]
#[inline]
pub fn max_depth_local(c: Vec3A, h: Vec3A, e: Vec3A) -> f32 {
    let depth = |s: f32| (e - (c + h * s).abs()).min_element();
    let mut best = depth(-1.0).max(depth(1.0));
    for i in 0..3 {
        if h[i] != 0.0 {
            best = best.max(depth((-c[i] / h[i]).clamp(-1.0, 1.0)));
        }
        for j in i + 1..3 {
            for (si, sj) in [(1.0f32, 1.0f32), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                // e_i − si (c_i + s h_i) = e_j − sj (c_j + s h_j)
                let den = sj * h[j] - si * h[i];
                if den != 0.0 {
                    let s = (e[j] - e[i] - sj * c[j] + si * c[i]) / den;
                    best = best.max(depth(s.clamp(-1.0, 1.0)));
                }
            }
        }
    }
    best
}

/// The six separating-axis tests, box frame: segment `c ± h`, box half
/// extents `e`. NaN anywhere gives `false`.
#[inline]
pub(crate) fn hits_centred_local(c: Vec3A, h: Vec3A, e: Vec3A) -> bool {
    let ah = h.abs();
    let faces = c.abs().cmple(e + ah);
    let cross = c.cross(h).abs();
    // (e.y ah.z + e.z ah.y, e.x ah.z + e.z ah.x, e.x ah.y + e.y ah.x)
    let reach = Vec3A::new(e.y, e.x, e.x) * Vec3A::new(ah.z, ah.z, ah.y)
        + Vec3A::new(e.z, e.z, e.y) * Vec3A::new(ah.y, ah.x, ah.x);
    (faces & cross.cmple(reach)).all()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;

    /// Reference: Liang–Barsky clipping of the parameter interval [0, 1]
    /// against the three slabs, in f64. Returns the clipped interval's
    /// length in parameter units (negative: miss by that much).
    fn clipped_length(a: Vec3, b: Vec3, e: Vec3) -> f64 {
        let (a, b, e) = (a.as_dvec3(), b.as_dvec3(), e.as_dvec3());
        let d = b - a;
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for i in 0..3 {
            if d[i] == 0.0 {
                if a[i].abs() > e[i] {
                    return -1.0;
                }
                continue;
            }
            let (ta, tb) = ((-e[i] - a[i]) / d[i], (e[i] - a[i]) / d[i]);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        t1 - t0
    }

    #[test]
    fn agrees_with_liang_barsky_clipping_away_from_ties() {
        // Deterministic pseudo-random segments (xorshift).
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15u64);
        let mut next = || rng.range(-2.0, 2.0);
        let e = Vec3::new(1.0, 0.5, 0.25);
        let mut checked = 0;
        for _ in 0..20_000 {
            let a = Vec3::new(next(), next(), next());
            let b = Vec3::new(next(), next(), next());
            // Skip near-tangent segments, where rounding may decide.
            let len = clipped_length(a, b, e);
            if len.abs() > 1e-5 {
                assert_eq!(segment_hits_box_local(a, b, e), len > 0.0, "{a} {b}");
                checked += 1;
            }
        }
        assert!(checked > 19_000, "{checked}");
    }

    /// The closed form of [`max_depth_local`] equals a dense sampling of the
    /// depth along the segment (which it bounds from above by at most the
    /// sampling step times the slope), and its sign is the hit test's.
    #[test]
    fn max_depth_matches_dense_sampling_and_the_hit_test() {
        let mut rng = XorShift(0x2545_f491_4f6c_dd1du64);
        let mut next = || rng.range(-2.0, 2.0);
        let e = Vec3A::new(1.0, 0.5, 0.25);
        for _ in 0..5_000 {
            let c = Vec3A::new(next(), next(), next());
            let h = Vec3A::new(next(), next(), next()) * 0.7;
            let depth = max_depth_local(c, h, e);
            let steps = 4000;
            let sampled = (0..=steps)
                .map(|i| {
                    let t = -1.0 + 2.0 * i as f32 / steps as f32;
                    (e - (c + h * t).abs()).min_element()
                })
                .fold(f32::NEG_INFINITY, f32::max);
            let slope = h.abs().max_element();
            assert!(
                depth >= sampled - 1e-5,
                "{c} {h}: {depth} < sampled {sampled}"
            );
            assert!(
                depth <= sampled + slope * 2.0 / steps as f32 + 1e-5,
                "{c} {h}: {depth} > sampled {sampled}"
            );
            if depth.abs() > 1e-5 {
                assert_eq!(hits_centred_local(c, h, e), depth > 0.0, "{c} {h}");
            }
        }
    }

    /// A segment sliding past a box: the depth changes continuously, with no
    /// jump where the hit test flips (the grazing contact of issue 12).
    #[test]
    fn depth_is_continuous_across_a_grazing_contact() {
        let e = Vec3A::new(0.5, 0.5, 0.5);
        let h = Vec3A::new(0.3, 0.4, 0.0);
        let mut last = None;
        for i in 0..=2000 {
            let x = 0.6 + 0.4 * i as f32 / 2000.0;
            let d = max_depth_local(Vec3A::new(x, 0.0, 0.1), h, e);
            if let Some(prev) = last {
                let step: f32 = d - prev;
                assert!(step.abs() <= 0.001, "jump of {step} at x = {x}");
            }
            last = Some(d);
        }
    }
}
