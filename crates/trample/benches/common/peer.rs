//! The parry3d peers of our collision queries, for the ratios of DESIGN §10.
//!
//! - [`ParryObbTree`] answers the narrow phase's question — does a segment
//!   meet a node of the OBB tree at the final depth, and with which EqN —
//!   with every segment–box test done by parry3d
//!   (`intersection_test_cuboid_segment`, its SAT test of a `Cuboid` against
//!   a `Segment`) on the *same* nodes, walked in the same order, with the same
//!   EqN directions and the same inside fallback. Only the box test differs,
//!   which is what the method is about: parry's own BVH has AABB nodes and
//!   answers a different question (exact triangle hits, no depth), so it is
//!   the peer of the exact reference instead. Boxes are converted to parry's
//!   (pose, cuboid) once, outside the timing.
//! - [`ParryMesh`] answers the exact reference's question — does a segment
//!   cross a triangle, or lie inside the closed mesh — with parry's `TriMesh`
//!   (AABB BVH): a ray cast of the segment (origin p0, direction p1 − p0,
//!   time of impact ≤ 1), then for a closed mesh `contains_local_point` of
//!   the midpoint (pseudo-normals, `TriMeshFlags::ORIENTED`).

use glam::Vec3;
use parry3d::math::{Pose, Vector};
use parry3d::query::details::intersection_test_cuboid_segment;
use parry3d::query::{PointQuery, Ray, RayCast};
use parry3d::shape::{Cuboid, Segment, TriMesh, TriMeshFlags};
use trample::collision::point_inside;
use trample::obb::ObbTree;

fn v(p: Vec3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// An OBB tree whose boxes are tested by parry3d.
pub struct ParryObbTree<'a> {
    tree: &'a ObbTree,
    /// Per node: segment frame (object) → box frame, and the box.
    boxes: Vec<(Pose, Cuboid)>,
}

impl<'a> ParryObbTree<'a> {
    /// Converts every node's box.
    pub fn new(tree: &'a ObbTree) -> Self {
        let boxes = tree
            .nodes
            .iter()
            .map(|n| {
                let [u, w1, w2] = n.obb.axes;
                let m = parry3d::math::Matrix::from_cols(v(u), v(w1), v(w2));
                let rot = parry3d::math::Rotation::from_mat3(&m).normalize();
                let box_to_object = Pose::from_parts(v(n.obb.center), rot);
                (box_to_object.inverse(), Cuboid::new(v(n.obb.half)))
            })
            .collect();
        Self { tree, boxes }
    }

    fn hits(&self, node: usize, seg: &Segment) -> bool {
        let (pose, cuboid) = &self.boxes[node];
        intersection_test_cuboid_segment(pose, cuboid, seg)
    }

    /// `trample::collision::collide_segment` with parry3d's box test:
    /// the push direction, or `None` when the segment does not hit.
    pub fn collide_segment(&self, p0: Vec3, p1: Vec3, precision: u32) -> Option<Vec3> {
        let tree = self.tree;
        if tree.is_empty() || !(p0.is_finite() && p1.is_finite()) {
            return None;
        }
        let seg = Segment::new(v(p0), v(p1));
        if !self.hits(0, &seg) {
            return None;
        }
        let (sum, first, deepest) = self.walk(&seg, p0, p1, precision);
        if let Some(first) = first {
            return Some(sum.normalize_or(first));
        }
        if deepest == 0 || !tree.closed || !point_inside(tree, (p0 + p1) * 0.5) {
            return None;
        }
        let (sum, first, _) = self.walk(&seg, p0, p1, deepest);
        first.map(|f| sum.normalize_or(f))
    }

    /// Depth-first walk to `final_depth`: (sum of EqN directions, first
    /// one, deepest depth hit).
    fn walk(
        &self,
        seg: &Segment,
        p0: Vec3,
        p1: Vec3,
        final_depth: u32,
    ) -> (Vec3, Option<Vec3>, u32) {
        let nodes = &self.tree.nodes;
        let (mut sum, mut first, mut deepest) = (Vec3::ZERO, None, 0);
        let mut stack = [(0u32, 1u32); 66];
        let mut len = 1;
        while len > 0 {
            len -= 1;
            let (i, depth) = stack[len];
            if !self.hits(i as usize, seg) {
                continue;
            }
            deepest = deepest.max(depth);
            let node = &nodes[i as usize];
            if depth < final_depth && !node.is_leaf() {
                stack[len] = (node.children[1], depth + 1);
                stack[len + 1] = (node.children[0], depth + 1);
                len += 2;
            } else {
                let dir = self.tree.eqn_direction(i, p0, p1);
                first.get_or_insert(dir);
                sum += dir;
            }
        }
        (sum, first, deepest)
    }
}

/// A mesh as parry3d's `TriMesh`.
pub struct ParryMesh {
    mesh: TriMesh,
    closed: bool,
}

impl ParryMesh {
    /// Builds the `TriMesh` (and its BVH) of the tree's triangles; closed
    /// meshes get pseudo-normals for the inside test.
    pub fn new(tree: &ObbTree) -> Self {
        let mut vertices = Vec::with_capacity(tree.triangles.len() * 3);
        let mut indices = Vec::with_capacity(tree.triangles.len());
        // Weld equal corners so that parry sees the shared edges.
        let mut index = std::collections::HashMap::new();
        for t in &tree.triangles {
            let tri = t.map(|p| {
                *index
                    .entry(p.to_array().map(f32::to_bits))
                    .or_insert_with(|| {
                        vertices.push(v(p));
                        (vertices.len() - 1) as u32
                    })
            });
            indices.push(tri);
        }
        let flags = if tree.closed {
            TriMeshFlags::ORIENTED
        } else {
            TriMeshFlags::empty()
        };
        let mesh = TriMesh::with_flags(vertices, indices, flags).expect("valid trimesh");
        Self {
            mesh,
            closed: tree.closed,
        }
    }

    /// `trample::collision::segment_hits_exact` through parry3d.
    pub fn segment_hits(&self, p0: Vec3, p1: Vec3) -> bool {
        let ray = Ray::new(v(p0), v(p1 - p0));
        self.mesh.intersects_local_ray(&ray, 1.0)
            || (self.closed && self.mesh.contains_local_point(v((p0 + p1) * 0.5)))
    }
}
