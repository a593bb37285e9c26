//! The contact response of a blade (ours, DESIGN §5 "Contact"): after the
//! bending of Eq. 5–7, every vertex still inside an object is moved out of
//! it, whatever the object's speed: a parked car, a standing cow, a ball
//! that stopped leave no blade inside them, and blades under an object
//! resting on the ground lie flat under it.
//!
//! A blade is a chain of rigid segments, so a vertex is not moved on its
//! own: the segment that ends at it **turns** about its lower end towards
//! the way out ([`push_out`](crate::collision::contact::push_out): towards the closest surface point) — its end
//! goes where the push takes it and the segment keeps its length
//! ([`turn_towards`]); the segments above follow (Fig. 7's length
//! preservation, with the ground guard). A blade leaning into a wall is
//! turned back out of it; a blade pushed straight along itself (an object
//! coming down on its tip) folds over the way it leans. A segment whose
//! lower end is **pinned** — on the ground and under the object, as the
//! root of a blade a box stands on — cannot rise inside the object: it is
//! laid flat along the ground, away from the object's centre and turned
//! towards the way it points ([`flat_direction`]), so a blade under an
//! object resting on the ground lies flat under it, and comes out from
//! under it where it is long enough. How pinned a point is goes from 0 to 1
//! with how deep under the object the point just above it lies
//! (`pinned`), so the two rules blend without a jump; the flat rule comes
//! in with the push ([`pin_for_push`]), so a vertex that only just passes
//! the tolerance is not laid down at once. One turn settles a
//! flat surface; for a curved one the vertices are tested again, up to
//! [`CONTACT_ITERATIONS`] rounds, each round starting at the lowest vertex
//! moved in the one before (vertices below it are final).

use glam::{Vec3, Vec3A};

use super::bend::preserve_from;
use crate::collision::contact::{NO_HINT, penetration, push_out_hinted};
use crate::field::MAX_SEGMENTS;
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

/// How much a blade's lean decides where a segment is laid flat, against
/// the segment's own direction (both at full length): see
/// [`flat_direction`].
pub const FLAT_LEAN: f32 = 0.1;

/// How much the way out from under the object decides where a segment is
/// laid flat, against the segment's own direction (both at full length):
/// see [`flat_direction`]. Above 1 + [`FLAT_LEAN`], so that the sum never
/// cancels away from the object's centre.
pub const FLAT_OUT: f32 = 2.0;

/// Horizontal extent, times the segment length, from which a segment's
/// own direction (or the blade's lean, or the way from the object's centre)
/// counts at full weight in [`flat_direction`]; below it, in proportion.
pub const FLAT_FLOOR: f32 = 0.25;

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
///   (see [`push_out`](crate::collision::contact::push_out)); the caller passes the blade's segment length.
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
    let mut hints = [NO_HINT; MAX_SEGMENTS + 1];
    resolve_contact_hinted(
        verts, seg_len, first, pose, tree, terrain, clearance, open_depth, &mut hints,
    )
}

