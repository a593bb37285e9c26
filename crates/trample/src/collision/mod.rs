//! Collision between blades and objects (paper §4, DESIGN §4): broad phase
//! over patches, narrow phase of segments through the OBB tree down to a
//! chosen precision, and an exact reference (segment vs triangles plus an
//! inside test for closed meshes).

pub mod broad_phase;
pub mod exact;
pub mod narrow_phase;
pub mod segment_obb;
pub mod segment_triangle;
