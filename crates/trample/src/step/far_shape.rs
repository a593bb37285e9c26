//! What a far body's shape does to its far pass's cost (ours, issue 16):
//! the weight of its work in the far turns' balance
//! ([`super::passes::far_schedule`]).
//!
//! The turns balance each far body's reach ground times its sub-steps
//! ([`super::passes::FarWork`]): the blades its narrow phase looks at. What
//! a pass costs for each of those blades depends on the shape over them:
//! a solid box's tree reaches the grass with every final node along its
//! floor, a cow's stands on four legs and its body passes above the
//! blades, so most of the walks under it end at the first boxes. Measured
//! one kind at a time on the herd at `far_every = 16` (two cores; ms per
//! m² of reach ground and sub-step): box 0.10, knot 0.10, beetle car
//! 0.084, ball 0.078, cow 0.052 (BENCHMARKS.md, session 69). A turn
//! balanced by ground alone then carries up to twice the work of another
//! (the herd's phases' medians 6–7 ms apart; weighed by kind, 2–3 ms).
//!
//! The measure is the pose's alone, so that both paths plan the same
//! turns without reading anything back: the **grass-reaching share**
//! ([`grass_reach_share`]) — over the body's colliders, the final nodes
//! of the narrow phase's walk (depth `precision`, or a shallower leaf) whose
//! world box comes down within a blade's length and the contact shell of
//! the ground, each counted by the area of its box's shadow on the ground
//! (the vertical projection of a box with half-extents `h` along unit axes
//! `a`: `4 (h₀h₁|a₂·y| + h₁h₂|a₀·y| + h₀h₂|a₁·y|)`, the same at every
//! heading), over the reach ground. On the herd at precision 7: box 0.35,
//! knot 0.46, car 0.32, ball 0.30, cow 0.20; the cost per m²·sub-step is
//! `0.019 + 0.198 · share` within 15 % for each kind. [`shape_weight`]
//! is that line over its value at the herd's mean share.

use super::body::Body;
use super::simulation::Simulation;
use crate::collision::broad_phase::world_obb;
use crate::obb::MAX_TREE_DEPTH;

/// The cost of a pass per m² of reach ground and sub-step that does not
/// grow with the shape's share, over what does: `0.019 / 0.198` of the line
/// fitted to the herd's five kinds (module docs).
pub const SHAPE_COST_BASE: f64 = 0.096;

/// The grass-reaching share the weight is 1 at: the herd's mean at
/// precision 7 (32 boxes 0.35, 32 balls 0.30, 20 cars 0.32, 20 cows 0.20,
/// 24 knots 0.46), so that the herd's weights average about 1.
pub const SHAPE_SHARE_TYPICAL: f64 = 0.33;

/// A far body's work weight for a grass-reaching share `share`
/// ([`grass_reach_share`]): `(SHAPE_COST_BASE + share) /
/// (SHAPE_COST_BASE + SHAPE_SHARE_TYPICAL)`, the fitted cost per m² over
/// its value at the typical share. Finite and > 0 for any input (a share
/// that is not finite or below 0 counts as 0).
#[must_use]
pub fn shape_weight(share: f64) -> f64 {
    let share = if share.is_finite() {
        share.max(0.0)
    } else {
        0.0
    };
    (SHAPE_COST_BASE + share) / (SHAPE_COST_BASE + SHAPE_SHARE_TYPICAL)
}

/// The share of `area` (m², the body's reach ground:
/// [`super::passes::FarWork::area`]) under the final nodes of its
/// colliders' trees that reach down into the grass (module docs): the sum
/// of those nodes' boxes' shadows on the ground over `area`. A node
/// reaches the grass when its world box's lowest point lies below the
/// terrain under its collider's root box plus the field's longest blade and
/// `sim.params.contact_shell_m`. 0 when `area` is not positive. In a
/// nested tree (every box holds its children's) a box wholly above that
/// height is not walked further.
#[must_use]
pub fn grass_reach_share(sim: &Simulation, body: &Body, area: f64) -> f64 {
    if !(area > 0.0 && area.is_finite()) {
        return 0.0;
    }
    let final_depth = sim.params.precision.clamp(1, MAX_TREE_DEPTH);
    let reach = sim.field.max_blade_length + sim.params.contact_shell_m;
    let mut shadow = 0.0f64;
    let mut stack = Vec::new();
    for c in body.colliders() {
        let centre = c.world_root.center;
        let top = sim.field.terrain.height_at(centre.x, centre.z) + reach;
        let nodes = &c.tree.nodes;
        if nodes.is_empty() {
            continue;
        }
        stack.clear();
        stack.push(0u32);
        while let Some(i) = stack.pop() {
            let node = &nodes[i as usize];
            let b = world_obb(&node.obb, c.pose);
            let up = b.axes.map(|a| a.y.abs());
            let h = b.half;
            let bottom = b.center.y - (h.x * up[0] + h.y * up[1] + h.z * up[2]);
            let reaches = bottom < top;
            if node.is_leaf() || node.depth >= final_depth {
                if reaches {
                    shadow += f64::from(
                        4.0 * (h.x * h.y * up[2] + h.y * h.z * up[0] + h.x * h.z * up[1]),
                    );
                }
            } else if reaches || !c.tree.nested {
                stack.extend(node.children);
            }
        }
    }
    let share = shadow / area;
    if share.is_finite() {
        share.max(0.0)
    } else {
        0.0
    }
}
