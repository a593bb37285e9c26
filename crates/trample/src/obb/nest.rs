//! Parents that contain their children (issue 12 item 2, issue 16 item 5):
//! an optional pass over a built tree.
//!
//! [`super::ObbTree::build`] fits every node's box to its own triangles, so
//! a child's box may stick out of its parent's where their orientations
//! differ. The narrow phase walks the tree and descends only into the
//! children of a box the segment hits, so a hit is decided by the whole
//! chain of boxes from the root to the final depth, not by the final-depth
//! box alone. [`super::ObbTree::nest_boxes`] grows every box, deepest
//! first, until it contains its children's boxes: then a segment that
//! meets a box meets all its ancestors', and only the final-depth boxes
//! decide a hit.
//!
//! **Not done by default.** The growth compounds from the leaves up: every
//! level must hold the corners its children already grew. Measured on the
//! default sphere and the knot (BENCHMARKS.md, "Collision accuracy"):
//! false positives at depth 7 rise from 5.6 % to 47 % and from 18 % to
//! 80 % (the roots hold the corners of every box below them). The tight
//! boxes with the chain's decision keep hits at depth d+1 ⊆ hits at depth
//! d all the same (the walk only descends through hit boxes), and the
//! contact walk, whose weights must be continuous, prunes with the reach
//! boxes ([`super::reach`]: the same grown boxes, kept beside the tight
//! ones) and decides with the final-depth boxes alone.

use super::node::ObbTree;
use super::reach::reach_boxes;

impl ObbTree {
    /// Grows every node's box (axes kept; centre and extents moved) until it
    /// contains the eight corners of each child's box, as
    /// [`super::Obb::to_box`] measures them, plus the fit's padding;
    /// children first, so the containment holds down to the leaves. That is
    /// each node's reach box ([`super::reach`], the same growth), so the
    /// grown boxes are the reach boxes and the reach boxes stay as they
    /// were. Sets [`ObbTree::nested`], which makes [`ObbTree::validate`]
    /// check it and [`ObbTree::refit`] keep it. Drops the tilted boxes
    /// ([`ObbTree::slabs`]), which hold the triangles, not the grown boxes.
    /// Costs accuracy (see the
    /// module doc); O(nodes).
    pub fn nest_boxes(&mut self) {
        let reach = reach_boxes(&self.nodes);
        for (node, grown) in self.nodes.iter_mut().zip(&reach) {
            node.obb = *grown;
        }
        self.reach = reach;
        // The tilted boxes hold the triangles, not the grown boxes.
        self.slabs.clear();
        self.nested = true;
    }
}
