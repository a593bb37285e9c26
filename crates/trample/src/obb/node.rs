//! OBB and tree node types (paper §4.2: centre C, orthonormal basis
//! [u, v, w], half extents (hu, hv, hw)).

use glam::{Vec3, Vec3A};

/// Marks a leaf in [`ObbNode::children`].
pub const NO_CHILD: u32 = u32::MAX;

/// An oriented bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Obb {
    /// Centre C.
    pub center: Vec3,
    /// Orthonormal axes u, v, w (right-handed).
    pub axes: [Vec3; 3],
    /// Half extents (hu, hv, hw) along the axes, metres, ≥ 0.
    pub half: Vec3,
}

impl Obb {
    /// Coordinates of world/parent-frame point `p` in the box frame.
    #[must_use]
    pub fn to_box(&self, p: Vec3) -> Vec3 {
        let d = p - self.center;
        Vec3::new(
            d.dot(self.axes[0]),
            d.dot(self.axes[1]),
            d.dot(self.axes[2]),
        )
    }

    /// [`Obb::to_box`] in SIMD registers (`Vec3A`): the same products and
    /// sums in the same order, so the same bits; for the hot loops (the
    /// closest-point walk's box distances).
    #[must_use]
    #[inline]
    pub fn to_box_a(&self, p: Vec3A) -> Vec3A {
        let d = p - Vec3A::from(self.center);
        Vec3A::new(
            d.dot(self.axes[0].into()),
            d.dot(self.axes[1].into()),
            d.dot(self.axes[2].into()),
        )
    }

    /// Half the length of the box diagonal: R in Eq. 8.
    #[must_use]
    pub fn half_diagonal(&self) -> f32 {
        self.half.length()
    }

    /// The eight corners.
    #[must_use]
    pub fn corners(&self) -> [Vec3; 8] {
        let mut out = [Vec3::ZERO; 8];
        for (i, c) in out.iter_mut().enumerate() {
            let s = |bit: usize| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
            *c = self.center
                + self.axes[0] * (s(0) * self.half.x)
                + self.axes[1] * (s(1) * self.half.y)
                + self.axes[2] * (s(2) * self.half.z);
        }
        out
    }
}

/// A node of the OBB tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObbNode {
    /// The node's box, object-local frame.
    pub obb: Obb,
    /// Equivalent normal, Eq. 3: area-weighted mean of the node's triangle
    /// normals (not normalised; its length says how one-sided the node is).
    pub eqn: Vec3,
    /// Left and right child indices, [`NO_CHILD`] for a leaf.
    pub children: [u32; 2],
    /// The node's triangles are `tree.triangles[first_tri .. first_tri + tri_count]`.
    pub first_tri: u32,
    /// Number of triangles under the node.
    pub tri_count: u32,
    /// Depth: the root is 1 (paper §4.2: "when the value of depth is one, the
    /// judgment stops at the root node").
    pub depth: u32,
}

impl ObbNode {
    /// True for a leaf.
    #[must_use]
    pub fn is_leaf(&self) -> bool {
        self.children[0] == NO_CHILD
    }
}

/// A binary OBB tree over a mesh, object-local frame. Node 0 is the root.
#[derive(Clone, Debug)]
pub struct ObbTree {
    /// Nodes; node 0 is the root, children come after their parent.
    pub nodes: Vec<ObbNode>,
    /// The mesh's triangles reordered so that every node's are contiguous.
    pub triangles: Vec<[Vec3; 3]>,
    /// True when the mesh is closed (every edge shared by exactly two
    /// triangles): then "inside the mesh" is defined and tested.
    pub closed: bool,
    /// Depth of the deepest leaf (root = 1).
    pub max_depth: u32,
    /// True when every node's box contains its children's boxes
    /// ([`ObbTree::nest_boxes`]); [`ObbTree::validate`] then checks it.
    /// False after [`ObbTree::build`].
    pub nested: bool,
    /// Voxel classification that answers most inside tests of a closed mesh
    /// without a ray cast (`None` for open meshes).
    pub inside: Option<crate::collision::inside_grid::InsideGrid>,
    /// Per node, the box with the node's axes that holds its own box and
    /// every descendant's ([`super::reach::reach_boxes`]): what the
    /// simulation's contact walk prunes with, so that it reaches every
    /// final-depth node whose box a segment meets even where a child's box
    /// sticks out of its parent's.
    pub reach: Vec<Obb>,
    /// Per node, the tilted boxes around its triangles that cut its box's
    /// empty corners ([`super::slabs`]): a segment meets a node only if it
    /// meets its box and these. Empty for a [`ObbTree::nested`] tree (its
    /// boxes alone decide) and then not tested.
    pub slabs: Vec<super::slabs::NodeSlabs>,
    /// Per node, how fast its box's centre moves in the object's frame
    /// because the mesh deforms, m/s (a skinned limb's own swing, set when
    /// the tree is refitted to a posed skin: `step/rig.rs`). Eq. 2's contact
    /// speed adds it to the body's rigid motion ([`ObbTree::node_velocity`]),
    /// so a planted foot pushes as little as it moves and a swinging one as
    /// fast as it swings. Empty for a mesh that does not deform: zero.
    pub velocity: Vec<Vec3>,
    /// Which corners and edges the triangles share, for an open mesh
    /// (empty for a closed one): what [`ObbTree::feature_normals`] is
    /// recomputed from when the tree is refitted.
    pub features: super::pseudo_normals::MeshFeatures,
    /// Per triangle of an open mesh (empty for a closed one), the
    /// angle-weighted pseudo-normals of its edges and corners
    /// ([`super::pseudo_normals`]): which side of the sheet a point whose
    /// closest surface point lies on an edge or a corner is on.
    pub feature_normals: Vec<[Vec3; 6]>,
    /// Per node of a winding open mesh (empty otherwise: closed, or the
    /// sheet rule), what stands for the node far from a point in the
    /// generalized winding number ([`crate::collision::winding::Dipole`]:
    /// its area vector, centroid, radius and second moment), which says how
    /// much a point is inside a mesh with holes.
    pub dipoles: Vec<crate::collision::winding::Dipole>,
    /// The rim of an open mesh (empty for a closed one): the edges its
    /// triangles do not close ([`super::pseudo_normals::MeshFeatures::rims`]), which
    /// bound how fast its winding number changes.
    pub rims: Vec<crate::collision::winding::Rim>,
    /// The winding number of an open mesh on a grid over its root box
    /// ([`crate::collision::winding_grid`]), which answers most winding
    /// queries away from the surface; `None` for a tree that does not wind,
    /// and after a refit.
    pub winding_grid: Option<crate::collision::winding_grid::WindingGrid>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;

    /// The SIMD transform gives the scalar one's bits (the closest-point
    /// walk relies on it: same pruning, same answers).
    #[test]
    fn to_box_a_equals_to_box_bit_for_bit() {
        let mut rng = XorShift(0x853c_49e6_748f_ea9bu64);
        let mut next = || rng.range(-3.5, 3.5);
        for _ in 0..10_000 {
            let u = Vec3::new(next(), next(), next()).normalize();
            let v = u.any_orthonormal_vector();
            let obb = Obb {
                center: Vec3::new(next(), next(), next()) * 100.0,
                axes: [u, v, u.cross(v)],
                half: Vec3::new(next(), next(), next()).abs(),
            };
            let p = Vec3::new(next(), next(), next()) * 150.0;
            let (a, b) = (obb.to_box(p), Vec3::from(obb.to_box_a(p.into())));
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits)
            );
        }
    }
}
