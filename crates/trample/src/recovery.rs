//! Recovery and trails (ours; the paper's future work): DESIGN §6.
//!
//! The paper leaves a bent blade bent: the track of an object lasts for
//! ever. Here every blade (and billboard slope) relaxes towards its rest
//! shape exponentially, with time constant `recovery_s`: after each step the
//! deviation from rest is multiplied by `exp(−dt/τ)`, which is frame-rate
//! independent (two steps of `dt` equal one of `2·dt`). A flattened blade may
//! recover more slowly, leaving a trail: `τ = recovery_s · (1 + trail ·
//! flatness)`. `recovery_s = ∞` is the paper's behaviour.
//!
//! **The tail** ([`RECOVERY_TAIL_M`]): within a centimetre of rest a blade
//! goes on at the speed the exponential has there (`RECOVERY_TAIL_M / τ`)
//! instead of slowing down for ever, so it is back at rest about `τ` after
//! it came within the centimetre, not `τ · ln(1 cm / REST_EPSILON)` ≈ 4.6 `τ`
//! after. The speed is continuous where the two laws meet. A blade that is
//! within a centimetre of rest is not seen to move (less than a pixel
//! wherever blades are drawn as geometry), but until it is at rest it is
//! relaxed, its cell recomputed and its vertices listed for upload
//! (`Simulation::changed_blades`) every step: with the exponential alone, a
//! crowd walking over a meadow with `recovery_s = 6` kept ~270 k blades
//! recovering after a minute, most of them within a centimetre of rest
//! (BENCHMARKS.md, "Session 34").
//!
//! Positions are blended vertex by vertex and the segment lengths are then
//! restored with the same length preservation as the bending
//! ([`preserve_lengths`], Fig. 7). When the largest deviation falls below
//! [`REST_EPSILON`] the blade snaps to its rest shape bit for bit, so a
//! recovered field is exactly the rest field and idle blades can be skipped.

use crate::deform::bend::preserve_lengths;
use crate::field::Terrain;
use glam::{Vec3, Vec3A};

/// Recovery parameters (DESIGN §6, ours).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecoveryParams {
    /// Time constant `τ` of the exponential return to rest, seconds: after
    /// `τ` a blade keeps `1/e` of its deviation (down to
    /// [`RECOVERY_TAIL_M`], then the tail's constant speed). `f32::INFINITY` is the
    /// paper's behaviour (a lasting track, no recovery); `≤ 0` snaps back at
    /// once; NaN means no recovery.
    pub recovery_s: f32,
    /// Trail strength, ≥ 0 (dimensionless): a blade recovers with time
    /// constant `recovery_s · (1 + trail · flatness)`, where
    /// `flatness = 1 − (tip height above root) / (rest tip height above
    /// root)`, clamped to `[0, 1]`. 0: every blade recovers alike; 4: a
    /// flattened blade recovers five times more slowly, so a track stays
    /// visible after the grass brushed aside has stood up again. Negative or
    /// NaN counts as 0.
    pub trail: f32,
}

/// Largest deviation from rest, metres, below which [`recover_blade`] snaps
/// a blade exactly to its rest shape (0.1 mm: far below a pixel at any
/// distance where blades are drawn as geometry). An exponential never
/// reaches rest; without the snap every blade ever touched would stay
/// slightly off rest for ever. [`recover_slope`] uses the same number per
/// unit height (so at most `REST_EPSILON · height` metres at a billboard's
/// top).
pub const REST_EPSILON: f32 = 1e-4;

/// Deviation from rest, metres, below which a blade recovers at a constant
/// speed ([`tail_fraction`]): 1 cm, the deviation at which the exponential's
/// speed `deviation / τ` is kept. [`recover_slope`] uses the same number per
/// unit height, as it does [`REST_EPSILON`].
pub const RECOVERY_TAIL_M: f32 = 0.01;

/// Longest a displaced blade waits between two recoveries when slow
/// blades recover in strides ([`stride_wait`]), seconds: a quarter of a
/// second, so a blade in its tail or held by an owner that does not
/// recover is still looked at four times a second.
pub const RECOVERY_WAIT_MAX_S: f32 = 0.25;

