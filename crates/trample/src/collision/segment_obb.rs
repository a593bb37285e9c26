//! STUB
use crate::obb::Obb;
use glam::Vec3;
pub fn segment_hits_obb(_a: Vec3, _b: Vec3, _o: &Obb) -> bool {
    todo!()
}
