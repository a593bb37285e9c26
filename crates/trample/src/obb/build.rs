//! STUB
use super::*;
use crate::object::TriMesh;
pub const DEFAULT_MAX_DEPTH: u32 = 32;
impl ObbTree {
    pub fn build(_m: &TriMesh, _d: u32) -> ObbTree {
        todo!()
    }
}
