//! STUB
use crate::field::Terrain;
use glam::Vec3;
pub fn billboard_slope(_o: Vec3, _t: Vec3, _r: f32) -> Vec3 {
    todo!()
}
pub fn deflect_billboard(_c: Vec3, _o: Vec3, _x: Vec3) -> Vec3 {
    todo!()
}
pub fn billboard_top(_b: Vec3, _s: Vec3, _h: f32, _t: &Terrain, _c: f32) -> Vec3 {
    todo!()
}
