//! Structural checks of an [`ObbTree`] (parry's `assert_well_formed` idea):
//! the invariants that the collision queries rely on (DESIGN §3: "every
//! triangle lies in its node's box and in every ancestor's box").

use glam::Vec3;

use super::node::{NO_CHILD, ObbTree};

/// Allowed deviation of an axis from unit length, and of two axes from
/// orthogonality (`|dot|`): a few ulps of `f32` after the fit's
/// re-orthonormalisation, with margin.
const AXIS_TOLERANCE: f32 = 1e-4;

impl ObbTree {
    /// Checks every invariant of a tree made by [`ObbTree::build`]; the first
    /// violation found is described in the error.
    ///
    /// - There is a root (node 0, depth 1) covering all triangles.
    /// - Every node: centre, half extents and Eq. 3 `eqn` finite; half
    ///   extents ≥ 0; `|eqn| ≤ 1` (Eq. 3 is a weighted mean of unit vectors);
    ///   axes orthonormal and right-handed (within 1e-4); its triangle range
    ///   inside `triangles`.
    /// - Every corner of every triangle of a node lies in the node's box, as
    ///   [`crate::obb::Obb::to_box`] measures it, with no tolerance beyond the
    ///   padding the fit put in the half extents ([`crate::obb::fit::padding`]).
    ///   Since a node's range is inside each ancestor's range (next point),
    ///   this checks each triangle against its leaf's box and every
    ///   ancestor's box. The same for the node's tilted boxes
    ///   ([`ObbTree::slabs`]: one per node, or none; none for a nested tree).
    /// - Children: both [`NO_CHILD`] (leaf) or both valid indices after
    ///   the parent, each node the child of exactly one parent; depth =
    ///   parent depth + 1; the two ranges are non-empty and partition the
    ///   parent's range (left first).
    /// - Every leaf holds ≥ 1 triangle (unless the tree is empty); the
    ///   deepest leaf's depth is `max_depth`.
    /// - When the tree is [`ObbTree::nested`]: every corner of each child's
    ///   box lies in its parent's box, as [`crate::obb::Obb::to_box`]
    ///   measures it, with no tolerance (parents contain their children).
    ///
    /// Cost: O(triangles × depth).
    pub fn validate(&self) -> Result<(), String> {
        let root = self.nodes.first().ok_or("the tree has no root node")?;
        if root.depth != 1 {
            return Err(format!("root depth is {}, expected 1", root.depth));
        }
        if root.first_tri != 0 || root.tri_count as usize != self.triangles.len() {
            return Err(format!(
                "root covers triangles {}..+{}, expected all {}",
                root.first_tri,
                root.tri_count,
                self.triangles.len()
            ));
        }
        if !(self.slabs.is_empty() || self.slabs.len() == self.nodes.len() && !self.nested) {
            return Err(format!(
                "{} nodes but {} tilted boxes (expected as many, or none for a nested tree)",
                self.nodes.len(),
                self.slabs.len()
            ));
        }
        let mut parents = vec![0u32; self.nodes.len()];
        let mut deepest_leaf = 0;
        for (i, node) in self.nodes.iter().enumerate() {
            let obb = &node.obb;
            if !(obb.center.is_finite() && obb.half.is_finite() && node.eqn.is_finite()) {
                return Err(format!(
                    "node {i}: non-finite centre, half extents or eqn: {node:?}"
                ));
            }
            if obb.half.min_element() < 0.0 {
                return Err(format!("node {i}: negative half extent {}", obb.half));
            }
            if node.eqn.length() > 1.0 + AXIS_TOLERANCE {
                return Err(format!("node {i}: |eqn| = {} > 1", node.eqn.length()));
            }
            check_axes(&obb.axes).map_err(|e| format!("node {i}: {e}"))?;
            let (first, count) = (node.first_tri as usize, node.tri_count as usize);
            let Some(tris) = self.triangles.get(first..first.saturating_add(count)) else {
                return Err(format!(
                    "node {i}: triangle range {first}..+{count} outside {}",
                    self.triangles.len()
                ));
            };
            let slabs = self.slabs.get(i);
            for (t, tri) in tris.iter().enumerate() {
                for corner in tri {
                    let q = obb.to_box(*corner);
                    if !q.abs().cmple(obb.half).all() {
                        return Err(format!(
                            "node {i}: corner {corner} of triangle {} is outside its box \
                             (box coordinates {q}, half extents {})",
                            first + t,
                            obb.half
                        ));
                    }
                    if let Some(s) = slabs.filter(|s| !s.holds(q.to_array(), 0.0)) {
                        return Err(format!(
                            "node {i}: corner {corner} of triangle {} is outside its tilted \
                             boxes (box coordinates {q}, {s:?})",
                            first + t
                        ));
                    }
                }
            }
            match node.children {
                [NO_CHILD, NO_CHILD] => {
                    if count == 0 && !self.triangles.is_empty() {
                        return Err(format!("leaf {i} holds no triangle"));
                    }
                    deepest_leaf = deepest_leaf.max(node.depth);
                }
                [l, r] => {
                    let (l, r) = (l as usize, r as usize);
                    if l <= i || r <= i || l >= self.nodes.len() || r >= self.nodes.len() || l == r
                    {
                        return Err(format!("node {i}: invalid children {:?}", node.children));
                    }
                    parents[l] += 1;
                    parents[r] += 1;
                    let (a, b) = (&self.nodes[l], &self.nodes[r]);
                    if a.depth != node.depth + 1 || b.depth != node.depth + 1 {
                        return Err(format!(
                            "node {i} (depth {}): children depths {} and {}",
                            node.depth, a.depth, b.depth
                        ));
                    }
                    let partitions = a.first_tri == node.first_tri
                        && a.tri_count > 0
                        && b.tri_count > 0
                        && u64::from(a.first_tri) + u64::from(a.tri_count)
                            == u64::from(b.first_tri)
                        && u64::from(a.tri_count) + u64::from(b.tri_count)
                            == u64::from(node.tri_count);
                    if self.nested {
                        for (c, child) in [(l, a), (r, b)] {
                            if let Some(corner) = child
                                .obb
                                .corners()
                                .into_iter()
                                .find(|p| !obb.to_box(*p).abs().cmple(obb.half).all())
                            {
                                return Err(format!(
                                    "node {i}: corner {corner} of child {c}'s box is outside its box \
                                     (box coordinates {}, half extents {})",
                                    obb.to_box(corner),
                                    obb.half
                                ));
                            }
                        }
                    }
                    if !partitions {
                        return Err(format!(
                            "node {i}: children ranges {}..+{} and {}..+{} do not partition {}..+{}",
                            a.first_tri,
                            a.tri_count,
                            b.first_tri,
                            b.tri_count,
                            node.first_tri,
                            node.tri_count
                        ));
                    }
                }
            }
        }
        if let Some(i) = parents.iter().skip(1).position(|&n| n != 1) {
            return Err(format!(
                "node {} has {} parents, expected 1",
                i + 1,
                parents[i + 1]
            ));
        }
        if deepest_leaf != self.max_depth {
            return Err(format!(
                "max_depth is {}, deepest leaf has depth {deepest_leaf}",
                self.max_depth
            ));
        }
        Ok(())
    }

    /// [`ObbTree::validate`], for tests: call it after every build.
    ///
    /// # Panics
    /// When the tree is not well formed, with the violation in the message.
    #[track_caller]
    pub fn assert_well_formed(&self) {
        if let Err(e) = self.validate() {
            panic!("OBB tree is not well formed: {e}");
        }
    }
}

/// Axes unit, pairwise orthogonal and right-handed (`u × v · w > 0`).
fn check_axes(axes: &[Vec3; 3]) -> Result<(), String> {
    let [u, v, w] = *axes;
    if !(u.is_finite() && v.is_finite() && w.is_finite()) {
        return Err(format!("non-finite axes {axes:?}"));
    }
    for a in axes {
        if (a.length() - 1.0).abs() > AXIS_TOLERANCE {
            return Err(format!("axis {a} is not unit length"));
        }
    }
    let dots = [u.dot(v), v.dot(w), w.dot(u)];
    if dots.iter().any(|d| d.abs() > AXIS_TOLERANCE) {
        return Err(format!("axes {axes:?} are not orthogonal (dots {dots:?})"));
    }
    if u.cross(v).dot(w) <= 0.0 {
        return Err(format!("axes {axes:?} are left-handed"));
    }
    Ok(())
}
