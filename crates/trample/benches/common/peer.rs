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
    /// Per node: segment frame (object) → box frame, and the box; then its
    /// tilted boxes (`trample::obb::slabs`), which the yes/no walk also
    /// tests.
    boxes: Vec<Vec<(Pose, Cuboid)>>,
    /// The contact walk's boxes ([`ParryObbTree::contact_hit`]), grown by
    /// `shell`: per node its own box and its reach box.
    grown: Vec<[(Pose, Cuboid); 2]>,
    shell: f32,
}

/// A box as parry's (object → box frame, cuboid), half extents grown by `grow`.
fn parry_box(obb: &trample::obb::Obb, grow: f32) -> (Pose, Cuboid) {
    let [u, w1, w2] = obb.axes;
    let m = parry3d::math::Matrix::from_cols(v(u), v(w1), v(w2));
    let rot = parry3d::math::Rotation::from_mat3(&m).normalize();
    let box_to_object = Pose::from_parts(v(obb.center), rot);
    (
        box_to_object.inverse(),
        Cuboid::new(v(obb.half + Vec3::splat(grow))),
    )
}

impl<'a> ParryObbTree<'a> {
    /// Converts every node's box; the contact walk's boxes grown by `shell`.
    pub fn new(tree: &'a ObbTree, shell: f32) -> Self {
        let boxes = tree
            .nodes
            .iter()
            .enumerate()
            .map(|(i, n)| {
                let tilted = tree.slabs.get(i).into_iter().flat_map(|s| {
                    (0..trample::obb::slabs::EXTRA_BOXES)
                        .map(|j| parry_box(&s.tilted_obb(&n.obb, j), 0.0))
                });
                std::iter::once(parry_box(&n.obb, 0.0))
                    .chain(tilted)
                    .collect()
            })
            .collect();
        let grown = tree
            .nodes
            .iter()
            .enumerate()
            .map(|(i, n)| {
                let reach = tree.reach.get(i).unwrap_or(&n.obb);
                [parry_box(&n.obb, shell), parry_box(reach, shell)]
            })
            .collect();
        Self {
            tree,
            boxes,
            grown,
            shell,
        }
    }

    /// Whether `trample::collision::contact_blade` finds a contact for the
    /// segment (its hit mask), with parry3d's box test on the same boxes:
    /// the contact walk's boxes grown by the shell, reach boxes above the
    /// final depth, the same inside fallback. Only hit or miss: ours also
    /// computes each contact's weight, direction, point and velocity.
    pub fn contact_hit(&self, p0: Vec3, p1: Vec3, precision: u32) -> bool {
        let tree = self.tree;
        if tree.is_empty() || !(p0.is_finite() && p1.is_finite()) || self.shell <= 0.0 {
            return false;
        }
        let seg = Segment::new(v(p0), v(p1));
        let test = |i: usize, reach: bool| {
            let (pose, cuboid) = &self.grown[i][usize::from(reach)];
            intersection_test_cuboid_segment(pose, cuboid, &seg)
        };
        if !test(0, true) {
            return false;
        }
        let nodes = &tree.nodes;
        let mut deepest = 0;
        let mut stack = [(0u32, 1u32); 66];
        let mut len = 1;
        while len > 0 {
            len -= 1;
            let (i, depth) = stack[len];
            let node = &nodes[i as usize];
            let descend = depth < precision && !node.is_leaf();
            if !test(i as usize, descend) {
                continue;
            }
            deepest = deepest.max(depth);
            if !descend {
                return true;
            }
            stack[len] = (node.children[1], depth + 1);
            stack[len + 1] = (node.children[0], depth + 1);
            len += 2;
        }
        deepest > 0 && tree.closed && point_inside(tree, (p0 + p1) * 0.5)
    }

    fn hits(&self, node: usize, seg: &Segment) -> bool {
        self.boxes[node]
            .iter()
            .all(|(pose, cuboid)| intersection_test_cuboid_segment(pose, cuboid, seg))
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
