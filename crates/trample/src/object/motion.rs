//! How an object moves: its path, how it turns, and when it starts.
//!
//! [`Motion::pose_at`] is a pure function of the simulation time t: the same
//! t gives the same [`Pose`], bit for bit, whatever was asked before, so the
//! simulation does not depend on the frame rate.

use super::object::Orientation;
use super::path::Path;
use super::pose::Pose;
use super::rolling::{self, Rolling};
use glam::{Quat, Vec3};

/// Why a motion was refused. Messages name the scene key.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MotionError {
    /// `start_s` is NaN or infinite.
    #[error("start_s = {value}: must be finite")]
    NonFiniteStart {
        /// The value.
        value: f32,
    },
    /// `orientation = "keyframes"` on a path that has no key rotations.
    #[error(
        "orientation = \"keyframes\" needs a keyframes path with rotation_deg on its keys; {found}"
    )]
    KeyframesWithoutRotations {
        /// What the path is instead.
        found: String,
    },
    /// `orientation = "rolling"` with no ground contact below the origin.
    #[error(
        "orientation = \"rolling\" needs the mesh's lowest point below its origin (a roll radius > 0); the roll radius is {radius} m"
    )]
    RollRadius {
        /// The roll radius, metres: the origin's height above the lowest point.
        radius: f32,
    },
}

/// A validated motion: path + orientation rule + start time (+ the rolling
/// rotation, precomputed).
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    path: Path,
    orientation: Orientation,
    start_s: f32,
    roll_radius: f32,
    rolling: Option<Rolling>,
}

impl Motion {
    /// A motion along `path` that starts at simulation time `start_s`
    /// seconds. `roll_radius` (metres, the height of the mesh's origin above
    /// its lowest point) is only used by [`Orientation::Rolling`], whose
    /// rotation table is built here.
    ///
    /// # Errors
    /// [`MotionError`] for a non-finite `start_s`, `Rolling` without a
    /// finite `roll_radius` > 0, `Keyframes` without key rotations.
    pub fn new(
        path: Path,
        orientation: Orientation,
        start_s: f32,
        roll_radius: f32,
    ) -> Result<Self, MotionError> {
        if !start_s.is_finite() {
            return Err(MotionError::NonFiniteStart { value: start_s });
        }
        let rolling = match orientation {
            Orientation::Rolling if !(roll_radius.is_finite() && roll_radius > 0.0) => {
                return Err(MotionError::RollRadius {
                    radius: roll_radius,
                });
            }
            Orientation::Rolling => Some(Rolling::new(&path, roll_radius)),
            Orientation::Keyframes if path.keyframe_rotation(0.0).is_none() => {
                let kind = path.params().kind_name();
                let found = match kind {
                    "keyframes" => "its keys have no rotation_deg".to_owned(),
                    _ => format!("the path is a {kind}"),
                };
                return Err(MotionError::KeyframesWithoutRotations { found });
            }
            _ => None,
        };
        Ok(Self {
            path,
            orientation,
            start_s,
            roll_radius,
            rolling,
        })
    }

    /// The path.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The orientation rule.
    #[must_use]
    pub fn orientation(&self) -> Orientation {
        self.orientation
    }

    /// Simulation time at which path time 0 is reached, seconds.
    #[must_use]
    pub fn start_s(&self) -> f32 {
        self.start_s
    }

    /// Roll radius, metres (meaningful for rolling objects).
    #[must_use]
    pub fn roll_radius(&self) -> f32 {
        self.roll_radius
    }

    /// The pose at simulation time `t`, seconds: position and velocity from
    /// the path at path time `t − start_s` (before that the object waits at
    /// the path's start, at rest), rotation and angular velocity from the
    /// orientation rule:
    /// - `Fixed`: identity, ω = 0.
    /// - `FaceMotion`: a yaw that turns mesh +z to the horizontal direction
    ///   of travel ([`Path::heading`]: held while stopped, the initial one
    ///   before the start), ω = yaw rate about +y (from the path's
    ///   acceleration; 0 on straight segments, whose corners turn at once).
    /// - `Rolling`: the rolling rotation ([`Rolling`]), ω = (up × v) / r.
    /// - `Keyframes`: the keys' rotations, slerped.
    #[must_use]
    pub fn pose_at(&self, t: f32) -> Pose {
        let tau = t - self.start_s;
        let velocity = self.path.velocity(tau);
        let (rotation, angular_velocity) = match self.orientation {
            Orientation::Fixed => (Quat::IDENTITY, Vec3::ZERO),
            Orientation::FaceMotion => {
                let yaw = self.path.heading(tau).map_or(0.0, |h| h.x.atan2(h.z));
                (
                    Quat::from_rotation_y(yaw),
                    Vec3::Y * yaw_rate(velocity, self.path.acceleration(tau)),
                )
            }
            Orientation::Rolling => (
                self.rolling
                    .as_ref()
                    .map_or(Quat::IDENTITY, |r| r.rotation(tau)),
                rolling::angular_velocity(&self.path, self.roll_radius, tau),
            ),
            Orientation::Keyframes => (
                self.path.keyframe_rotation(tau).unwrap_or(Quat::IDENTITY),
                self.path
                    .keyframe_angular_velocity(tau)
                    .unwrap_or(Vec3::ZERO),
            ),
        };
        Pose {
            position: self.path.position(tau),
            rotation,
            velocity,
            angular_velocity,
        }
    }
}

/// dψ/dt of the heading ψ = atan2(vx, vz), rad/s; 0 without horizontal motion.
fn yaw_rate(velocity: Vec3, acceleration: Vec3) -> f32 {
    let horizontal2 = velocity.x * velocity.x + velocity.z * velocity.z;
    if horizontal2 <= 1e-12 {
        return 0.0;
    }
    (velocity.z * acceleration.x - velocity.x * acceleration.z) / horizontal2
}
