//! Collision between blades and objects (paper §4, DESIGN §4): broad phase
//! over patches, narrow phase of segments through the OBB tree down to a
//! chosen precision, and an exact reference (segment vs triangles plus an
//! inside test for closed meshes). One query per file, named by shape pair.

pub mod broad_phase;
pub mod closest_point;
pub mod contact;
pub mod exact;
pub mod inside_grid;
pub mod narrow_phase;
pub mod segment_obb;
pub mod segment_obb_wide;
pub mod segment_slabs;
pub mod segment_triangle;

pub use broad_phase::{
    PatchRect, obb_may_overlap_aabb, obb_overlaps_aabb, patch_rect, patches_hit, patches_under,
    world_obb,
};
pub use exact::{point_inside, segment_hits_exact};
pub use narrow_phase::{
    BladeContacts, LocalMotion, SegmentContact, collide_blade, collide_segment, contact_blade,
    contact_segment,
};
pub use segment_obb::{segment_hits_box_local, segment_hits_obb};
pub use segment_obb_wide::Segments4;
pub use segment_triangle::{segment_crosses_triangle_interior, segment_hits_triangle};
