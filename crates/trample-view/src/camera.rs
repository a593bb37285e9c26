//! Camera controllers: orbit around the first object, free-fly, or the
//! scene's own camera path. Plain state; the app turns the current one into
//! the simulation's camera (whose eye is also the LOD viewpoint).

use glam::Vec3;

/// Which camera is in use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CameraMode {
    /// Around the first object (mouse drag turns, wheel zooms).
    #[default]
    Orbit,
    /// Free flight: WASD moves, Q/E down/up, mouse drag looks.
    Fly,
    /// The scene file's camera path.
    Scene,
}

impl CameraMode {
    /// The next mode (the camera key cycles through them).
    #[must_use]
    pub fn next(self) -> Self {
        match self {
            Self::Orbit => Self::Fly,
            Self::Fly => Self::Scene,
            Self::Scene => Self::Orbit,
        }
    }

    /// Name shown in the panel.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Orbit => "orbit",
            Self::Fly => "free-fly",
            Self::Scene => "scene path",
        }
    }
}

/// Radians of turn per pixel of mouse drag.
const TURN_PER_PIXEL: f32 = 0.005;
/// Pitch limit, radians (short of straight up or down, where yaw is undefined).
const MAX_PITCH: f32 = 1.5;

/// Direction at `yaw` (about +y, 0 = +z) and `pitch` (up from horizontal).
fn direction(yaw: f32, pitch: f32) -> Vec3 {
    Vec3::new(
        pitch.cos() * yaw.sin(),
        pitch.sin(),
        pitch.cos() * yaw.cos(),
    )
}

/// Orbit camera: the eye on a sphere around a target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Yaw of the eye around the target, radians.
    pub yaw: f32,
    /// Height angle of the eye above the target, radians.
    pub pitch: f32,
    /// Distance from the target, metres.
    pub distance: f32,
}

impl Default for Orbit {
    fn default() -> Self {
        Self {
            yaw: -0.9,
            pitch: 0.35,
            distance: 7.0,
        }
    }
}

impl Orbit {
    /// The eye for `target`.
    #[must_use]
    pub fn eye(&self, target: Vec3) -> Vec3 {
        target + direction(self.yaw, self.pitch) * self.distance
    }

    /// A mouse drag of (dx, dy) pixels turns around the target.
    pub fn drag(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * TURN_PER_PIXEL;
        self.pitch = (self.pitch + dy * TURN_PER_PIXEL).clamp(0.02, MAX_PITCH);
    }

    /// A wheel of `lines` notches zooms (positive: closer).
    pub fn zoom(&mut self, lines: f32) {
        self.distance = (self.distance * 0.9f32.powf(lines)).clamp(1.0, 150.0);
    }
}

/// Free-fly camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fly {
    /// Eye, metres.
    pub eye: Vec3,
    /// Yaw of the view direction, radians (0 = +z).
    pub yaw: f32,
    /// Pitch of the view direction, radians.
    pub pitch: f32,
    /// Speed, m/s (Shift doubles it).
    pub speed: f32,
}

impl Fly {
    /// A camera at `eye` looking at `target`.
    #[must_use]
    pub fn looking_at(eye: Vec3, target: Vec3) -> Self {
        let d = (target - eye).normalize_or(Vec3::Z);
        Self {
            eye,
            yaw: d.x.atan2(d.z),
            pitch: d.y.asin().clamp(-MAX_PITCH, MAX_PITCH),
            speed: 5.0,
        }
    }

    /// Unit view direction.
    #[must_use]
    pub fn forward(&self) -> Vec3 {
        direction(self.yaw, self.pitch)
    }

    /// The point looked at (one metre ahead).
    #[must_use]
    pub fn target(&self) -> Vec3 {
        self.eye + self.forward()
    }

    /// Moves `dt` seconds along `input` = (right, up, forward) axes in [-1, 1].
    pub fn update(&mut self, input: Vec3, fast: bool, dt: f32) {
        let forward = self.forward();
        let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        let v = right * input.x + Vec3::Y * input.y + forward * input.z;
        let speed = self.speed * if fast { 2.0 } else { 1.0 };
        self.eye += v.normalize_or_zero() * speed * dt;
    }

    /// A mouse drag of (dx, dy) pixels turns the view.
    pub fn drag(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * TURN_PER_PIXEL;
        self.pitch = (self.pitch - dy * TURN_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
    }
}
