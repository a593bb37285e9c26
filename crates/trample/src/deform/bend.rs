//! Bending a geometric blade under a force: paper §6.1, Eq. 5–7 and the
//! length preservation of Fig. 7; DESIGN §6.
//!
//! Step 1: the **offset-base vector** `base` (Eq. 5) is the part of the force
//! perpendicular to the blade's root→tip line AB, shared by the segments that
//! hit. Step 2: vertex `V_i` is offset by `off_i = P(i) · base` (Eq. 6) with
//! the weight function `P(x) = a·sqrt(1 + x²/b²) − a` (Eq. 7), so the tip
//! moves more than the root. Step 3: from the root up, every segment is put
//! back to its rest length along its new direction (Fig. 7), and (ours) no
//! vertex goes below the ground plus a clearance.
//!
//! Blades are slices of `n + 1` vertices (vertex 0 = root, never moved;
//! vertex n = tip), all segments of rest length `seg_len`, world space,
//! metres. The functions here allocate nothing.

use crate::field::{MAX_SEGMENTS, Terrain};
use glam::{Vec3, Vec3A};

/// Weight `P(x) = a·sqrt(1 + x²/b²) − a` of segment number `x` (Eq. 7),
/// dimensionless. `x` counts segments from the root (1, 2, …); `a` and `b`
/// are the shape constants of the paper (`b ≠ 0`; `b = 0` gives ∞ or NaN,
/// which [`bend_blade`] refuses).
///
/// Evaluated as `a·t²/(sqrt(1 + t²) + 1)`, `t = x/b`: the same value without
/// the cancellation of `sqrt(1 + t²) − 1` for small `t`.
///
/// See also [`weights`].
#[must_use]
pub fn weight(x: f32, a: f32, b: f32) -> f32 {
    let t = x / b;
    let t2 = t * t;
    a * t2 / ((1.0 + t2).sqrt() + 1.0)
}

/// The weights `P(1), …, P(n)` of Eq. 6–7 at indices `0 .. n`, zero beyond;
/// `n` above [`MAX_SEGMENTS`] is lowered to it. Compute once per parameter
/// set and pass to [`bend_blade`].
#[must_use]
pub fn weights(n: usize, a: f32, b: f32) -> [f32; MAX_SEGMENTS] {
    let mut w = [0.0; MAX_SEGMENTS];
    for (i, wi) in w.iter_mut().enumerate().take(n.min(MAX_SEGMENTS)) {
        *wi = weight((i + 1) as f32, a, b);
    }
    w
}

/// The offset-base vector of Eq. 5, metres: `base = (v2 · v1) v2 / num`,
/// where `v2` is the unit vector perpendicular to `AB` in the plane of `AB`
/// and `v1`. That is the component of `v1` perpendicular to `AB`, divided by
/// `num`.
///
/// - `ab`: root → tip of the blade (the bending trend, Fig. 6).
/// - `v1`: the external force as a displacement of this step, `EqF · dt`
///   (DESIGN §6, ours), metres.
/// - `num`: the number of the blade's segments that hit the object (1 for
///   PBG). The simulation counts each segment by its contact weight in
///   [0, 1] (DESIGN §6, ours: a grazing segment counts for little), so
///   `num` is a real number; below 1 it is taken as 1 (NaN too).
///
/// Returns [`Vec3::ZERO`] when `AB` is (nearly) zero, when `v1` is parallel
/// to `AB` within 1e-6 rad (no perpendicular direction: the paper's `v2` is
/// undefined), or when an input is not finite.
#[must_use]
pub fn offset_base(ab: Vec3, v1: Vec3, num: f32) -> Vec3 {
    let ab_len2 = ab.length_squared();
    if !ab.is_finite() || !v1.is_finite() || ab_len2 <= f32::MIN_POSITIVE {
        return Vec3::ZERO;
    }
    let perpendicular = v1 - ab * (v1.dot(ab) / ab_len2);
    if perpendicular.length_squared() <= 1e-12 * v1.length_squared() {
        return Vec3::ZERO;
    }
    let base = perpendicular / num.max(1.0);
    if base.is_finite() { base } else { Vec3::ZERO }
}

/// Length preservation (Fig. 7) with a ground guard (ours), in place.
///
/// From the root up: `V_i = V_{i−1} + seg_len · normalize(V_i − V_{i−1})`,
/// where `V_{i−1}` is already corrected. Where `V_i − V_{i−1}` is zero or not
/// finite, the previous segment's direction is kept (straight up for the
/// first segment), so a damaged blade comes back finite.
///
/// Ground guard: no vertex above the root ends below
/// `terrain.height_at(x, z) + clearance`. A segment that would is rotated
/// about `V_{i−1}` in its vertical plane (same horizontal direction, exact
/// length) up to the lowest angle at which its end clears the guard; where
/// the ground rises ahead of a vertex that is itself below the guard (the
/// root stands on the ground), that means tilting it upward. If even
/// straight up cannot clear it (`clearance > seg_len`), the segment points
/// straight up. On uneven terrain the angle is found by bisection (24 steps)
/// and always errs on the clear side.
///
/// Preconditions: `seg_len > 0` and finite and a finite root, otherwise the
/// blade is left unchanged; a non-finite `clearance` counts as 0.
pub fn preserve_lengths(verts: &mut [Vec3A], seg_len: f32, terrain: &Terrain, clearance: f32) {
    preserve_from(verts, 1, seg_len, terrain, clearance);
}

