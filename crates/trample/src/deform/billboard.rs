//! Deforming a billboard (one per cell at middle distance): paper §6.2,
//! Eq. 8; DESIGN §6.
//!
//! A billboard is bent through its **slope vector** `slope^b`: when its
//! skeleton line (base centre → top) meets the object's root OBB,
//! `slope^b = slope^b_origin + t · R / |t|²` (Eq. 8), `t` from the OBB centre
//! to the billboard centre and `R` half the OBB diagonal: the closer the
//! object, the larger the slope. Slopes are dimensionless directions "per
//! unit height" (DESIGN §6): the top edge is drawn at
//! `base + normalize(slope) · height` ([`billboard_top`]).

use super::bend::guarded_end;
use crate::field::Terrain;
use glam::{Vec3, Vec3A};

/// Below this distance (metres) between the OBB centre and the billboard
/// centre, `t` of Eq. 8 has no usable direction (the object sits on the
/// billboard): [`billboard_slope`] then pushes straight down, with the
/// magnitude Eq. 8 has at this distance.
pub const MIN_T: f32 = 1e-4;

/// The slope of a billboard under an object, Eq. 8:
/// `slope^b = slope^b_origin + t · R / |t|²`, dimensionless.
///
/// - `slope_origin`: the billboard's rest slope (per unit height, length ≈ 1).
/// - `t`: from the centre of the object's root OBB to the centre of the
///   billboard, metres.
/// - `r`: `R`, half the length of the OBB's diagonal, metres (≥ 0).
///
/// The caller tests first that the billboard's skeleton line meets the OBB.
/// When `|t| < `[`MIN_T`] the deflection is straight down (`−y`) with
/// magnitude `R / MIN_T`. A negative or non-finite `r`, or a non-finite `t`,
/// leaves `slope_origin` as it is.
///
/// See also [`deflect_billboard`], which keeps the strongest deflection of a
/// passing object.
#[must_use]
pub fn billboard_slope(slope_origin: Vec3, t: Vec3, r: f32) -> Vec3 {
    if !t.is_finite() || !r.is_finite() || r < 0.0 {
        return slope_origin;
    }
    let t2 = t.length_squared();
    if t2 < MIN_T * MIN_T {
        slope_origin + Vec3::NEG_Y * (r / MIN_T)
    } else {
        slope_origin + t * (r / t2)
    }
}

/// The billboard's slope after an object's Eq. 8 gives `candidate` (ours):
/// whichever of `current` and `candidate` is farther from `slope_origin`.
///
/// Eq. 8 alone would make a billboard spring back as soon as the object
/// moves on (the deflection falls off as `1/|t|`); keeping the larger one
/// leaves the deflection of the object's closest approach, which recovery
/// (`crate::recovery::recover_slope`) then relaxes. A non-finite `candidate`
/// is ignored; a non-finite `current` is replaced by `candidate`. Ties keep
/// `current`.
#[must_use]
pub fn deflect_billboard(current: Vec3, slope_origin: Vec3, candidate: Vec3) -> Vec3 {
    if !candidate.is_finite() {
        return current;
    }
    if !current.is_finite() {
        return candidate;
    }
    if candidate.distance_squared(slope_origin) > current.distance_squared(slope_origin) {
        candidate
    } else {
        current
    }
}

/// The centre of a billboard's top edge: `base + normalize(slope) · height`
/// (DESIGN §6: slopes are directions; Eq. 12's `· height_g`), metres.
///
/// - `base`: the centre of the billboard's bottom edge, on the ground.
/// - `slope`: its slope; zero or non-finite means straight up.
/// - `height`: the billboard's height, metres; ≤ 0 or non-finite gives `base`.
///
/// Ground guard as for blades
/// ([`preserve_lengths`](super::bend::preserve_lengths)): a top that would
/// go below `terrain + clearance` is rotated up about `base`, keeping its
/// horizontal direction and the height.
#[must_use]
pub fn billboard_top(
    base: Vec3,
    slope: Vec3,
    height: f32,
    terrain: &Terrain,
    clearance: f32,
) -> Vec3 {
    if !base.is_finite() || !height.is_finite() || height <= 0.0 {
        return base;
    }
    let dir = Vec3A::from(slope).try_normalize().unwrap_or(Vec3A::Y);
    let clearance = if clearance.is_finite() {
        clearance
    } else {
        0.0
    };
    guarded_end(base.into(), dir, height, terrain, clearance, || Vec3A::X).into()
}
