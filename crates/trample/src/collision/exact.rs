//! STUB
use crate::obb::ObbTree;
use glam::Vec3;
pub fn segment_hits_exact(_t: &ObbTree, _a: Vec3, _b: Vec3) -> bool {
    todo!()
}