/// Bends a blade under a force (Eq. 5–7) and restores its segment lengths
/// (Fig. 7), in place.
///
/// `AB` = tip − root; `base` = [`offset_base`]`(AB, v1, num)`;
/// `V_i += P(i) · base` for `i = 1 ..= n` with `P(i) = weights[i − 1]`
/// (Eq. 6; a missing weight counts as 0; see [`weights`]); then
/// [`preserve_lengths`].
///
/// - `v1`: the force as this step's displacement `EqF · dt`, metres
///   (DESIGN §6, ours: frame-rate independent).
/// - `num`: segments that hit (Eq. 5; 1 for PBG; below 1 taken as 1), each
///   counted by its contact weight (see [`offset_base`]).
///
/// The blade is left unchanged (bit for bit) when the offset-base vector is
/// zero, or when `v1`, a weight, `seg_len` or the root is not finite (or
/// `seg_len ≤ 0`): bad input never poisons a blade.
pub fn bend_blade(
    verts: &mut [Vec3A],
    seg_len: f32,
    v1: Vec3,
    num: f32,
    weights: &[f32],
    terrain: &Terrain,
    clearance: f32,
) {
    let n = verts.len().saturating_sub(1);
    if n == 0 || !valid_blade(verts, seg_len) || !v1.is_finite() {
        return;
    }
    let weight_of = |i: usize| weights.get(i - 1).copied().unwrap_or(0.0);
    if !(1..=n).all(|i| weight_of(i).is_finite()) {
        return;
    }
    let base = Vec3A::from(offset_base((verts[n] - verts[0]).into(), v1, num));
    if base == Vec3A::ZERO {
        return;
    }
    for (i, v) in verts.iter_mut().enumerate().skip(1) {
        *v += base * weight_of(i);
    }
    preserve_lengths(verts, seg_len, terrain, clearance);
}

/// Whether length preservation can run: at least a root, finite positive
/// segment length, finite root.
pub(crate) fn valid_blade(verts: &[Vec3A], seg_len: f32) -> bool {
    seg_len.is_finite() && seg_len > 0.0 && verts.first().is_some_and(|v| v.is_finite())
}

/// [`preserve_lengths`] for vertices `first ..= n` only; the vertices below
/// `first` are taken as they are.
pub(crate) fn preserve_from(
    verts: &mut [Vec3A],
    first: usize,
    seg_len: f32,
    terrain: &Terrain,
    clearance: f32,
) {
    if first == 0 || first >= verts.len() || !valid_blade(verts, seg_len) {
        return;
    }
    let clearance = if clearance.is_finite() {
        clearance
    } else {
        0.0
    };
    // The unit direction of the segment below, the fallback of the next
    // one's: normalised only when a fallback is taken (a segment of zero
    // length, or a vertical one the guard must lift), which is rare — the
    // same bits as normalising it every segment, for half the square roots
    // and divisions of the chain (BENCHMARKS.md, "Session 34").
    let mut last_dir = if first >= 2 {
        LastDir {
            d: verts[first - 1] - verts[first - 2],
            fallback: Vec3A::Y,
        }
    } else {
        LastDir {
            d: Vec3A::Y,
            fallback: Vec3A::Y,
        }
    };
    for i in first..verts.len() {
        let from = verts[i - 1];
        let dir = unit_or_else(verts[i] - from, || last_dir.unit());
        let end = guarded_end(from, dir, seg_len, terrain, clearance, || last_dir.unit());
        last_dir = LastDir {
            d: end - from,
            fallback: dir,
        };
        verts[i] = end;
    }
}

/// A direction not yet normalised: `unit_or(d, fallback)` when asked
/// ([`preserve_from`]).
#[derive(Clone, Copy)]
struct LastDir {
    d: Vec3A,
    fallback: Vec3A,
}

impl LastDir {
    fn unit(self) -> Vec3A {
        unit_or(self.d, self.fallback)
    }
}

/// `d` normalised, or `fallback` where `d` is (nearly) zero or not finite.
fn unit_or(d: Vec3A, fallback: Vec3A) -> Vec3A {
    unit_or_else(d, || fallback)
}

/// [`unit_or`] with the fallback computed only when it is taken.
fn unit_or_else(d: Vec3A, fallback: impl FnOnce() -> Vec3A) -> Vec3A {
    let len2 = d.length_squared();
    if len2.is_finite() && len2 > 1e-24 {
        d / len2.sqrt()
    } else {
        fallback()
    }
}

