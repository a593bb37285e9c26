//! The contact response of a blade (ours, DESIGN §5 "Contact"): after the
//! bending of Eq. 5–7, every vertex still inside an object is moved out of
//! it, whatever the object's speed: a parked car, a standing cow, a ball
//! that stopped leave no blade inside them, and blades under an object
//! resting on the ground lie flat under it.
//!
//! A blade is a chain of rigid segments, so a vertex is not moved on its
//! own: the segment that ends at it **turns** about its lower end towards
//! the way out ([`push_out`]: towards the closest surface point) — its end
//! goes where the push takes it and the segment keeps its length
//! ([`turn_towards`]); the segments above follow (Fig. 7's length
//! preservation, with the ground guard). A blade leaning into a wall is
//! turned back out of it; a blade pushed straight along itself (an object
//! coming down on its tip) folds over the way it leans. A segment whose
//! lower end is **pinned** — on the ground and under the object, as the
//! root of a blade a box stands on — cannot rise inside the object: it is
//! laid flat along the ground in the direction it points, so a blade under
//! an object resting on the ground lies flat under it, and comes out from
//! under it where it is long enough. How pinned a point is goes from 0 to 1
//! with how deep under the object the point just above it lies
//! (`pinned`), so the two rules blend without a jump. One turn settles a
//! flat surface; for a curved one the vertices are tested again, up to
//! [`CONTACT_ITERATIONS`] rounds, each round starting at the lowest vertex
//! moved in the one before (vertices below it are final).

use glam::{Vec3, Vec3A};

use super::bend::preserve_from;
use crate::collision::contact::{penetration, push_out};
use crate::field::Terrain;
use crate::obb::ObbTree;
use crate::object::Pose;

/// How high above the ground guard a vertex still counts as on the ground,
/// and how deep under an object the point this far above it must lie, for
/// the vertex to be wholly pinned (see `pinned`), metres: 2 cm, four
/// times the contact tolerance plus the guard's clearance. Narrower, the
/// rule's gain turns ulps into millimetres; wider, it pins blades the
/// object does not press.
pub const PIN_HEIGHT: f32 = 0.02;

/// How much a blade's lean decides where a segment standing straight up is
/// laid flat (times the segment length, against the segment's own
/// horizontal extent): see [`resolve_contact`].
pub const FLAT_LEAN: f32 = 0.1;

/// Rounds of tests and turns per blade, object and sub-step. One round
/// settles a blade pushed out of a flat face; a blade bent over a curved
/// surface needs two or three. The next sub-step goes on from where this
/// one stopped.
pub const CONTACT_ITERATIONS: usize = 4;

/// How much a blade's lean decides which way it folds (dimensionless weight
/// of the lean's direction, times the push's length): a little always, so
/// that a push straight along the segment still has a side to fold to, and
/// more the more the push opposes the segment (see [`turn_towards`]);
/// continuous, so that it never flips a blade.
const LEAN_BIAS: f32 = 0.05;

/// The new unit direction of a segment of length `len` with direction
/// `dir` whose end is pushed by `push` (metres, the way out): towards the
/// pushed end, `normalize(dir · len + push)` — a turn in the plane of the
/// segment and the push, smooth in its inputs (no saturation, unlike the
/// exact turn that would carry the end all of `|push|` along the push; the
/// rounds of [`resolve_contact`] make up the difference). A push that
/// opposes the segment (an object coming down on a blade's tip) cannot turn
/// it by itself: it folds it towards `lean` (see `LEAN_BIAS`). A push a
/// few ulp long turns the segment by a few ulp.
#[must_use]
pub fn turn_towards(dir: Vec3A, push: Vec3A, lean: Vec3A, len: f32) -> Vec3A {
    let d = dir.try_normalize().unwrap_or(Vec3A::Y);
    let delta = push.length();
    if !(delta > 0.0 && len > 0.0 && delta.is_finite()) {
        return d;
    }
    // The lean's part across the segment, not renormalised: it fades as
    // the lean comes in line with the segment (a near-zero vector made unit
    // would point anywhere: float noise would decide the fold).
    let lean = lean.try_normalize().unwrap_or(Vec3A::ZERO);
    let lean = lean - d * lean.dot(d);
    // The more the push opposes the segment, the less it can turn it: the
    // lean takes over, up to the push's own length when straight opposed.
    let bias = (LEAN_BIAS + (-d.dot(push) / delta).max(0.0)) * delta;
    (d * len + push + lean * bias).try_normalize().unwrap_or(d)
}

