//! Segment vs oriented box, four segments at once (issue 16, item 2): the
//! test of [`super::segment_obb`] (paper §4.2, ref. \[16\]: Schneider &
//! Eberly's separating-axis form of the slab test) in structure-of-arrays
//! form, one segment per lane of glam's SIMD `Vec4` (SSE2 on x86_64, NEON
//! on aarch64, scalar elsewhere), no new dependency.
//!
//! Same conventions as the scalar test, and the same answers, bit for bit:
//! every lane does the scalar test's float operations in the scalar test's
//! order (the box-frame transform as glam's `Mat3A * Vec3A` sums it, the
//! cross product as glam's `Vec3A::cross` does), so a tie that the scalar
//! test decides one way is decided the same way here (tested on random,
//! grazing, face-parallel and degenerate segments). Touching counts as a
//! hit (`≤`); a zero-length segment is a point-in-box test; a non-finite
//! endpoint is rejected before the test (its lane's centre is made NaN,
//! which every comparison rejects), so it is a miss.
//!
//! Use: a traversal moves a blade's segments into the object's frame once,
//! packs them with [`Segments4::new`], and tests them against each node's
//! box with [`Segments4::hit_mask`] ([`Segments4::hit_mask_grown`] for the
//! contact walk's boxes grown by the shell): the narrow phase's
//! [`super::narrow_phase::contact_blade`] walks the tree once for four
//! segments of a blade.

use glam::{Vec3, Vec4};

use crate::obb::Obb;

/// Four segments as centre and half-vector, one component per `Vec4`, lane
/// `i` = segment `i`: the form [`Segments4::hit_mask`] tests.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segments4 {
    /// Centres' x, y, z (NaN in a lane whose segment has a non-finite endpoint).
    pub centre: [Vec4; 3],
    /// Half-vectors' x, y, z: `(p1 − p0) / 2`.
    pub half: [Vec4; 3],
}

impl Segments4 {
    /// Packs segments `p0[i]–p1[i]`, `i` in 0..4, as the scalar test's
    /// `centred` does: centre `(p0 + p1) / 2`, half-vector `(p1 − p0) / 2`,
    /// and a lane with a non-finite endpoint poisoned with NaN (`x − x` is 0
    /// for finite `x`, NaN otherwise). Fewer than four segments: repeat one
    /// (lanes are independent) or pass NaN endpoints for a lane that must
    /// miss.
    #[must_use]
    #[inline]
    #[allow(clippy::eq_op)] // `x - x` is the point: 0, or NaN for a non-finite x
    pub fn new(p0: [Vec3; 4], p1: [Vec3; 4]) -> Self {
        let lane = |p: &[Vec3; 4], k: usize| Vec4::new(p[0][k], p[1][k], p[2][k], p[3][k]);
        let (a, b) = (
            [0, 1, 2].map(|k| lane(&p0, k)),
            [0, 1, 2].map(|k| lane(&p1, k)),
        );
        let poison = ((a[0] - a[0]) + (b[0] - b[0]))
            + ((a[1] - a[1]) + (b[1] - b[1]))
            + ((a[2] - a[2]) + (b[2] - b[2]));
        Self {
            centre: [0, 1, 2].map(|k| (a[k] + b[k]) * 0.5 + poison),
            half: [0, 1, 2].map(|k| (b[k] - a[k]) * 0.5),
        }
    }

    /// Each segment's axis-aligned box, `(lo, hi)` per axis, one lane a
    /// segment: `centre ∓ |half|` (NaN lanes stay NaN).
    #[must_use]
    #[inline]
    pub fn boxes(&self) -> ([Vec4; 3], [Vec4; 3]) {
        let reach = self.half.map(Vec4::abs);
        (
            [0, 1, 2].map(|k| self.centre[k] - reach[k]),
            [0, 1, 2].map(|k| self.centre[k] + reach[k]),
        )
    }

    /// Bit `i` set when segment `i` meets `obb` (same frame); touching
    /// counts, a non-finite segment misses. The same answers as
    /// [`super::segment_obb::segment_hits_obb`] on each segment.
    #[must_use]
    #[inline]
    pub fn hit_mask(&self, obb: &Obb) -> u32 {
        self.mask_within(obb, [obb.half.x, obb.half.y, obb.half.z], 0b1111)
    }

    /// [`Segments4::hit_mask`] against `obb` grown by `shell` metres on
    /// every side: the same answers as the scalar
    /// `segment_hits_obb_inflated` on each segment (the grown half extents
    /// are summed as it sums them).
    #[must_use]
    #[inline]
    pub fn hit_mask_grown(&self, obb: &Obb, shell: f32) -> u32 {
        self.hit_mask_grown_in(obb, shell, 0b1111)
    }

    /// [`Segments4::hit_mask_grown`] for the lanes set in `lanes` only (the
    /// others come back clear): a traversal passes the segments still in,
    /// and the test stops as soon as all of those are separated.
    #[must_use]
    #[inline]
    pub fn hit_mask_grown_in(&self, obb: &Obb, shell: f32, lanes: u32) -> u32 {
        let grown = glam::Vec3A::from(obb.half) + shell;
        self.mask_within(obb, [grown.x, grown.y, grown.z], lanes)
    }

    /// The lanes of `lanes` whose segment meets the box of `obb`'s centre
    /// and axes with half extents `half`. Axis by axis, each face axis's
    /// answer as soon as it is known: when no lane of `lanes` is left the
    /// rest is skipped (the answer is the AND over the axes, so skipping
    /// changes no bit of it).
    #[inline]
    fn mask_within(&self, obb: &Obb, half: [f32; 3], lanes: u32) -> u32 {
        let [u, v, w] = obb.axes;
        let o = obb.center;
        let d = [0, 1, 2].map(|k| self.centre[k] - Vec4::splat(o[k]));
        // Into the box frame, summed as glam's `Mat3A * Vec3A`: x, then y, then z.
        let frame = |a: Vec3, x: &[Vec4; 3]| {
            x[0] * Vec4::splat(a.x) + x[1] * Vec4::splat(a.y) + x[2] * Vec4::splat(a.z)
        };
        let e = half.map(Vec4::splat);
        // The three face normals (the slab test), one at a time.
        let mut c = [Vec4::ZERO; 3];
        let mut h = [Vec4::ZERO; 3];
        let mut ah = [Vec4::ZERO; 3];
        let mut mask = lanes;
        for (k, axis) in [u, v, w].into_iter().enumerate() {
            c[k] = frame(axis, &d);
            h[k] = frame(axis, &self.half);
            ah[k] = h[k].abs();
            mask &= c[k].abs().cmple(e[k] + ah[k]).bitmask();
            if mask == 0 {
                return 0;
            }
        }
        // The three cross products h × e_i, as glam's `Vec3A::cross`.
        let cross = [
            (c[1] * h[2] - h[1] * c[2]).abs(),
            (c[2] * h[0] - h[2] * c[0]).abs(),
            (c[0] * h[1] - h[0] * c[1]).abs(),
        ];
        let reach = [
            e[1] * ah[2] + e[2] * ah[1],
            e[0] * ah[2] + e[2] * ah[0],
            e[0] * ah[1] + e[1] * ah[0],
        ];
        let edges = cross[0].cmple(reach[0]) & cross[1].cmple(reach[1]) & cross[2].cmple(reach[2]);
        mask & edges.bitmask()
    }
}
