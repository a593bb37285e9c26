//! STUB
use crate::field::Terrain;
use glam::{Vec3, Vec3A};
pub struct RecoveryParams {
    pub recovery_s: f32,
    pub trail: f32,
}
pub fn recover_blade(
    _v: &mut [Vec3A],
    _r: &[Vec3A],
    _l: f32,
    _dt: f32,
    _p: &RecoveryParams,
    _t: &Terrain,
    _c: f32,
) -> bool {
    todo!()
}
pub fn recover_slope(_s: &mut Vec3, _o: Vec3, _dt: f32, _p: &RecoveryParams) -> bool {
    todo!()
}
