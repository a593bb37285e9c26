//! STUB
use crate::field::{MAX_SEGMENTS, Terrain};
use glam::{Vec3, Vec3A};
pub fn weights(_n: usize, _a: f32, _b: f32) -> [f32; MAX_SEGMENTS] {
    todo!()
}
pub fn bend_blade(
    _v: &mut [Vec3A],
    _l: f32,
    _v1: Vec3,
    _n: u32,
    _w: &[f32],
    _t: &Terrain,
    _c: f32,
) {
    todo!()
}
