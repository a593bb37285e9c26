//! The accumulated rotation of an object rolling without slipping (ours,
//! DESIGN §3): it spins at ω(t) = (up × v(t)) / r, r = roll radius, so the
//! material point touching the ground (r below the origin) has no horizontal
//! velocity. R(t) solves dR/dt = [ω(t)]× R, R(start) = identity.
//!
//! The rotation must be a pure function of t (the same t gives the same
//! bits however many steps led there), so it is never integrated step by
//! step during the simulation. It is computed at construction:
//! - on a circle, in closed form;
//! - on straight segments (static, line, polyline, keyframes), exactly: ω is
//!   constant on each segment, so R is a product of axis-angle rotations;
//! - on a spline, by integration with a fixed step into a table, looked up
//!   with slerp.

use super::path::Path;
use glam::{DQuat, DVec3, Quat, Vec3};
use std::f64::consts::TAU;

/// Longest integration step of the spline table, seconds: 1/240 s, a
/// quarter of a 60 Hz frame.
pub const ROLL_STEP_S: f64 = 1.0 / 240.0;
/// Largest turn per table step, radians: slerp between entries then stays
/// within 10⁻³ rad of the integrated rotation where the axis turns.
pub const MAX_ROLL_STEP_ANGLE: f64 = 0.25;
/// Most table entries (4 MiB of rotations): a spline longer than
/// 65,536 roll radii gets larger steps than [`MAX_ROLL_STEP_ANGLE`].
pub const MAX_ROLL_STEPS: usize = 1 << 18;

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
    /// Straight segments: on segment i (from `times[i]` to `times[i + 1]`)
    /// R(t) = exp(ωᵢ (t − tᵢ)) Rᵢ. Held before the first time and after the
    /// last.
    Segments {
        /// Segment start times, seconds, increasing; at least one.
        times: Vec<f32>,
        /// Rᵢ, the rotation at each time (f64 products).
        rotations: Vec<DQuat>,
        /// ωᵢ, rad/s, one per segment (one fewer than `times`).
        rates: Vec<DVec3>,
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
        let rate = |t: f64| angular_velocity(path, radius, t as f32).as_dvec3();
        let Some(end) = path.end_time() else {
            let omega_path = path_angular_rate(path);
            return Rolling::Circle {
                omega_path,
                body_rate: rate(0.0) - DVec3::Y * omega_path,
            };
        };
        if let Some(times) = path.breakpoints() {
            let rates: Vec<DVec3> = times
                .windows(2)
                .map(|w| rate(0.5 * (f64::from(w[0]) + f64::from(w[1]))))
                .collect();
            let mut rotations = vec![DQuat::IDENTITY];
            for (w, &omega) in times.windows(2).zip(&rates) {
                let previous = *rotations.last().unwrap_or(&DQuat::IDENTITY);
                let duration = f64::from(w[1]) - f64::from(w[0]);
                rotations.push((exp(omega * duration) * previous).normalize());
            }
            return Rolling::Segments {
                times: times.to_vec(),
                rotations,
                rates,
            };
        }
        let start = path.start_time();
        let duration = f64::from(end) - f64::from(start);
        let turn = f64::from(path.length().unwrap_or(0.0)) / f64::from(radius);
        let steps = (duration / ROLL_STEP_S)
            .max(turn / MAX_ROLL_STEP_ANGLE)
            .ceil()
            .clamp(1.0, MAX_ROLL_STEPS as f64) as usize;
        let step = (duration / steps as f64).max(f64::MIN_POSITIVE);
        let mut rotations = Vec::with_capacity(steps + 1);
        let mut r = DQuat::IDENTITY;
        rotations.push(Quat::IDENTITY);
        for k in 0..steps {
            let middle = f64::from(start) + (k as f64 + 0.5) * step;
            r = (exp(rate(middle) * step) * r).normalize();
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
                // f64 keeps late times precise (and quaternions continuous in t).
                let revolution = DQuat::from_rotation_y(omega_path * t);
                (revolution * exp(body_rate * t)).as_quat()
            }
            Rolling::Segments {
                times,
                rotations,
                rates,
            } => {
                if t.is_nan() || t <= times[0] {
                    return rotations[0].as_quat();
                }
                let i = times.partition_point(|&k| k <= t) - 1;
                match rates.get(i) {
                    Some(&omega) => {
                        let elapsed = f64::from(t) - f64::from(times[i]);
                        (exp(omega * elapsed) * rotations[i]).as_quat()
                    }
                    None => rotations[rotations.len() - 1].as_quat(),
                }
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
