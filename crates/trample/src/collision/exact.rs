//! The exact collision reference of DESIGN §4 ("an exact segment–triangle
//! reference, which the project also implements"): what the variable
//! precision test of paper §4.2 approaches as the depth grows.
//!
//! A segment collides with an object when it meets a triangle of its mesh
//! ([`segment_hits_triangle`]) or, for a closed mesh, lies inside it (a blade
//! swallowed whole by the object crosses no triangle). Inside is decided by
//! the parity of the crossings of a ray (the Jordan–Brouwer theorem), cast
//! in a fixed direction, slightly skewed from straight down so that it
//! generically misses edges and vertices. Both walk the OBB tree down to its
//! leaves, pruning with the segment–box test; since every box contains its
//! triangles (checked by [`ObbTree::validate`]), the pruning loses nothing.

use std::ops::ControlFlow;

use glam::Vec3;

use super::segment_obb::{centred, segment_hits_obb_centred};
use super::segment_triangle::{segment_crosses_triangle_interior, segment_hits_triangle};
use crate::obb::{MAX_TREE_DEPTH, ObbTree};

/// Direction of the inside-test ray, object-local frame: down (grass lies
/// below and around objects, so from a blade point the ray leaves the root
/// box after a short way and meets few boxes), tilted by about 1.2° by
/// irrational-looking amounts so that it is parallel to no axis, face
/// diagonal or grid line of a modelled mesh. Not normalised (no need).
pub const INSIDE_RAY: Vec3 = Vec3::new(0.012_345_679, -1.0, 0.017_320_508);

/// Entries of the traversal stack: one pending sibling per level plus one
/// ([`MAX_TREE_DEPTH`] bounds the depth of any tree).
pub(crate) const STACK_SIZE: usize = MAX_TREE_DEPTH as usize + 2;

/// True when `p` (object-local frame) is inside the closed mesh of `tree`.
///
/// Parity of the crossings of the ray from `p` along [`INSIDE_RAY`] with the
/// mesh, counted with [`segment_crosses_triangle_interior`] down the tree
/// (ray against box, then triangles at the leaves). The ray stops just past
/// the root box, which holds every triangle. `false` when the mesh is not
/// `closed` (inside is not defined), for a point outside the root box, a
/// non-finite point, or an empty tree. A point on the surface may go either
/// way. No allocation. Answered from the tree's [`InsideGrid`] where the
/// point's voxel meets no triangle, by [`point_inside_by_ray`] elsewhere:
/// the same answers either way.
///
/// [`InsideGrid`]: super::inside_grid::InsideGrid
#[must_use]
pub fn point_inside(tree: &ObbTree, p: Vec3) -> bool {
    if tree.closed
        && let Some(known) = tree.inside.as_ref().and_then(|g| g.classify(p))
    {
        return known;
    }
    point_inside_by_ray(tree, p)
}

/// [`point_inside`] by the ray-parity test alone (the exact reference; also
/// what classifies the voxels of the inside grid).
#[must_use]
pub fn point_inside_by_ray(tree: &ObbTree, p: Vec3) -> bool {
    if !tree.closed || tree.is_empty() || !p.is_finite() {
        return false;
    }
    let Some(root) = tree.nodes.first() else {
        return false;
    };
    let obb = &root.obb;
    let q = obb.to_box(p);
    if q.abs().cmpgt(obb.half).any() || !q.is_finite() {
        return false;
    }
    // Parameter where the ray leaves the root box (slab exit), plus a margin:
    // past it there is no triangle.
    let [u, v, w] = obb.axes;
    let d = Vec3::new(INSIDE_RAY.dot(u), INSIDE_RAY.dot(v), INSIDE_RAY.dot(w));
    let mut t_exit = f32::INFINITY;
    for k in 0..3 {
        if d[k] != 0.0 {
            t_exit = t_exit.min((obb.half[k].copysign(d[k]) - q[k]) / d[k]);
        }
    }
    if !t_exit.is_finite() {
        return false;
    }
    let end = p + INSIDE_RAY * (t_exit.max(0.0) * 1.001 + 1e-3 * obb.half.max_element() + 1e-5);
    let mut crossings = 0u32;
    let _ = visit_leaves(tree, p, end, |tris| {
        crossings += tris
            .iter()
            .filter(|t| segment_crosses_triangle_interior(p, end, t))
            .count() as u32;
        ControlFlow::Continue(())
    });
    crossings % 2 == 1
}

/// True when segment `p0–p1` (object-local frame) collides with the object
/// exactly: it meets a triangle ([`segment_hits_triangle`], boundary
/// included), or the mesh is `closed` and the segment's midpoint is inside
/// it ([`point_inside`]; a segment that meets no triangle is wholly inside
/// or wholly outside). Non-finite endpoints give `false`. No allocation.
///
/// The narrow phase ([`super::narrow_phase::collide_segment`]) reports every
/// segment this reports, at every precision (DESIGN §4).
#[must_use]
pub fn segment_hits_exact(tree: &ObbTree, p0: Vec3, p1: Vec3) -> bool {
    if !(p0.is_finite() && p1.is_finite()) || tree.is_empty() {
        return false;
    }
    let crosses = visit_leaves(tree, p0, p1, |tris| {
        if tris.iter().any(|t| segment_hits_triangle(p0, p1, t)) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    crosses.is_break() || (tree.closed && point_inside(tree, (p0 + p1) * 0.5))
}

/// Calls `f` with the triangles of every leaf whose box, and whose
/// ancestors' boxes, segment `p0–p1` meets, depth first, left child first;
/// stops early when `f` breaks. Children are only followed to larger
/// indices, so a malformed tree cannot make this loop.
fn visit_leaves(
    tree: &ObbTree,
    p0: Vec3,
    p1: Vec3,
    mut f: impl FnMut(&[[Vec3; 3]]) -> ControlFlow<()>,
) -> ControlFlow<()> {
    let (centre, half) = centred(p0, p1);
    let mut stack = [0u32; STACK_SIZE];
    let mut len = 1;
    while len > 0 {
        len -= 1;
        let i = stack[len];
        let Some(node) = tree.nodes.get(i as usize) else {
            continue;
        };
        if !segment_hits_obb_centred(centre, half, &node.obb) {
            continue;
        }
        let [l, r] = node.children;
        if node.is_leaf() || l <= i || r <= i || len + 2 > STACK_SIZE {
            let (first, count) = (node.first_tri as usize, node.tri_count as usize);
            if let Some(tris) = tree.triangles.get(first..first.saturating_add(count)) {
                f(tris)?;
            }
        } else {
            stack[len] = r;
            stack[len + 1] = l;
            len += 2;
        }
    }
    ControlFlow::Continue(())
}
