//! The driven object: arrow keys set its speed and steering; it moves on
//! the ground plane of its starting height. Plain state, no window: each
//! frame [`Driver::update`] advances it, and the app hands the resulting
//! pose to the simulation ([`trample::Simulation::drive`]).

use crate::input::Held;
use glam::{Quat, Vec3};

/// Handling of the driven object (units in each field).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DriverParams {
    /// Top forward speed, m/s. Default 6 (a brisk run; the default ball's
    /// path goes 3 m/s).
    pub max_speed: f32,
    /// Top reverse speed, m/s. Default 2.
    pub max_reverse: f32,
    /// Acceleration with the throttle held, m/s². Default 4.
    pub accel: f32,
    /// Deceleration with no throttle (rolling to a stop), m/s². Default 3.
    pub coast: f32,
    /// Turn rate at full steering, rad/s. Default 1.5.
    pub turn_rate: f32,
}

impl Default for DriverParams {
    fn default() -> Self {
        Self {
            max_speed: 6.0,
            max_reverse: 2.0,
            accel: 4.0,
            coast: 3.0,
            turn_rate: 1.5,
        }
    }
}

/// Position, heading and speed of the driven object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Driver {
    /// World position of the object's origin, metres.
    pub position: Vec3,
    /// Heading: yaw about +y, radians; forward is `(sin h, 0, cos h)`
    /// (0 = +z, π/2 = +x, as the core's `face_motion`).
    pub heading: f32,
    /// Signed speed along the heading, m/s.
    pub speed: f32,
    /// Orientation, world from local.
    pub rotation: Quat,
    /// Roll radius, metres: when > 0 the object rolls (spins about
    /// `up × forward` by distance / radius) instead of turning to face
    /// its heading.
    pub roll_radius: f32,
    /// Handling.
    pub params: DriverParams,
}

impl Driver {
    /// A driver at rest at `position`, facing `heading`, with `rotation`.
    #[must_use]
    pub fn new(position: Vec3, heading: f32, rotation: Quat, roll_radius: f32) -> Self {
        Self {
            position,
            heading,
            speed: 0.0,
            rotation,
            roll_radius,
            params: DriverParams::default(),
        }
    }

    /// Unit forward direction.
    #[must_use]
    pub fn forward(&self) -> Vec3 {
        Vec3::new(self.heading.sin(), 0.0, self.heading.cos())
    }

    /// Advances `dt` seconds under the held keys: throttle accelerates (or
    /// brakes, then reverses), no throttle coasts to a stop, steering turns
    /// the heading (reversed when going backwards, as a car).
    pub fn update(&mut self, held: &Held, dt: f32) {
        let p = self.params;
        let throttle = held.throttle();
        if throttle != 0.0 {
            self.speed += throttle * p.accel * dt;
        } else {
            let slow = (p.coast * dt).min(self.speed.abs());
            self.speed -= slow * self.speed.signum();
        }
        self.speed = self.speed.clamp(-p.max_reverse, p.max_speed);
        let turn = held.steer() * p.turn_rate * dt * if self.speed < 0.0 { -1.0 } else { 1.0 };
        self.heading += turn;
        let step = self.forward() * (self.speed * dt);
        self.position += step;
        if self.roll_radius > 0.0 {
            let axis = Vec3::Y.cross(self.forward());
            let roll = Quat::from_axis_angle(axis, self.speed * dt / self.roll_radius);
            self.rotation = (roll * self.rotation).normalize();
        } else {
            self.rotation = (Quat::from_rotation_y(turn) * self.rotation).normalize();
        }
    }
}
