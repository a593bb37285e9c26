//! Building the binary OBB tree of a mesh (the HBV of paper §3.2 "off-line
//! processing" and §4.2; DESIGN §3), its equivalent normals (Eq. 3), and the
//! direction a node pushes a blade (DESIGN §3 "EqN direction (ours)").
//!
//! Top-down, as in Gottschalk et al., *OBBTree* (SIGGRAPH 1996): fit a box to
//! the node's triangles ([`super::fit::fit_obb`]), split them in two ([`super::split`]:
//! between pieces that share no edge when there are such, else by the plane
//! through the mean of their centroids orthogonal to the box's longest
//! axis), recurse; stop at one triangle or at the depth cap.

use crate::collision::exact::point_inside_by_ray;
use crate::collision::inside_grid::InsideGrid;

use glam::{DVec3, Vec3};

use super::fit::fit_obb_searched;
use super::node::{NO_CHILD, Obb, ObbNode, ObbTree};
use super::pseudo_normals::MeshFeatures;
use super::split::{Topology, split};
use crate::object::TriMesh;

/// Deepest nodes whose box [`ObbTree::build`] fits with the orientation
/// search of [`super::fit::fit_obb`]; deeper ones get the covariance or world box
/// ([`super::fit::fit_obb_searched`] without search). The search triples
/// the fit's cost and pays where queries stop: precisions up to 12 cover the
/// paper's 1–7 and the accuracy tables' 1–10. A 327,680-triangle sphere is
/// 22 levels deep: the cap halves its build time. Nodes of at most
/// [`SEARCH_TRIANGLES`] triangles are searched at any depth (cheap, and the
/// leaves decide the hits at full depth: without it the torus of the
/// precision tests went from 0.0 % to 1.1 % false positives there).
pub const SEARCH_DEPTH: u32 = 12;

/// See [`SEARCH_DEPTH`].
pub const SEARCH_TRIANGLES: usize = 4;

/// Whether a node at `depth` (root = 1) of `count` triangles gets the
/// orientation search ([`SEARCH_DEPTH`], [`SEARCH_TRIANGLES`]): the rule
/// of the build and of [`ObbTree::refit`] with `AxisRule::Fit`, so that a
/// refit at the bind pose fits the boxes the build fitted.
#[must_use]
pub fn searched_at(depth: u32, count: usize) -> bool {
    depth <= SEARCH_DEPTH || count <= SEARCH_TRIANGLES
}

/// Default depth cap of [`ObbTree::build`]: deep enough that meshes of up to
/// 2³¹ triangles get one triangle per leaf with balanced splits, and well past
/// the paper's precision range 1–7 (§7, Fig. 12).
pub const DEFAULT_MAX_DEPTH: u32 = 32;

/// Hard cap on tree depth, whatever [`ObbTree::build`] is asked for. Queries
/// traverse the tree with a fixed-size stack (no allocation per query) that
/// holds at most one entry per level plus one, so this bounds the stack.
pub const MAX_TREE_DEPTH: u32 = 64;

/// Below this length, Eq. 3's EqN is not used as a direction
/// ([`ObbTree::eqn_direction`]).
///
/// |EqN| is 1 for a flat node and 0 for a closed one (the area-weighted
/// normals of a closed surface sum to zero), e.g. a sphere's or a box's root.
/// When it is small, its direction is set by the few percent of the area
/// whose normals do not cancel, and a change to a few triangles turns it by
/// a large angle: with a fraction `f` of the area perturbed, the direction
/// moves by about `f / |EqN|` radians. At 0.1, perturbing 5 % of the area
/// moves it by at most ~30°. Below that, the direction from the node to the
/// blade is the better guess.
pub const EQN_EPSILON: f32 = 0.1;

