//! STUB
use crate::field::MAX_SEGMENTS;
use crate::obb::ObbTree;
use glam::Vec3;
#[derive(Clone, Copy, Debug, Default)]
pub struct SegmentContact {
    pub dir: Vec3,
    pub point: Vec3,
}
#[derive(Clone, Debug, Default)]
pub struct BladeContacts {
    pub mask: u32,
    pub contacts: [SegmentContact; MAX_SEGMENTS],
}
pub fn collide_segment(_a: Vec3, _b: Vec3, _t: &ObbTree, _p: u32) -> Option<SegmentContact> {
    todo!()
}
pub fn collide_blade(_v: &[Vec3], _t: &ObbTree, _p: u32, _o: &mut BladeContacts) {
    todo!()
}