/// Bytes a blade's strides clock takes (`[owed, wait]`, two `f32`: the CPU's
/// `Scratch::recover_clock`, the GPU path's `vec2` clock), counted in the
/// field's memory estimate while strides are on.
pub const RECOVERY_CLOCK_BYTES: u64 = 8;

/// Slow blades recover in strides (ours, issue 16;
/// `SimParams::recovery_stride_m`): how much recovery time a blade must owe
/// before it is relaxed again, seconds, given that its last relaxation, over
/// `recovered_s` seconds, moved it `moved_m` metres (the largest move of a
/// vertex). The time that would move it `stride_m` at that speed, at most
/// [`RECOVERY_WAIT_MAX_S`]: a recovery slows down as it goes (the
/// exponential, then the tail's constant speed), so the next stride moves
/// the blade at most about `stride_m`. 0 — relaxed at the next step, as
/// without strides — when `stride_m` is 0 (or not a number) or no time was
/// recovered (a blade held whole, or one an object just moved); a blade
/// that did not move waits the longest. Continuous in `moved_m` and
/// `recovered_s` where it is not 0 or the cap.
#[must_use]
pub fn stride_wait(stride_m: f32, moved_m: f32, recovered_s: f32) -> f32 {
    if !(stride_m > 0.0 && recovered_s > 0.0) {
        return 0.0;
    }
    if moved_m > 0.0 {
        (stride_m * recovered_s / moved_m).min(RECOVERY_WAIT_MAX_S)
    } else {
        // Not moved, or NaN.
        RECOVERY_WAIT_MAX_S
    }
}

/// The fraction of its way back to rest that a blade `deviation` metres
/// from rest recovers in a step whose exponential fraction is `q`: `q` at
/// [`RECOVERY_TAIL_M`] or more; closer, the fraction that moves it as far
/// as a blade [`RECOVERY_TAIL_M`] from rest moves, `q · RECOVERY_TAIL_M /
/// deviation` (at most 1): a constant speed, continuous in `deviation` and
/// `q`, and frame-rate independent as `q` is to first order. `q = 0` (a held
/// blade, `recovery_s = ∞`) stays 0.
#[must_use]
pub fn tail_fraction(q: f32, deviation: f32) -> f32 {
    if deviation > 0.0 && deviation < RECOVERY_TAIL_M {
        (q * (RECOVERY_TAIL_M / deviation)).min(1.0)
    } else {
        q
    }
}

/// The fraction of a deviation from rest that remains after `dt` seconds of
/// recovery with time constant `tau` seconds: `exp(−dt/τ)`.
///
/// Frame-rate independent: `recovery_factor(dt, τ)² = recovery_factor(2·dt,
/// τ)` in exact arithmetic. `τ = ∞`, `dt ≤ 0` or a NaN input give 1 (no
/// recovery); `τ ≤ 0` gives 0 (instant).
#[must_use]
pub fn recovery_factor(dt: f32, tau: f32) -> f32 {
    match recovery_case(dt, tau) {
        Some(x) => (-x).exp(),
        None if tau <= 0.0 && dt > 0.0 => 0.0,
        None => 1.0,
    }
}

/// `1 − recovery_factor(dt, tau)`, computed without cancellation
/// (`−expm1(−dt/τ)`), so a long `τ` still recovers at small `dt` in f32.
fn recovered_fraction(dt: f32, tau: f32) -> f32 {
    match recovery_case(dt, tau) {
        Some(x) => (-(-x).exp_m1()).clamp(0.0, 1.0),
        None if tau <= 0.0 && dt > 0.0 => 1.0,
        None => 0.0,
    }
}

/// `Some(dt/τ)` for a regular step; `None` for the edge cases handled by
/// the callers (`dt ≤ 0`, `τ ≤ 0`, NaN).
fn recovery_case(dt: f32, tau: f32) -> Option<f32> {
    (dt > 0.0 && tau > 0.0)
        .then(|| dt / tau)
        .filter(|x| !x.is_nan())
}

/// The recovery time constant for a given flatness, seconds (see
/// [`RecoveryParams::trail`]).
fn time_constant(p: &RecoveryParams, flatness: f32) -> f32 {
    // `trail = ∞` with `flatness = 0` must not give NaN.
    let extra = if p.trail > 0.0 && flatness > 0.0 {
        p.trail * flatness
    } else {
        0.0
    };
    p.recovery_s * (1.0 + extra)
}

