//! The external force on a blade hit directly (DBG): paper §5.1, Eq. 2.
//!
//! `EqF = |v| · EqN`. The object's speed sets the magnitude, the equivalent
//! normal EqN (Eq. 3) of the OBB-tree node the blade hit sets the direction.

use glam::Vec3;

/// The equivalent force `EqF` on a directly hit blade (DBG), Eq. 2:
/// `EqF = speed · EqN`, in m/s.
///
/// - `speed`: the speed of the object's surface at the contact point,
///   `|v + ω × r|` (DESIGN §3, ours; equals `|v|` of Eq. 2 for an object that
///   does not spin), m/s. Eq. 2 uses a magnitude, so the sign is dropped.
/// - `eqn_dir`: the equivalent normal EqN (Eq. 3) used as a direction
///   (DESIGN §3). It is normalised here, so a summed EqN of several nodes may
///   be passed as is.
///
/// Returns [`Vec3::ZERO`] (no force: the blade stays as it is) when `eqn_dir`
/// is zero or either input is not finite.
///
/// The deformation does not take this force directly: the caller turns it
/// into the displacement of one step, `v1 = EqF · dt` (DESIGN §6), for
/// [`crate::deform::bend::bend_blade`].
#[must_use]
pub fn eqf(speed: f32, eqn_dir: Vec3) -> Vec3 {
    let force = eqn_dir.normalize_or_zero() * speed.abs();
    if force.is_finite() { force } else { Vec3::ZERO }
}
