//! STUB
use crate::field::Patch;
use crate::obb::Obb;
use crate::object::Pose;
pub fn world_obb(_l: &Obb, _p: &Pose) -> Obb {
    todo!()
}
pub fn patches_hit(_p: &[Patch], _o: &Obb, _out: &mut Vec<u32>) {
    todo!()
}
