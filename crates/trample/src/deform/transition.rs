//! STUB
use crate::field::Terrain;
use glam::{Vec3, Vec3A};
pub fn blade_offset(_a: Vec3, _b: Vec3) -> Vec3 {
    todo!()
}
pub fn mean_offset(_o: impl IntoIterator<Item = Vec3>) -> Vec3 {
    todo!()
}
pub fn slope_from_offset(_o: Vec3, _f: Vec3) -> Vec3 {
    todo!()
}
pub fn offset_from_slope(_s: Vec3, _o: Vec3) -> Vec3 {
    todo!()
}
pub fn bend_last_segment(_v: &mut [Vec3A], _l: f32, _v1: Vec3, _t: &Terrain, _c: f32) {
    todo!()
}