impl ObbTree {
    /// Builds the OBB tree of `mesh` (paper §4.2, DESIGN §3).
    ///
    /// - Binary; the root is node 0 with depth 1; children are stored after
    ///   their parent, siblings next to each other (`children[1] ==
    ///   children[0] + 1`).
    /// - Each node's box is [`super::fit::fit_obb`] of its triangles, so it contains
    ///   them, and by construction it contains its children's triangles; its
    ///   `eqn` is Eq. 3, `Σ S_i N_i / Σ S_i` (not normalised; zero when the
    ///   node's total area is zero).
    /// - A node whose triangles form two or more pieces that share no edge
    ///   (each with ≥ [`super::split::PIECE_SHARE`] of them) is split between
    ///   pieces, at the cut of least segment-hit cost; any other along its
    ///   box's longest axis at the mean of its triangle centroids projected
    ///   on it; if one side would be empty, along the other axes in order of
    ///   decreasing extent; if still empty (all centroids equal), at the
    ///   median ([`super::split`]). A node is a leaf when it holds one
    ///   triangle or its depth is `max_depth` (clamped to
    ///   `1..=`[`MAX_TREE_DEPTH`]).
    /// - `triangles` are the mesh's triangles reordered so that every node's
    ///   are the contiguous range `first_tri .. first_tri + tri_count`.
    /// - `closed`: every undirected edge, with vertices identified by
    ///   position (so an unwelded mesh counts), belongs to exactly two
    ///   triangles, and no triangle has repeated corners.
    /// - `max_depth` of the result is the depth of its deepest leaf.
    ///
    /// Triangles whose indices are out of range are skipped (and the mesh is
    /// then not `closed`); sanitising rejects them earlier (DESIGN §9). An
    /// empty mesh gives a tree with one empty root (zero box, no triangles)
    /// that no query hits. Never panics.
    #[must_use]
    pub fn build(mesh: &TriMesh, max_depth: u32) -> ObbTree {
        let depth_cap = max_depth.clamp(1, MAX_TREE_DEPTH);
        let mut triangles: Vec<[Vec3; 3]> = Vec::with_capacity(mesh.indices.len());
        let mut all_valid = true;
        for idx in &mesh.indices {
            let corners = idx.map(|i| mesh.positions.get(i as usize).copied());
            match corners {
                [Some(a), Some(b), Some(c)] => triangles.push([a, b, c]),
                _ => all_valid = false,
            }
        }
        let mut topology = Topology::new(&triangles);
        let closed = all_valid && topology.every_edge_twice;
        let mut ids: Vec<u32> = (0..triangles.len() as u32).collect();

        let mut nodes = vec![make_node(&triangles, 0, triangles.len(), 1)];
        let mut pending = vec![0usize];
        while let Some(i) = pending.pop() {
            let ObbNode {
                first_tri,
                tri_count,
                depth,
                obb,
                ..
            } = nodes[i];
            if tri_count <= 1 || depth >= depth_cap {
                continue;
            }
            let (first, count) = (first_tri as usize, tri_count as usize);
            let range = first..first + count;
            let left_count = split(
                &mut triangles[range.clone()],
                &mut ids[range],
                &obb,
                &mut topology,
            );
            let left = nodes.len();
            nodes.push(make_node(&triangles, first, left_count, depth + 1));
            nodes.push(make_node(
                &triangles,
                first + left_count,
                count - left_count,
                depth + 1,
            ));
            nodes[i].children = [left as u32, left as u32 + 1];
            pending.push(left + 1);
            pending.push(left);
        }
        let max_depth = nodes
            .iter()
            .filter(|n| n.is_leaf())
            .map(|n| n.depth)
            .max()
            .unwrap_or(1);
        let mut tree = ObbTree {
            nodes,
            triangles,
            closed,
            max_depth,
            nested: false,
            inside: None,
            reach: Vec::new(),
            slabs: Vec::new(),
            velocity: Vec::new(),
            features: MeshFeatures::default(),
            feature_normals: Vec::new(),
            dipoles: Vec::new(),
            rims: Vec::new(),
            winding_grid: None,
        };
        if !closed {
            tree.features = MeshFeatures::new(&tree.triangles);
            tree.feature_normals = tree.features.normals(&tree.triangles);
        }
        tree.reach = super::reach::reach_boxes(&tree.nodes);
        tree.slabs = super::slabs::fit_slabs(&tree.nodes, &tree.triangles);
        tree.inside = InsideGrid::build(&tree, |p| point_inside_by_ray(&tree, p));
        tree
    }