/// The end of a segment of length `len` from `from` along unit `dir`, lifted
/// above the ground guard `terrain + clearance` by rotating it upward in its
/// vertical plane (see [`preserve_lengths`]). `fallback` gives the
/// horizontal direction when `dir` is vertical (asked only then).
pub(crate) fn guarded_end(
    from: Vec3A,
    dir: Vec3A,
    len: f32,
    terrain: &Terrain,
    clearance: f32,
    fallback: impl FnOnce() -> Vec3A,
) -> Vec3A {
    let clears = |p: Vec3A| p.y >= terrain.height_at(p.x, p.z) + clearance;
    let end = from + dir * len;
    if clears(end) {
        return end;
    }
    let horizontal = |d: Vec3A| unit_or(Vec3A::new(d.x, 0.0, d.z), Vec3A::ZERO);
    let mut h = horizontal(dir);
    if h == Vec3A::ZERO {
        h = horizontal(fallback());
    }
    if h == Vec3A::ZERO {
        h = Vec3A::X;
    }
    // The end at elevation sin θ = s, keeping the horizontal direction h.
    let at = |s: f32| from + (h * (1.0 - s * s).max(0.0).sqrt() + Vec3A::Y * s) * len;
    // Exact on flat ground: the elevation that puts the end on the guard.
    // Elsewhere it brackets the answer for the bisection.
    let guard_y = terrain.height_at(end.x, end.z) + clearance;
    let mut lo = dir.y.clamp(-1.0, 1.0);
    let guess = ((guard_y - from.y) / len).clamp(lo, 1.0);
    let mut hi = if guess.is_finite() && clears(at(guess)) {
        if matches!(terrain, Terrain::Flat(_)) {
            return at(guess);
        }
        guess
    } else if clears(at(1.0)) {
        1.0
    } else {
        return at(1.0);
    };
    for _ in 0..24 {
        let mid = 0.5 * (lo + hi);
        if clears(at(mid)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    at(hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;

    /// `preserve_from`'s chain as it was before its fallback direction
    /// became lazy: the previous segment's unit direction normalised at
    /// every segment. Only the chain: the test's blades are valid, from
    /// `first` in `1..len`, with a finite clearance (the prologue that
    /// screens other input is `preserve_from`'s own).
    fn preserve_from_eager(
        verts: &mut [Vec3A],
        first: usize,
        seg_len: f32,
        terrain: &Terrain,
        clearance: f32,
    ) {
        let mut last_dir = if first >= 2 {
            unit_or(verts[first - 1] - verts[first - 2], Vec3A::Y)
        } else {
            Vec3A::Y
        };
        for i in first..verts.len() {
            let from = verts[i - 1];
            let dir = unit_or(verts[i] - from, last_dir);
            let end = guarded_end(from, dir, seg_len, terrain, clearance, || last_dir);
            last_dir = unit_or(end - from, dir);
            verts[i] = end;
        }
    }

    /// The lazy fallback gives the eager one's bits, on blades whose
    /// fallbacks are taken: segments of zero length (a vertex on the one
    /// below it), vertical segments driven into the ground (the guard
    /// lifts them along the segment below's direction), vertices below
    /// the ground, on flat and hilly ground, from every first vertex.
    #[test]
    fn the_lazy_fallback_direction_gives_the_eager_bits() {
        let mut rng = XorShift(0x5eed_cafe_f00d_0001);
        let hills = Terrain::Noise {
            amplitude: 0.3,
            wavelength: 2.0,
            seed: 7,
        };
        let (mut zero_length, mut vertical_lifted) = (0, 0);
        for case in 0..4000 {
            let terrain = if case % 2 == 0 {
                Terrain::Flat(0.0)
            } else {
                hills.clone()
            };
            let root = Vec3A::new(rng.range(-2.0, 2.0), 0.0, rng.range(-2.0, 2.0));
            let root = root + Vec3A::Y * terrain.height_at(root.x, root.z);
            let mut v = vec![root; 5];
            for k in 1..5 {
                v[k] = match rng.next_u64() % 5 {
                    // On the vertex below: a zero-length segment.
                    0 => {
                        zero_length += 1;
                        v[k - 1]
                    }
                    // Straight down from the vertex below, into the ground.
                    1 => {
                        vertical_lifted += 1;
                        v[k - 1] - Vec3A::Y * rng.range(0.05, 0.5)
                    }
                    // Straight up.
                    2 => v[k - 1] + Vec3A::Y * rng.range(0.0, 0.2),
                    _ => v[k - 1] + Vec3A::from(rng.vec(-0.2, 0.2)),
                };
            }
            let first = 1 + (case % 4);
            let (mut lazy, mut eager) = (v.clone(), v.clone());
            preserve_from(&mut lazy, first, 0.1, &terrain, 0.002);
            preserve_from_eager(&mut eager, first, 0.1, &terrain, 0.002);
            let bits = |v: &[Vec3A]| -> Vec<[u32; 3]> {
                v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
            };
            assert_eq!(bits(&lazy), bits(&eager), "case {case}: {v:?}");
        }
        assert!(zero_length > 1000 && vertical_lifted > 1000);
    }
}
