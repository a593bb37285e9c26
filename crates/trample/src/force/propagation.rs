//! STUB
use glam::Vec3;
pub const NO_GENERATION: u8 = u8::MAX;
pub struct PropagationParams {
    pub att: f32,
    pub threshold: f32,
    pub max_generations: u32,
}
pub struct PropagationResult {
    pub generations: u32,
    pub pbg: Vec<u32>,
}
pub fn propagate_forces(
    _d: &[u32],
    _n: &[[u32; 4]],
    _f: &mut [Vec3],
    _g: &mut [u8],
    _p: &PropagationParams,
) -> PropagationResult {
    todo!()
}