    /// Gives an open mesh's tree the winding number's data (its dipoles,
    /// their spheres and its rim: [`crate::collision::winding`]), which
    /// makes the contact response take the mesh's hollow as its inside
    /// (an object's `track.open_inside = "winding"`), and the grid of its
    /// winding number ([`crate::collision::winding_grid`]: a tree sum and a
    /// closest point at each of about 2¹⁸ corners; the beetle car's
    /// 288,288 take 0.72 s on two cores). Nothing for a closed mesh or a
    /// tree that has them.
    pub fn enable_winding(&mut self) {
        if self.closed || !self.dipoles.is_empty() {
            return;
        }
        self.enable_winding_without_grid();
        self.winding_grid = crate::collision::winding_grid::WindingGrid::build(self);
    }

    /// [`ObbTree::enable_winding`] without the grid: for a mesh that
    /// deforms (a skinned body), whose first refit would drop the grid
    /// (its queries sum the tree). Nothing for a closed mesh or a tree that
    /// has the data.
    pub fn enable_winding_without_grid(&mut self) {
        if self.closed || !self.dipoles.is_empty() {
            return;
        }
        self.dipoles = crate::collision::winding::dipoles(self);
        self.rims = self.features.rims();
    }

    /// True when the tree uses the winding number for its inside
    /// ([`ObbTree::enable_winding`]).
    #[must_use]
    pub fn winds(&self) -> bool {
        !self.closed && !self.dipoles.is_empty()
    }

    /// True when the tree holds no triangle (built from an empty mesh).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// Node `node`'s deformation velocity in the object's frame, m/s
    /// ([`ObbTree::velocity`]; zero for a mesh that does not deform).
    #[must_use]
    #[inline]
    pub fn node_velocity(&self, node: u32) -> Vec3 {
        self.velocity
            .get(node as usize)
            .copied()
            .unwrap_or(Vec3::ZERO)
    }

    /// Eq. 3's EqN of node `node`, normalised, when it is a reliable normal
    /// (`|EqN| ≥` [`EQN_EPSILON`]: the node's triangles face mostly one way);
    /// `None` otherwise (or for a node out of range). See also
    /// [`ObbTree::eqn_direction`].
    #[must_use]
    #[inline]
    pub fn eqn_unit(&self, node: u32) -> Option<Vec3> {
        let n = self.nodes.get(node as usize)?;
        let len = n.eqn.length();
        (len >= EQN_EPSILON && len.is_finite()).then(|| n.eqn / len)
    }

    /// The unit direction in which node `node` pushes a blade whose segment
    /// `p0–p1` (object-local frame) hit it: DESIGN §3 "EqN direction (ours)".
    ///
    /// 1. Eq. 3's EqN, normalised, when `|EqN| ≥` [`EQN_EPSILON`].
    /// 2. Otherwise (a closed or symmetric node: a sphere's root has EqN ≈ 0),
    ///    the direction from the node's box centre to the nearest point of
    ///    the segment: the object pushes the blade away from itself.
    /// 3. If the segment passes through the centre, the box axis of smallest
    ///    extent (the way out of the box is shortest along it), signed so that
    ///    its y component is ≥ 0 (then x, then z, for a horizontal axis): a
    ///    deterministic choice for a measure-zero case.
    ///
    /// `node` out of range, or a non-finite node, gives `+y`. Always returns
    /// a unit vector. See also [`crate::collision::narrow_phase`], which sums
    /// these over the final-depth nodes a segment hits.
    #[must_use]
    #[inline]
    pub fn eqn_direction(&self, node: u32, p0: Vec3, p1: Vec3) -> Vec3 {
        let Some(n) = self.nodes.get(node as usize) else {
            return Vec3::Y;
        };
        let len = n.eqn.length();
        if len >= EQN_EPSILON && len.is_finite() {
            return n.eqn / len;
        }
        let c = n.obb.center;
        if let Some(dir) = (closest_point_on_segment(p0, p1, c) - c).try_normalize() {
            return dir;
        }
        smallest_axis_up(&n.obb)
    }
}

