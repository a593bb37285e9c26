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
pub mod winding;
pub mod winding_grid;

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

/// Pairs of faces that share an edge, for the continuity tests of the
/// contact push (`contact`, `narrow_phase`).
#[cfg(test)]
pub(crate) mod test_edges {
    use crate::obb::ObbTree;
    use glam::Vec3;

    /// A face edge of `tree`'s mesh: its midpoint, the way into the mesh
    /// halfway between its two faces' normals, and the way across the
    /// plane halfway between them (both unit).
    pub(crate) struct Edge {
        pub(crate) triangle: usize,
        pub(crate) mid: Vec3,
        pub(crate) inward: Vec3,
        pub(crate) across: Vec3,
    }

    /// `count` edges: the first edge of every `step`-th triangle that has
    /// a triangle across it later in the mesh.
    pub(crate) fn edges(tree: &ObbTree, step: usize, count: usize) -> Vec<Edge> {
        let tris = &tree.triangles;
        let normal = |t: &[Vec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        let shares = |b: &[Vec3; 3], v: Vec3| b.iter().any(|w| w.distance(v) < 1e-6);
        let found: Vec<Edge> = tris
            .iter()
            .enumerate()
            .step_by(step)
            .filter_map(|(i, a)| {
                let b = tris
                    .iter()
                    .skip(i + 1)
                    .find(|b| shares(b, a[0]) && shares(b, a[1]))?;
                let (na, nb) = (normal(a), normal(b));
                Some(Edge {
                    triangle: i,
                    mid: (a[0] + a[1]) * 0.5,
                    inward: -(na + nb).normalize(),
                    across: (na - nb).normalize(),
                })
            })
            .take(count)
            .collect();
        assert_eq!(found.len(), count, "the mesh has too few edges");
        found
    }
}
