//! Reach boxes (ours, DESIGN §5 "a continuous response"): for every node,
//! a box with the node's own axes that holds the node's box and every
//! descendant's.
//!
//! The tree's boxes are fitted to their triangles, so a child's box may
//! stick out of its parent's (measured on the default sphere: a quarter of
//! the depth-3 hits lay in a part of a child its parent does not cover).
//! The paper's walk prunes a child whose parent the segment misses; for a
//! hit flag that is the definition of precision, but for a force it makes
//! a grazing touch of the parent all or nothing of the child. The contact
//! walk of the simulation prunes with the reach boxes instead, so it finds
//! exactly the final-depth nodes whose own boxes the segment meets.
//! Growing the boxes themselves to contain their children (tried) bloats
//! them level after level: 98 % false positives at depth 7 on a sphere.

use glam::Vec3;

use super::fit::padding;
use super::node::{Obb, ObbNode};

/// The reach box of every node of `nodes` (a tree's, children after their
/// parents), bottom-up: a leaf's is its own box; a parent's is the smallest
/// box with the parent's axes that contains its own box and its children's
/// reach boxes (their corners, projected on the parent's axes), plus the
/// fit's padding. O(nodes).
#[must_use]
pub fn reach_boxes(nodes: &[ObbNode]) -> Vec<Obb> {
    let mut reach: Vec<Obb> = nodes.iter().map(|n| n.obb).collect();
    for i in (0..nodes.len()).rev() {
        let [l, r] = nodes[i].children;
        if nodes[i].is_leaf() || l as usize >= nodes.len() || r as usize >= nodes.len() {
            continue;
        }
        let corners = [reach[l as usize].corners(), reach[r as usize].corners()];
        reach[i] = box_holding(&nodes[i].obb, corners.as_flattened());
    }
    reach
}

/// `own` grown (same axes; centre and extents moved) to hold `points` as
/// [`Obb::to_box`] measures them, plus the fit's padding; `own` itself when
/// it holds them already. Moving the centre rounds the points' box
/// coordinates anew: the padding covers that, and more padding is added in
/// the unlikely case it does not, so every point is inside with no
/// tolerance. Shared by the reach boxes and [`super::ObbTree::nest_boxes`].
#[must_use]
pub fn box_holding(own: &Obb, points: &[Vec3]) -> Obb {
    let holds = |o: &Obb| {
        points
            .iter()
            .all(|p| o.to_box(*p).abs().cmple(o.half).all())
    };
    let (mut lo, mut hi) = (-own.half, own.half);
    for p in points {
        let q = own.to_box(*p);
        lo = lo.min(q);
        hi = hi.max(q);
    }
    if lo.cmpge(-own.half).all() && hi.cmple(own.half).all() {
        return *own;
    }
    let mid = (lo + hi) * 0.5;
    let center = own.center + own.axes[0] * mid.x + own.axes[1] * mid.y + own.axes[2] * mid.z;
    let half = (hi - lo) * 0.5;
    let mut out = Obb {
        center,
        axes: own.axes,
        half: half + Vec3::splat(padding(half.max_element(), center)),
    };
    for _ in 0..8 {
        if holds(&out) {
            break;
        }
        out.half += Vec3::splat(padding(out.half.max_element(), center));
    }
    out
}

#[cfg(test)]
mod tests {
    use crate::obb::ObbTree;
    use crate::object::shapes::{knot, sphere};

    /// Every corner of a node's box and of its descendants' boxes lies in its
    /// reach box.
    #[test]
    fn reach_boxes_hold_every_descendant() {
        for mesh in [sphere(1.0, 3), knot(2.4)] {
            let tree = ObbTree::build(&mesh, 32);
            assert_eq!(tree.reach.len(), tree.nodes.len());
            let mut sticking_out = 0;
            for (i, node) in tree.nodes.iter().enumerate() {
                let mut stack = vec![i];
                while let Some(j) = stack.pop() {
                    for c in tree.nodes[j].obb.corners() {
                        let q = tree.reach[i].to_box(c);
                        let slack = 1e-5 * tree.reach[i].half.max_element();
                        assert!(
                            q.abs().cmple(tree.reach[i].half + slack).all(),
                            "node {j}'s box pokes out of node {i}'s reach"
                        );
                        if tree.nodes[i].obb.to_box(c).abs().cmpgt(node.obb.half).any() {
                            sticking_out += 1;
                        }
                    }
                    if !tree.nodes[j].is_leaf() {
                        stack.extend(tree.nodes[j].children.map(|c| c as usize));
                    }
                }
            }
            assert!(sticking_out > 0, "the test needs children that stick out");
        }
    }
}
