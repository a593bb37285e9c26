//! The accumulated rotation of an object rolling without slipping (ours,
//! DESIGN §3): it spins at ω(t) = (up × v(t)) / r, r = roll radius, so the
//! material point touching the ground (r below the origin) has no horizontal
//! velocity. R(t) solves dR/dt = [ω(t)]× R, R(start) = identity.
//!
//! The rotation must be a pure function of t (the same t gives the same
//! bits however many steps led there), so it is never integrated step by
//! step during the simulation:
//! - on a circle it has a closed form (below);
//! - on any other path it is integrated once, at construction, with a fixed
//!   step into a table, and looked up with slerp.

use super::path::Path;
use glam::{DQuat, DVec3, Quat, Vec3};
use std::f64::consts::TAU;

/// Integration step of the table, seconds: 1/240 s, a quarter of a 60 Hz
/// frame, so a ball turns at most |v| / (240 r) rad per step.
pub const ROLL_STEP_S: f64 = 1.0 / 240.0;
/// Most table entries (1 MiB of rotations). Paths longer than
/// `MAX_ROLL_STEPS × ROLL_STEP_S` ≈ 273 s get a proportionally longer step;
/// the error stays zero on straight segments (constant axis: slerp is exact)
/// and only grows at turns.
pub const MAX_ROLL_STEPS: usize = 1 << 16;

/// The rolling rotation of one object along one path.
#[derive(Clone, Debug, PartialEq)]
pub enum Rolling {
    /// On a circle of angular rate Ω about y, ω(t) turns with the path:
    /// ω(t) = R_y(Ωt) ω₀. Then R(t) = R_y(Ωt) · exp([ω₀ − Ω ŷ] t), since
    /// B = R_y(Ωt)⁻¹ R obeys dB/dt = [R_y⁻¹ ω − Ω ŷ] B = [ω₀ − Ω ŷ] B with
    /// a constant rate. Exact at every t, and R(kP + τ) = R(τ) R(P)^k.
    Circle {
        /// Ω, rad/s about +y.
        omega_path: f64,
        /// ω₀ − Ω ŷ, rad/s.
        body_rate: DVec3,
    },
    /// Rotations at `start + k × step`, integrated with the midpoint rule in
    /// f64; held before the first and after the last.
    Table {
        /// Path time of the first entry, seconds.
        start: f32,
        /// Time between entries, seconds (> 0).
        step: f64,
        /// At least one entry.
        rotations: Vec<Quat>,
    },
}

impl Rolling {
    /// The rolling rotation along `path` with roll radius `radius` metres
    /// (precondition: finite and > 0, checked by [`super::motion::Motion::new`]).
    #[must_use]
    pub fn new(path: &Path, radius: f32) -> Self {
        let rate = |t: f32| angular_velocity(path, radius, t).as_dvec3();
        let Some(end) = path.end_time() else {
            let omega_path = path_angular_rate(path);
            return Rolling::Circle {
                omega_path,
                body_rate: rate(0.0) - DVec3::Y * omega_path,
            };
        };
        let start = path.start_time();
        let duration = f64::from(end) - f64::from(start);
        let steps = ((duration / ROLL_STEP_S).ceil() as usize).clamp(1, MAX_ROLL_STEPS);
        let step = (duration / steps as f64).max(f64::MIN_POSITIVE);
        let mut rotations = Vec::with_capacity(steps + 1);
        let mut r = DQuat::IDENTITY;
        rotations.push(Quat::IDENTITY);
        for k in 0..steps {
            let middle = f64::from(start) + (k as f64 + 0.5) * step;
            r = (exp(rate(middle as f32) * step) * r).normalize();
            rotations.push(r.as_quat());
        }
        Rolling::Table {
            start,
            step,
            rotations,
        }
    }

    /// The accumulated rotation at path time `t` (identity before the path
    /// starts).
    #[must_use]
    pub fn rotation(&self, t: f32) -> Quat {
        match self {
            &Rolling::Circle {
                omega_path,
                body_rate,
            } => {
                if t.is_nan() || t <= 0.0 {
                    return Quat::IDENTITY;
                }
                let t = f64::from(t);
                let revolution = DQuat::from_rotation_y((omega_path * t) % TAU);
                let rate = body_rate.length();
                let spin = match body_rate.try_normalize() {
                    Some(axis) => DQuat::from_axis_angle(axis, (rate * t) % TAU),
                    None => DQuat::IDENTITY,
                };
                (revolution * spin).as_quat()
            }
            Rolling::Table {
                start,
                step,
                rotations,
            } => {
                let last = rotations.len() - 1;
                let x = (f64::from(t) - f64::from(*start)) / step;
                if x.is_nan() || x <= 0.0 {
                    return rotations[0];
                }
                if x >= last as f64 {
                    return rotations[last];
                }
                let k = x.floor() as usize;
                rotations[k].slerp(rotations[k + 1], (x - k as f64) as f32)
            }
        }
    }
}

/// ω = (up × v) / r at path time `t`, rad/s, world frame.
#[must_use]
pub fn angular_velocity(path: &Path, radius: f32, t: f32) -> Vec3 {
    Vec3::Y.cross(path.velocity(t)) / radius
}

/// Ω of a circle path, rad/s: the rate at which its velocity turns about +y.
fn path_angular_rate(path: &Path) -> f64 {
    match path.params() {
        super::path::PathParams::Circle { period_s, .. } => TAU / f64::from(*period_s),
        _ => 0.0,
    }
}

/// exp of the rotation vector `v` (axis × angle) as a quaternion.
fn exp(v: DVec3) -> DQuat {
    let angle = v.length();
    if angle > 0.0 {
        DQuat::from_axis_angle(v / angle, angle)
    } else {
        DQuat::IDENTITY
    }
}
