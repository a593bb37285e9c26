//! A rigid pose with its velocities.

use glam::{EulerRot, Quat, Vec3};

/// Where an object is at one instant, and how fast it moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// World position of the object's local origin, metres.
    pub position: Vec3,
    /// World-from-local rotation.
    pub rotation: Quat,
    /// Linear velocity of the local origin, m/s.
    pub velocity: Vec3,
    /// Angular velocity, rad/s, world frame.
    pub angular_velocity: Vec3,
}

impl Pose {
    /// A pose at rest at `position`.
    #[must_use]
    pub fn at_rest(position: Vec3) -> Self {
        Self {
            position,
            rotation: Quat::IDENTITY,
            velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
        }
    }

    /// Local point → world point.
    #[must_use]
    pub fn to_world(&self, p: Vec3) -> Vec3 {
        self.position + self.rotation * p
    }

    /// World point → local point.
    #[must_use]
    pub fn to_local(&self, p: Vec3) -> Vec3 {
        self.rotation.inverse() * (p - self.position)
    }

    /// Velocity of the material point at world position `p`: `v + ω × (p − c)`.
    /// Its length is the contact point speed used in Eq. 2 (DESIGN §3).
    #[must_use]
    pub fn point_velocity(&self, p: Vec3) -> Vec3 {
        self.velocity + self.angular_velocity.cross(p - self.position)
    }
}

/// The rotation of scene-file Euler angles `[yaw, pitch, roll]` in degrees:
/// yaw about y, then pitch about the turned x, then roll about the turned z,
/// i.e. R = R_y(yaw) R_x(pitch) R_z(roll). Used by `rotation_deg` of objects
/// and of keyframes.
#[must_use]
pub fn rotation_from_euler_deg(degrees: [f32; 3]) -> Quat {
    let [yaw, pitch, roll] = degrees.map(f32::to_radians);
    Quat::from_euler(EulerRot::YXZ, yaw, pitch, roll)
}