/// The point of segment `p0–p1` closest to `q` (`p0` for a zero-length segment).
#[must_use]
#[inline]
pub(crate) fn closest_point_on_segment(p0: Vec3, p1: Vec3, q: Vec3) -> Vec3 {
    let d = p1 - p0;
    let dd = d.length_squared();
    if dd > 0.0 {
        let t = ((q - p0).dot(d) / dd).clamp(0.0, 1.0);
        if t.is_finite() {
            return p0 + d * t;
        }
    }
    p0
}

/// The box axis of smallest half extent, signed to point up (y ≥ 0, ties
/// broken by x ≥ 0, then z ≥ 0); `+y` if the axis is not a unit vector.
fn smallest_axis_up(obb: &Obb) -> Vec3 {
    let h = obb.half;
    let k = if h.x <= h.y && h.x <= h.z {
        0
    } else if h.y <= h.z {
        1
    } else {
        2
    };
    let axis = obb.axes[k];
    if !axis.is_finite() || axis.length_squared() < 0.5 {
        return Vec3::Y;
    }
    let key = if axis.y != 0.0 {
        axis.y
    } else if axis.x != 0.0 {
        axis.x
    } else {
        axis.z
    };
    let axis = if key < 0.0 { -axis } else { axis };
    axis.try_normalize().unwrap_or(Vec3::Y)
}

/// A leaf node over `triangles[first .. first + count]` at depth 1; the
/// caller sets depth and children.
fn make_node(triangles: &[[Vec3; 3]], first: usize, count: usize, depth: u32) -> ObbNode {
    let tris = &triangles[first..first + count];
    ObbNode {
        obb: fit_obb_searched(tris, searched_at(depth, count)),
        eqn: equivalent_normal(tris),
        children: [NO_CHILD; 2],
        first_tri: first as u32,
        tri_count: count as u32,
        depth,
    }
}

/// Eq. 3: `EqN = Σ S_i N_i / Σ S_i`, with `S_i` the area and `N_i` the unit
/// normal of triangle `i` (`S_i N_i = ½ (b − a) × (c − a)`, counter-clockwise
/// triangles face outwards). Not normalised: |EqN| ≤ 1, equal to 1 only for
/// a flat node. Zero when the total area is zero or not finite. Accumulated
/// in `f64`.
#[must_use]
pub fn equivalent_normal(triangles: &[[Vec3; 3]]) -> Vec3 {
    let (weighted, area) = equivalent_normal_sums(triangles);
    equivalent_normal_from_sums(weighted, area)
}

/// Eq. 3's two sums over `triangles`: `Σ S_i N_i` and `Σ S_i` (f64). A
/// node's sums are its children's added, which is how
/// [`ObbTree::refit`] recomputes EqN bottom-up.
#[must_use]
pub(crate) fn equivalent_normal_sums(triangles: &[[Vec3; 3]]) -> (DVec3, f64) {
    let mut weighted = DVec3::ZERO;
    let mut area = 0.0f64;
    for tri in triangles {
        let [a, b, c] = tri.map(Vec3::as_dvec3);
        let n = 0.5 * (b - a).cross(c - a);
        weighted += n;
        area += n.length();
    }
    (weighted, area)
}

/// Eq. 3 from its sums ([`equivalent_normal_sums`]): `Σ S N / Σ S`, zero
/// when the area is zero or the ratio is not finite.
#[must_use]
pub(crate) fn equivalent_normal_from_sums(weighted: DVec3, area: f64) -> Vec3 {
    let eqn = weighted / area;
    if area > 0.0 && eqn.is_finite() {
        eqn.as_vec3()
    } else {
        Vec3::ZERO
    }
}