/// [`resolve_contact`] with a triangle of `tree` per vertex to try first
/// (`hints[k]` for vertex `k`; [`NO_HINT`] or any index: the answers are
/// the same bit for bit, a triangle near the vertex saves the most, see
/// [`push_out_hinted`]); on return each holds the triangle of the vertex's
/// last closest point, for the collider's next sub-step.
#[allow(clippy::too_many_arguments)]
pub fn resolve_contact_hinted(
    verts: &mut [Vec3A],
    seg_len: f32,
    first: usize,
    pose: &Pose,
    tree: &ObbTree,
    terrain: &Terrain,
    clearance: f32,
    open_depth: f32,
    hints: &mut [u32; MAX_SEGMENTS + 1],
) -> bool {
    if verts.len() < 2 || !super::bend::valid_blade(verts, seg_len) {
        return false;
    }
    let mut from = first.max(1);
    let mut moved = false;
    // Per vertex, the triangle of its last closest point: a later round
    // (or sub-step) tries it first (`push_out_hinted`, same answers).
    // Per vertex, the last point it was asked `pinned` at and the answer: a
    // later round asking again at the same point (the lower end of a
    // segment turned again) takes it from here (a third of the questions
    // on herd_small; the same answers).
    let mut pins = [None::<([u32; 3], f32)>; MAX_SEGMENTS + 1];
    for _ in 0..CONTACT_ITERATIONS {
        let mut lowest = None;
        for k in from..verts.len() {
            let local = pose.to_local(Vec3::from(verts[k]));
            // A vertex with no triangle of its own yet tries the one below
            // it, a segment away (the walk is bounded near there instead of
            // starting unbounded; the same answers: `push_out_hinted`).
            let below = hints.get(k - 1).copied().unwrap_or(NO_HINT);
            let mut no_hint = NO_HINT;
            let hint = hints.get_mut(k).unwrap_or(&mut no_hint);
            if *hint == NO_HINT {
                *hint = below;
            }
            let Some(target) = push_out_hinted(tree, local, open_depth, hint) else {
                continue;
            };
            let start = verts[k - 1];
            let horizontal = Vec3A::new(1.0, 0.0, 1.0);
            let lean = ((verts[k] - verts[0]) * horizontal)
                .try_normalize()
                .unwrap_or(Vec3A::ZERO);
            let push = Vec3A::from(pose.to_world(target)) - verts[k];
            let turned = turn_towards(verts[k] - start, push, lean, seg_len);
            let flat = flat_direction(
                verts[k] - start,
                verts[k] - verts[0],
                start - Vec3A::from(pose.position),
                seg_len,
            )
            .unwrap_or(turned);
            let at = start.to_array().map(f32::to_bits);
            let mut no_pin = None;
            let known = pins.get_mut(k - 1).unwrap_or(&mut no_pin);
            let pin = match *known {
                Some((asked, pin)) if asked == at => pin,
                _ => {
                    let pin = pinned(start, pose, tree, terrain, clearance);
                    *known = Some((at, pin));
                    pin
                }
            };
            let pin = pin_for_push(pin, push.length(), (flat - turned).length(), seg_len);
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

/// The horizontal unit direction a pinned segment is laid flat in
/// ([`resolve_contact`]), from its vector `seg`, the blade's lean `lean`
/// (its vertex minus its root) and `out`, its lower end minus the object's
/// centre. Each horizontal part is divided by `max(its length, FLAT_FLOOR ·
/// seg_len)`: at full length once it is that long, shorter in proportion
/// below. The direction is that of `seg + FLAT_LEAN · lean + FLAT_OUT ·
/// out` (the parts): away from the object's centre — grass pressed down
/// spreads out from under what presses it — turned by up to about 30°
/// towards the way the segment points and the blade leans. `None` when the
/// sum is zero, which needs the segment's lower end within
/// `FLAT_FLOOR · seg_len` of the centre's vertical.
///
/// Why not the way the segment points alone (the rule before): a blade
/// standing straight up has a horizontal part of a few millimetres, whose
/// direction turns by `noise / length` — the float noise between two runs
/// (CPU and GPU) became millimetres to centimetres on a box sliding over
/// upright blades (herd_small's box12: 3.5 mm). Any rule that turns from
/// the segment's direction to another has a place where the two cancel;
/// with the way out weighted above the other two together it lies under
/// the object's centre, not at every upright blade, and elsewhere the gain
/// is at most `1 / (FLAT_OUT · FLAT_FLOOR · seg_len)` (measured: a blend
/// that gave the way out weight only where the segment was short still
/// cancelled for segments leaning a little towards the centre, 9.6 mm on
/// the busy test scene).
#[must_use]
pub fn flat_direction(seg: Vec3A, lean: Vec3A, out: Vec3A, seg_len: f32) -> Option<Vec3A> {
    let horizontal = Vec3A::new(1.0, 0.0, 1.0);
    let floor = (FLAT_FLOOR * seg_len).max(f32::MIN_POSITIVE);
    let part = |v: Vec3A| {
        let h = v * horizontal;
        h / h.length().max(floor)
    };
    (part(seg) + part(lean) * FLAT_LEAN + part(out) * FLAT_OUT).try_normalize()
}

/// How far a pinned segment's end must be pushed for the flat rule to take
/// it all the way (see [`pin_for_push`]), as a share of the segment's
/// length: three quarters.
pub const PIN_REACH: f32 = 0.75;

/// How far towards flat a segment whose lower end is `pin` pinned
/// (`pinned`, 0 to 1) is turned, when its upper end is pushed out by
/// `push` metres, `turn` is the distance between the unit directions it
/// would take lying flat and turned by the push alone (0 to 2), and
/// `seg_len` its length: `pin · min(push / span, 1)` with `span =
/// min(turn, PIN_REACH) · seg_len`, the way the end would go towards flat.
/// A small push moves the end towards flat by about `pin · push`, not
/// more, and a push of a few ulp turns the segment by a few ulp, as
/// [`turn_towards`] does; a vertex deep under an object (pushed by three
/// quarters of a segment or more) is laid flat whole, whatever its push's
/// direction.
///
/// Why: applied whole the moment a vertex's depth passed the contact
/// tolerance, the rule laid a segment down by centimetres for one ulp of
/// depth (4 cm from a 1e-7 m change of a capsule's height,
/// `tests/contact_continuity.rs`). A ramp over a fixed centimetre of push
/// kept a gain of ~15 that grew step after step (115 runs of 1,500 moved a
/// blade by over 1 mm for 1e-7 m, against 11 with the whole rule); over
/// `turn · seg_len` alone, a vertex 14 cm deep was laid only 79 % flat and
/// took the rest from its push, whose way turns fast deep in a box. 0 for
/// a push that is not positive (or NaN).
#[must_use]
pub fn pin_for_push(pin: f32, push: f32, turn: f32, seg_len: f32) -> f32 {
    if push.is_nan() || push <= 0.0 {
        return 0.0;
    }
    let span = turn.min(PIN_REACH) * seg_len;
    if span.is_nan() || span <= push {
        return pin;
    }
    pin * (push / span)
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

    /// The flat rule comes in with the push: nothing for no push (or NaN),
    /// an end moved towards flat by about `pin · push` while the push is
    /// short of the way to flat (or of `PIN_REACH` of the segment), the
    /// whole pin beyond; and a few ulp of push more change it by as
    /// little (the rule applied whole before, this failed at once).
    #[test]
    fn the_flat_rule_comes_in_with_the_push() {
        let len = 0.12;
        assert_eq!(pin_for_push(1.0, 0.0, 1.2, len), 0.0);
        assert_eq!(pin_for_push(1.0, f32::NAN, 1.2, len), 0.0);
        assert_eq!(pin_for_push(1.0, -1e-3, 1.2, len), 0.0);
        // Deep: the whole pin, whatever the push's way.
        assert_eq!(pin_for_push(0.8, 0.2, 1.2, len), 0.8);
        assert_eq!(pin_for_push(0.8, PIN_REACH * len, 1.9, len), 0.8);
        // Short: in proportion to the push over the way to flat.
        let p = pin_for_push(1.0, 0.01, 0.5, len);
        assert!((p - 0.01 / (0.5 * len)).abs() < 1e-6, "{p}");
        let p = pin_for_push(0.5, 0.01, 1.5, len);
        assert!((p - 0.5 * 0.01 / (PIN_REACH * len)).abs() < 1e-6, "{p}");
        // Continuous from the tolerance on: a push of 1e-7 m, a pin of ~1e-6.
        let tiny = pin_for_push(1.0, 1e-7, 1.2, len);
        assert!(tiny > 0.0 && tiny < 2e-6, "{tiny}");
        let mut last = 0.0;
        for k in 1..=2000 {
            let p = pin_for_push(0.9, k as f32 * 1e-4, 1.0, len);
            assert!(p >= last && p - last < 2e-3, "{k}: {last} → {p}");
            last = p;
        }
        assert_eq!(last, 0.9);
    }

    /// Whatever triangles the hints name — none, the right ones, wrong
    /// ones, indices past the mesh — the blade ends where it ends without
    /// them, bit for bit, and the hints it hands back name the triangles it
    /// found (the contact stage keeps them for the collider's next
    /// sub-step).
    #[test]
    fn hints_change_no_bit_of_the_response() {
        use crate::object::shapes::{cuboid, knot, sphere};
        use crate::test_rng::XorShift;
        let terrain = Terrain::Flat(0.0);
        let mut rng = XorShift(0x0000_ddb1_a5e5_u64);
        let (mut moved, mut checked) = (0, 0);
        for mesh in [sphere(0.6, 3), knot(1.2), cuboid(Vec3::new(0.5, 0.3, 0.4))] {
            let tree = ObbTree::build(&mesh, 32);
            let n_tri = tree.triangles.len() as u64;
            let pose = Pose::at_rest(Vec3::new(0.0, 0.35, 0.0));
            for _ in 0..300 {
                // A blade of four 0.1 m segments rooted under or beside the
                // object, leaning a little.
                let root = Vec3A::new(rng.range(-0.8, 0.8), 0.0, rng.range(-0.8, 0.8));
                let lean = Vec3A::new(rng.range(-0.3, 0.3), 1.0, rng.range(-0.3, 0.3)).normalize();
                let blade: Vec<Vec3A> = (0..5).map(|k| root + lean * (0.1 * k as f32)).collect();
                let mut plain = blade.clone();
                let m = resolve_contact(&mut plain, 0.1, 1, &pose, &tree, &terrain, 0.002, 0.1);
                let mut found = [NO_HINT; MAX_SEGMENTS + 1];
                let mut again = blade.clone();
                resolve_contact_hinted(
                    &mut again, 0.1, 1, &pose, &tree, &terrain, 0.002, 0.1, &mut found,
                );
                for round in 0..3 {
                    let mut hints = match round {
                        0 => found,
                        1 => [0; MAX_SEGMENTS + 1].map(|_| (rng.next_u64() % n_tri) as u32),
                        _ => [u32::MAX - 1; MAX_SEGMENTS + 1],
                    };
                    let mut v = blade.clone();
                    let mh = resolve_contact_hinted(
                        &mut v, 0.1, 1, &pose, &tree, &terrain, 0.002, 0.1, &mut hints,
                    );
                    assert_eq!(mh, m);
                    for (a, b) in v.iter().zip(&plain) {
                        assert_eq!(
                            a.to_array().map(f32::to_bits),
                            b.to_array().map(f32::to_bits)
                        );
                    }
                    checked += 1;
                }
                moved += usize::from(m);
            }
        }
        assert_eq!(checked, 2700);
        assert!(moved > 100, "only {moved} blades met an object");
    }

    /// A blade meeting an object for the first time (no hints) leaves every
    /// vertex it asked about with a triangle to try first next time: one
    /// whose own question needed no walk (its voxel is known outside) takes
    /// the triangle of the vertex below, a segment away, so its next walk
    /// starts bounded there. Without the seeding the top vertices came back
    /// with none (checked: the last assertion below).
    #[test]
    fn a_vertex_with_no_triangle_of_its_own_takes_the_one_below() {
        use crate::object::shapes::sphere;
        let tree = ObbTree::build(&sphere(0.3, 3), 32);
        let pose = Pose::at_rest(Vec3::new(0.0, 0.35, 0.0));
        let terrain = Terrain::Flat(0.0);
        // Upright through the sphere's side: the lower vertices inside it,
        // the top one 0.4 m above it.
        let root = Vec3A::new(0.1, 0.0, 0.05);
        let mut blade: Vec<Vec3A> = (0..6).map(|k| root + Vec3A::Y * (0.2 * k as f32)).collect();
        let top = pose.to_local(Vec3::from(blade[5]));
        let mut alone = NO_HINT;
        assert_eq!(push_out_hinted(&tree, top, 0.2, &mut alone), None);
        assert_eq!(
            alone, NO_HINT,
            "the top vertex's own question walks nothing"
        );
        let mut hints = [NO_HINT; MAX_SEGMENTS + 1];
        let moved = resolve_contact_hinted(
            &mut blade, 0.2, 1, &pose, &tree, &terrain, 0.002, 0.2, &mut hints,
        );
        assert!(moved, "the sphere pushes the blade");
        for (k, &h) in hints.iter().enumerate().take(6).skip(1) {
            assert!(
                (h as usize) < tree.triangles.len(),
                "vertex {k} left with no triangle: {hints:?}"
            );
        }
    }

    /// A segment standing straight up, a few ulp of noise either way: it is
    /// laid flat the way out from under the object both times (the
    /// directions a few ulp apart). Taken from the segment and the blade's
    /// lean alone (the rule before `flat_direction`), noise of 1e-6 m
    /// turned it by 180°; this test failed then.
    #[test]
    fn an_upright_segment_is_laid_flat_the_same_way_whatever_its_noise() {
        let out = Vec3A::new(0.3, -0.4, 0.4);
        let len = 0.1;
        let mut dirs = Vec::new();
        for noise in [1e-6f32, -1e-6] {
            let seg = Vec3A::new(noise, len, noise * 0.5);
            let d = flat_direction(seg, seg, out, len).unwrap();
            assert!((d.length() - 1.0).abs() < 1e-6 && d.y == 0.0, "{d}");
            dirs.push(d);
        }
        let want = (out * Vec3A::new(1.0, 0.0, 1.0)).normalize();
        for d in &dirs {
            assert!(d.distance(want) < 1e-3, "{d} vs {want}");
        }
        assert!(dirs[0].distance(dirs[1]) < 1e-3);
        // A leaning segment goes down away from the centre, turned towards
        // the way it points (by atan(1 / FLAT_OUT) here: its part is at
        // full length, at right angles to the way out).
        let seg = Vec3A::new(0.04, 0.08, -0.03);
        let d = flat_direction(seg, Vec3A::ZERO, out, len).unwrap();
        let turn = d.dot(want).clamp(-1.0, 1.0).acos();
        assert!((turn - (1.0 / FLAT_OUT).atan()).abs() < 1e-3, "{turn}");
        assert!(d.dot(Vec3A::new(0.8, 0.0, -0.6)) > 0.0, "{d}");
        // Nothing horizontal at all: no direction.
        assert!(flat_direction(Vec3A::Y, Vec3A::Y, Vec3A::ZERO, len).is_none());
    }
}