/// `1 − height / rest_height`, clamped to `[0, 1]`; 0 when the rest height
/// is not positive.
pub(crate) fn flatness(height: f32, rest_height: f32) -> f32 {
    if rest_height > 0.0 {
        let f = 1.0 - height / rest_height;
        if f.is_nan() { 0.0 } else { f.clamp(0.0, 1.0) }
    } else {
        0.0
    }
}

/// Relaxes a blade towards its rest shape for `dt` seconds, in place; returns
/// `true` when the blade is now exactly (bit for bit) at rest.
///
/// Each vertex above the root moves towards its rest position by the
/// recovered fraction `1 − exp(−dt/τ)` ([`recovery_factor`]), with `τ` from
/// [`RecoveryParams`] and the blade's flatness, raised within
/// [`RECOVERY_TAIL_M`] of rest by [`tail_fraction`] (the deviation: the
/// largest distance of a vertex from its rest position); then [`preserve_lengths`]
/// restores the segment lengths and the ground guard. When no vertex is
/// farther than [`REST_EPSILON`] from rest, the blade is set to `rest`.
///
/// - `verts`, `rest`: the blade now and at rest, `n + 1` vertices each,
///   root first, world space, metres. Different lengths: nothing happens,
///   returns `false`.
/// - `seg_len`: the rest length of every segment, metres.
/// - `dt`: the step, seconds.
///
/// `recovery_s = ∞` (or `dt ≤ 0`, or NaN parameters) leaves the blade
/// unchanged and returns whether it is already at rest. A blade with a
/// non-finite vertex cannot be relaxed and is reset to `rest` (returns
/// `true`). Allocation-free.
pub fn recover_blade(
    verts: &mut [Vec3A],
    rest: &[Vec3A],
    seg_len: f32,
    dt: f32,
    p: &RecoveryParams,
    terrain: &Terrain,
    clearance: f32,
) -> bool {
    match recovery_start(verts, rest, dt, p) {
        Start::Done(at_rest) => at_rest,
        Start::Blend(q) => recovery_finish(verts, rest, seg_len, q, terrain, clearance),
    }
}

/// How [`recover_blade`] goes on after its checks ([`recovery_start`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Start {
    /// Nothing to blend: the blade was left as it is, or reset to rest when
    /// it had a non-finite vertex; whether it is at rest.
    Done(bool),
    /// Blend each vertex above the root by this fraction of its way back
    /// ([`recovery_finish`]).
    Blend(f32),
}

/// [`recover_blade`]'s checks and its fraction: the blade at rest, not
/// finite (reset to `rest` here), or not recovering this step (`q = 0`:
/// held, `recovery_s = ∞`) is done; otherwise the fraction of its way back
/// it recovers, [`tail_fraction`] of the exponential's.
pub(crate) fn recovery_start(
    verts: &mut [Vec3A],
    rest: &[Vec3A],
    dt: f32,
    p: &RecoveryParams,
) -> Start {
    if verts.len() != rest.len() || verts.is_empty() {
        return Start::Done(false);
    }
    if verts == rest {
        return Start::Done(true);
    }
    if !verts.iter().all(|v| v.is_finite()) {
        verts.copy_from_slice(rest);
        return Start::Done(true);
    }
    let n = verts.len() - 1;
    let flat = flatness(verts[n].y - verts[0].y, rest[n].y - rest[0].y);
    let q = recovered_fraction(dt, time_constant(p, flat));
    if q == 0.0 {
        return Start::Done(false);
    }
    let deviation = verts
        .iter()
        .zip(rest)
        .map(|(v, r)| v.distance_squared(*r))
        .fold(0.0, f32::max)
        .sqrt();
    Start::Blend(tail_fraction(q, deviation))
}

