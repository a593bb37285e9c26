//! STUB
use glam::Vec3;
pub fn eqf(s: f32, d: Vec3) -> Vec3 {
    s * d
}