/// Moves the vertices of one blade out of one object, in place; returns
/// whether any vertex moved.
///
/// - `verts`: the blade's `n + 1` vertices, world space, root first.
/// - `first`: the lowest vertex that may be inside (vertex 0, the root, is
///   never moved; 0 is taken as 1): the narrow phase knows which segments
///   reached the object.
/// - `pose`, `tree`: the object at this sub-step.
/// - `open_depth`: how far behind an open mesh a vertex counts as inside
///   (see [`push_out`]); the caller passes the blade's segment length.
///
/// Leaves the blade unchanged when it cannot be length-preserved (see
/// [`super::bend::preserve_lengths`]).
pub fn resolve_contact(
    verts: &mut [Vec3A],
    seg_len: f32,
    first: usize,
    pose: &Pose,
    tree: &ObbTree,
    terrain: &Terrain,
    clearance: f32,
    open_depth: f32,
) -> bool {
    if verts.len() < 2 || !super::bend::valid_blade(verts, seg_len) {
        return false;
    }
    let mut from = first.max(1);
    let mut moved = false;
    for _ in 0..CONTACT_ITERATIONS {
        let mut lowest = None;
        for k in from..verts.len() {
            let local = pose.to_local(Vec3::from(verts[k]));
            let Some(target) = push_out(tree, local, open_depth) else {
                continue;
            };
            let start = verts[k - 1];
            let horizontal = Vec3A::new(1.0, 0.0, 1.0);
            let lean = ((verts[k] - verts[0]) * horizontal)
                .try_normalize()
                .unwrap_or(Vec3A::ZERO);
            let push = Vec3A::from(pose.to_world(target)) - verts[k];
            let turned = turn_towards(verts[k] - start, push, lean, seg_len);
            // Laid flat the way the segment points, or, as it stands up, the
            // way the blade leans (a blend: no jump where one takes over).
            let flat = ((verts[k] - start) * horizontal + lean * (FLAT_LEAN * seg_len))
                .try_normalize()
                .unwrap_or(turned);
            let pin = pinned(start, pose, tree, terrain, clearance);
            let dir = turned.lerp(flat, pin).try_normalize().unwrap_or(turned);
            verts[k] = start + dir * seg_len;
            preserve_from(verts, k, seg_len, terrain, clearance);
            lowest.get_or_insert(k);
        }
        let Some(k) = lowest else {
            break;
        };
        moved = true;
        from = k;
    }
    moved
}

/// How pinned under the object a vertex at `p` (world) is, in [0, 1]: how
/// close it is to the ground guard (1 on it, 0 from [`PIN_HEIGHT`] above
/// it) times how deep under the object the point [`PIN_HEIGHT`] above it
/// lies, over [`PIN_HEIGHT`] (clamped) — 1 under a box standing on the
/// ground, falling to 0 where the object's surface rises above the ground
/// (the edge of a ball's contact patch). Both fade over centimetres, so
/// the float noise between two runs moves a pinned blade by as little. A
/// segment starting at a pinned vertex is laid flat (see
/// [`resolve_contact`]).
fn pinned(p: Vec3A, pose: &Pose, tree: &ObbTree, terrain: &Terrain, clearance: f32) -> f32 {
    let guard = terrain.height_at(p.x, p.z) + clearance.max(0.0);
    let on_ground = (1.0 - (p.y - guard) / PIN_HEIGHT).clamp(0.0, 1.0);
    if on_ground.is_nan() || on_ground <= 0.0 {
        return 0.0;
    }
    let above = pose.to_local(Vec3::from(p) + Vec3::Y * PIN_HEIGHT);
    let under = penetration(tree, above, PIN_HEIGHT)
        .map_or(0.0, |(_, depth)| (depth / PIN_HEIGHT).min(1.0));
    on_ground * under
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turn_keeps_the_length_and_moves_the_end_towards_the_push() {
        let d = Vec3A::new(0.0, 1.0, 0.0);
        for push in [
            Vec3A::new(0.03, 0.0, 0.0),
            Vec3A::new(0.02, -0.05, 0.01),
            Vec3A::new(0.0, -0.04, 0.0),
        ] {
            let new = turn_towards(d, push, Vec3A::X, 0.1);
            assert!((new.length() - 1.0).abs() < 1e-6);
            let moved = (new - d) * 0.1;
            let along = moved.dot(push.normalize());
            assert!(along > 0.3 * push.length(), "{push}: {along}");
            assert!(moved.length() < 2.0 * push.length(), "{push}: {moved}");
        }
        // Straight down along the segment: it folds the way it leans.
        let new = turn_towards(d, Vec3A::new(0.0, -0.05, 0.0), Vec3A::X, 0.1);
        assert!(new.x > 0.0 && new.z.abs() < 1e-6, "{new}");
        // No push, no turn; a tiny push, a tiny turn.
        assert_eq!(turn_towards(d, Vec3A::ZERO, Vec3A::X, 0.1), d);
        let tiny = turn_towards(d, Vec3A::new(1e-7, 0.0, 0.0), Vec3A::X, 0.1);
        assert!((tiny - d).length() < 1e-5);
    }
}