/// [`recover_blade`] after [`recovery_start`] gave `Blend(q)`: every vertex
/// above the root moves the fraction `q` of its way to rest, the lengths are
/// restored ([`preserve_lengths`]), and a blade within [`REST_EPSILON`] of
/// rest is set to it. Returns whether it is at rest.
pub(crate) fn recovery_finish(
    verts: &mut [Vec3A],
    rest: &[Vec3A],
    seg_len: f32,
    q: f32,
    terrain: &Terrain,
    clearance: f32,
) -> bool {
    for (v, r) in verts.iter_mut().zip(rest).skip(1) {
        *v += (*r - *v) * q;
    }
    preserve_lengths(verts, seg_len, terrain, clearance);
    let at_rest = verts
        .iter()
        .zip(rest)
        .all(|(v, r)| v.distance_squared(*r) < REST_EPSILON * REST_EPSILON);
    if at_rest {
        verts.copy_from_slice(rest);
    }
    at_rest
}

/// Relaxes a billboard's slope (Eq. 8, 12) towards its rest slope for `dt`
/// seconds, with the same law as [`recover_blade`] (its tail within
/// [`RECOVERY_TAIL_M`] per unit height of rest); returns `true` when the
/// slope is now exactly `slope_origin`.
///
/// Flatness of a slope: `1 − ŝ.y / ô.y` (`ŝ`, `ô` the normalised slope and
/// rest slope: the top's height over its rest height). The slope snaps to
/// `slope_origin` when it is within [`REST_EPSILON`] of it (per unit height).
/// `recovery_s = ∞` leaves it unchanged; a non-finite slope is reset to
/// `slope_origin`.
pub fn recover_slope(slope: &mut Vec3, slope_origin: Vec3, dt: f32, p: &RecoveryParams) -> bool {
    if *slope == slope_origin {
        return true;
    }
    if !slope.is_finite() {
        *slope = slope_origin;
        return true;
    }
    let height = slope.normalize_or_zero().y;
    let rest_height = slope_origin.normalize_or_zero().y;
    let q = recovered_fraction(dt, time_constant(p, flatness(height, rest_height)));
    if q == 0.0 {
        return false;
    }
    let q = tail_fraction(q, slope.distance(slope_origin));
    *slope += (slope_origin - *slope) * q;
    let at_rest = slope.distance_squared(slope_origin) < REST_EPSILON * REST_EPSILON;
    if at_rest {
        *slope = slope_origin;
    }
    at_rest
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stride's wait: the time that moves the blade a stride at its
    /// last speed, capped; none without a stride, without time recovered,
    /// or for a NaN stride; the longest for a blade that did not move.
    #[test]
    fn a_stride_waits_for_the_time_that_moves_a_blade_a_stride() {
        // 1 mm a stride, moved 0.5 mm in 1/60 s: two steps' time.
        assert!((stride_wait(1e-3, 5e-4, 1.0 / 60.0) - 2.0 / 60.0).abs() < 1e-7);
        // Slower: longer, up to the cap.
        assert!(stride_wait(1e-3, 1e-4, 1.0 / 60.0) > stride_wait(1e-3, 2e-4, 1.0 / 60.0));
        assert_eq!(stride_wait(1e-3, 1e-6, 1.0 / 60.0), RECOVERY_WAIT_MAX_S);
        // Faster than a stride a step: less than a step's wait.
        assert!(stride_wait(1e-3, 0.05, 1.0 / 60.0) < 1.0 / 60.0);
        assert_eq!(stride_wait(0.0, 5e-4, 1.0 / 60.0), 0.0);
        assert_eq!(stride_wait(f32::NAN, 5e-4, 1.0 / 60.0), 0.0);
        assert_eq!(stride_wait(1e-3, 5e-4, 0.0), 0.0);
        assert_eq!(stride_wait(1e-3, 0.0, 1.0 / 60.0), RECOVERY_WAIT_MAX_S);
        assert_eq!(stride_wait(1e-3, f32::NAN, 1.0 / 60.0), RECOVERY_WAIT_MAX_S);
        // Continuous in the move: a few ulp apart, a few ulp apart.
        let (a, b) = (3e-4f32, f32::from_bits(3e-4f32.to_bits() + 2));
        let (wa, wb) = (stride_wait(1e-3, a, 0.02), stride_wait(1e-3, b, 0.02));
        assert!((wa - wb).abs() <= 4.0 * f32::EPSILON * wa, "{wa} {wb}");
    }
}
