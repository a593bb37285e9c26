//! The position-level contact test (ours, DESIGN §5 "Contact"): is a blade
//! vertex inside an object, and where on the surface must it go?
//!
//! Eq. 2 makes the force on a blade `|v| · EqN`: an object that stands
//! still pushes nothing, so the paper leaves grass inside anything parked or
//! stopped. The contact response moves every vertex found inside an object
//! to the object's surface, whatever the object's speed. It uses the mesh,
//! not the boxes of the chosen precision:
//!
//! - **Closed meshes**: the inside grid (`inside_grid.rs`) answers for a
//!   vertex in a voxel that meets no triangle; otherwise the closest point of
//!   the mesh ([`closest_point_on_mesh`](super::closest_point::closest_point_on_mesh)) decides by the side of its
//!   triangle where it lies on a face's interior (exact: the point projects
//!   onto the face along its normal), and the exact ray-parity test
//!   ([`point_inside_by_ray`]) where it lies on an edge or a corner.
//! - **Open meshes** have no inside that parity can tell. Two rules:
//!   - *sheets* (the default): a vertex counts as inside when it lies
//!     behind the surface (against the normal of its closest triangle's
//!     face, or the angle-weighted pseudo-normal of the edge or corner its
//!     closest point lies on: [`crate::obb::pseudo_normals`]) and within
//!     `open_depth` of it (a blade cannot be deeper than that behind a thin
//!     sheet it crossed; farther, "behind" means nothing). The hollow of a
//!     body with holes (a car with no floor) is outside.
//!   - *winding* ([`ObbTree::enable_winding`]; an object's
//!     `track.open_inside = "winding"`): how much a vertex is inside is the
//!     [`inside_factor`] of the mesh's generalized winding number there
//!     ([`super::winding`]: 1 inside a closed part, ½ in the plane of a
//!     hole, 0 outside), faded in over [`super::winding::ROOT_FADE_M`]
//!     from the faces of the mesh's root box, and its depth is that factor times the distance to
//!     its closest surface point, at any distance (`open_depth` is not
//!     used). Off the surface the winding number is continuous, and on it
//!     the distance is 0, so the depth is continuous everywhere, across
//!     holes too. Away from the surface the winding number is read from a
//!     grid ([`super::winding_grid`]); near it each query walks the tree
//!     (BENCHMARKS.md, "Session 37" and "Session 38").
//!
//! The target is continuous in the vertex (ours, DESIGN §5 "continuous"):
//! a vertex `d` deep goes to depth [`CONTACT_TOLERANCE_M`], i.e. it moves
//! by `d − tolerance`, and not at all when `d ≤ tolerance`. A vertex a few
//! ulp deeper moves a few ulp more. It moves along the way to its closest
//! surface point blended with the ways to the other faces' points about as
//! near ([`PUSH_BLEND_M`]): the closest point alone jumps where two faces
//! are equally near, and inside a mesh that is not only deep (the medial
//! axis) but at every edge — the plane halfway between two faces of a
//! tessellated ball reaches its surface. A vertex 1.3 cm inside the
//! garden's ball, moved by 1e-7 m across that plane, went 1.2 mm another
//! way (the CPU and GPU paths 1.2 mm apart). (Deep inside, where faces
//! across the object are as near, the way out still turns fast: no
//! continuous rule can retract a ball onto its sphere.)

use glam::Vec3;

use super::closest_point::{
    Feature, NearPoints, SurfacePoint, closest_point_and_near, closest_point_on_triangle_region,
    closest_point_within_sq,
};
use super::exact::point_inside_by_ray;
use super::winding::{inside_factor, root_fade};
use super::winding_grid::winding_at;
use crate::obb::ObbTree;

/// How deep, metres, the contact response leaves a vertex inside an object:
/// 3 mm. It must exceed the ground clearance of the ground guard
/// ([`crate::field::generate::GROUND_CLEARANCE_M`], 2 mm), or a vertex under
/// an object resting on the ground would be pushed into the ground and
/// lifted back for ever; at 3 mm it is below a blade's half width.
pub const CONTACT_TOLERANCE_M: f32 = 0.003;

/// Over how much farther than the closest surface point, metres, another
/// face's closest point still turns the way a vertex is pushed out
/// ([`push_out`]): 1 mm. A face as near as the closest one counts as much
/// (weight 1), one 1 mm farther not at all, linearly between. Two faces
/// meeting at an angle θ hand the push from one to the other over
/// `PUSH_BLEND_M / (2 sin(θ/2))` of the vertex's travel, not at a point;
/// the push turns by about `d · sin(θ/2)` there, for a vertex `d` deep.
pub const PUSH_BLEND_M: f32 = 0.001;

/// How deep vertex `p` (object-local frame) lies inside the object of
/// `tree`, and the surface point it is closest to: `Some((point, depth))`
/// when it is inside (`depth` metres ≥ 0 to `point`), `None` when it is
/// outside (see the module docs for what "inside" means for closed and open
/// meshes: with the winding rule `depth` is the distance times the
/// [`inside_factor`]; `open_depth`, metres: how far behind an open mesh
/// a vertex still counts as inside by the sheet rule). Non-finite `p`
/// gives `None`. No allocation.
#[must_use]
pub fn penetration(tree: &ObbTree, p: Vec3, open_depth: f32) -> Option<(Vec3, f32)> {
    match surface_and_side(tree, p, open_depth, f32::INFINITY, None) {
        Some((s, inside)) if inside > 0.0 => Some((s.point, s.distance_sq.sqrt() * inside)),
        _ => None,
    }
}

/// [`penetration`] with the way out of [`push_out`]: `Some((way, depth))`
/// when `p` lies inside, `way` the unit [`push_direction`] (the way to the
/// closest surface point blended with the faces about as near), `depth`
/// metres to the closest point; `None` when it is outside, or on the
/// surface with no way out. The narrow phase's push on a segment wholly
/// inside a closed mesh (`contact_segment`) takes it: with the closest
/// point alone its push turned by up to a face's angle for 1e-7 m.
#[must_use]
pub fn way_out(tree: &ObbTree, p: Vec3, open_depth: f32) -> Option<(Vec3, f32)> {
    let mut near = NearPoints::default();
    match surface_and_side(tree, p, open_depth, f32::INFINITY, Some(&mut near)) {
        Some((s, inside)) if inside > 0.0 => {
            let depth = s.distance_sq.sqrt();
            let way = push_direction(&near, p, depth).or_else(|| (s.point - p).try_normalize())?;
            Some((way, depth * inside))
        }
        _ => None,
    }
}

/// The closest surface point that [`penetration`] measured `p` against and
/// how much `p` is inside (see the module docs): 1 or 0 for a closed mesh,
/// the [`inside_factor`] for an open one; `None` when no point was needed
/// (empty tree, non-finite `p`, a voxel known outside, an open mesh's
/// factor 0, nothing within `open_depth` of an open mesh). `bound_sq`: a squared distance
/// from `p` to some point of the mesh, measured as the walk measures
/// (`closest_point_on_triangle_region`, `distance_squared`), or infinity:
/// the walk skips the boxes farther than it, with the same answer
/// ([`closest_point_within_sq`]). With `near`, the walk also keeps the
/// points within [`PUSH_BLEND_M`] of the closest
/// ([`closest_point_and_near`]; `bound_sq` then bounds those).
fn surface_and_side(
    tree: &ObbTree,
    p: Vec3,
    open_depth: f32,
    bound_sq: f32,
    near: Option<&mut NearPoints>,
) -> Option<(SurfacePoint, f32)> {
    let closest = |max_sq: f32, near: Option<&mut NearPoints>| match near {
        Some(n) => closest_point_and_near(tree, p, max_sq, PUSH_BLEND_M, n),
        None => closest_point_within_sq(tree, p, max_sq),
    };
    if tree.is_empty() || !p.is_finite() {
        return None;
    }
    if tree.closed {
        let known = tree.inside.as_ref().and_then(|g| g.classify(p));
        if known == Some(false) {
            return None;
        }
        let s = closest(bound_sq, near)?;
        let inside = match (known, s.feature()) {
            (Some(true), _) => true,
            (_, Feature::Face) => (p - s.point).dot(s.normal) < 0.0,
            (_, Feature::EdgeOrVertex) => point_inside_by_ray(tree, p),
        };
        Some((s, if inside { 1.0 } else { 0.0 }))
    } else {
        if open_depth.is_nan() || open_depth < 0.0 {
            return None;
        }
        if tree.winds() {
            // Outside (factor 0) needs no closest point; no depth bound.
            let fade = root_fade(tree, p);
            if fade <= 0.0 {
                return None;
            }
            let inside = inside_factor(winding_at(tree, p)) * fade;
            if inside <= 0.0 {
                return None;
            }
            return Some((closest(bound_sq, near)?, inside));
        }
        let s = closest((open_depth * open_depth).min(bound_sq), near)?;
        let inside = (p - s.point).dot(s.side_normal(tree)) < 0.0;
        Some((s, if inside { 1.0 } else { 0.0 }))
    }
}

/// Where vertex `p` (object-local frame) must go so that it lies no deeper
/// than [`CONTACT_TOLERANCE_M`] inside the object of `tree`: `Some(target)`
/// when it is deeper, `None` when it is outside or shallower
/// ([`penetration`]). A vertex `d` deep moves by `d −` the tolerance, along
/// [`push_direction`]: the way to its closest surface point blended with
/// the ways to the faces about as near. No allocation.
#[must_use]
pub fn push_out(tree: &ObbTree, p: Vec3, open_depth: f32) -> Option<Vec3> {
    let mut hint = NO_HINT;
    push_out_hinted(tree, p, open_depth, &mut hint)
}

/// No triangle to try first ([`push_out_hinted`]).
pub const NO_HINT: u32 = u32::MAX;

/// [`push_out`], trying triangle `hint` first: when `p` lies within
/// [`CONTACT_TOLERANCE_M`] of it, `p` is no deeper than that whichever side
/// it is on, and the answer (`None`) needs no walk of the tree. Otherwise
/// the answer of [`push_out`], and `hint` becomes the triangle of the
/// closest point measured (kept when none was). The same answers bit for
/// bit: the closest point is never farther than the hint's. For a vertex
/// asked about again (the contact response's later rounds), most of which
/// rest against the surface at the tolerance.
#[must_use]
pub fn push_out_hinted(tree: &ObbTree, p: Vec3, open_depth: f32, hint: &mut u32) -> Option<Vec3> {
    let mut bound_sq = f32::INFINITY;
    if let Some(tri) = tree.triangles.get(*hint as usize) {
        let (q, _) = closest_point_on_triangle_region(p, tri);
        let d = q.distance_squared(p);
        if d.sqrt() <= CONTACT_TOLERANCE_M {
            return None;
        }
        // The walk need not look farther than the hint and the blend past
        // it (same answer).
        bound_sq = (d.sqrt() + PUSH_BLEND_M) * (d.sqrt() + PUSH_BLEND_M);
    }
    let mut near = NearPoints::default();
    let (s, inside) = surface_and_side(tree, p, open_depth, bound_sq, Some(&mut near))?;
    *hint = s.triangle;
    let depth = s.distance_sq.sqrt();
    // An open mesh's depth is the distance times how much p is inside.
    let deep = depth * inside;
    if deep.is_nan() || deep <= CONTACT_TOLERANCE_M {
        return None;
    }
    let way = push_direction(&near, p, depth).unwrap_or((s.point - p) / depth);
    Some(p + way * (deep - CONTACT_TOLERANCE_M))
}

/// The unit way out of vertex `p` (object-local frame), `depth` metres from
/// its closest surface point: the mean of the unit ways to the triangles'
/// closest points in `near` ([`closest_point_and_near`]), each weighted by
/// `1 − (its distance − depth) /` [`PUSH_BLEND_M`] (the closest point's at
/// 1, those [`PUSH_BLEND_M`] farther or more at 0), summed in triangle
/// order (the same bits whatever bound the walk started from). Continuous
/// in `p` where the sum does not vanish (it would only deep inside,
/// between faces across the object); `None` there, or for `depth` not
/// positive.
#[must_use]
pub fn push_direction(near: &NearPoints, p: Vec3, depth: f32) -> Option<Vec3> {
    if depth.is_nan() || depth <= 0.0 {
        return None;
    }
    let mut sum = Vec3::ZERO;
    for (q, d_sq) in near.in_triangle_order() {
        let d = d_sq.sqrt();
        let w = (1.0 - (d - depth) / PUSH_BLEND_M).min(1.0);
        if w > 0.0 && d > 0.0 {
            sum += (q - p) * (w / d);
        }
    }
    sum.try_normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::closest_point::closest_point_on_mesh;
    use crate::collision::exact::point_inside;
    use crate::object::TriMesh;
    use crate::object::shapes::{cuboid, knot, sphere};
    use crate::test_rng::XorShift;

    #[test]
    fn pushed_points_end_on_the_surface_and_outside_points_stay() {
        let mut rng = XorShift(0x5851_f42d_4c95_7f2du64);
        let mut next = || rng.range(-1.0, 1.0);
        for mesh in [sphere(1.0, 3), knot(2.4), cuboid(Vec3::new(0.6, 0.3, 0.9))] {
            let tree = ObbTree::build(&mesh, 32);
            let (mut pushed, mut kept) = (0, 0);
            for _ in 0..2000 {
                let p = Vec3::new(next(), next(), next()) * 1.3;
                let inside = point_inside(&tree, p);
                match push_out(&tree, p, 0.1) {
                    Some(q) => {
                        assert!(inside, "{p} pushed but outside");
                        let s = closest_point_on_mesh(&tree, q, f32::INFINITY).unwrap();
                        // The way out blends the faces about as near as
                        // the closest (`PUSH_BLEND_M`): a vertex d deep
                        // that moves d − tolerance a little askew ends a
                        // little off the tolerance (≤ 1 % of d within
                        // 5 cm of the surface, where grass reaches; deeper,
                        // faces across a thin part blend, and the vertex
                        // comes a good way out).
                        let d = closest_point_on_mesh(&tree, p, f32::INFINITY)
                            .unwrap()
                            .distance_sq
                            .sqrt();
                        let now = s.distance_sq.sqrt();
                        let off = (now - CONTACT_TOLERANCE_M).abs();
                        assert!(
                            off < 1e-4 + 0.01 * d || (d > 0.05 && now < 0.1 * d),
                            "{p} ({d} deep) -> {q}: {now} from the surface"
                        );
                        pushed += 1;
                    }
                    None => {
                        if inside {
                            let s = closest_point_on_mesh(&tree, p, f32::INFINITY).unwrap();
                            assert!(s.distance_sq.sqrt() <= CONTACT_TOLERANCE_M + 1e-6, "{p}");
                        }
                        kept += 1;
                    }
                }
            }
            assert!(pushed > 50 && kept > 50, "{pushed} {kept}");
        }
    }

    /// A hint changes no answer: random points near the surface of closed
    /// and open meshes, each asked with no hint, with the triangle of its
    /// closest point, with a random triangle and again with the hint the
    /// first answer left, all give `push_out`'s answer bit for bit; the
    /// hint left is the closest point's triangle.
    #[test]
    fn a_hint_gives_the_answers_of_push_out() {
        let mut rng = XorShift(0x2545_f491_4f6c_dd1du64);
        let mut next = || rng.unit();
        let mut sheet = cuboid(Vec3::ONE);
        sheet
            .indices
            .retain(|t| t.iter().all(|&i| sheet.positions[i as usize].y > 0.5));
        let (mut hinted_none, mut walked) = (0, 0);
        for mesh in [sphere(1.0, 3), knot(2.4), sheet] {
            let tree = ObbTree::build(&mesh, 32);
            for _ in 0..3000 {
                let t = &tree.triangles[(next() * tree.triangles.len() as f32) as usize];
                // Around a surface point, up to 2 cm off: many within the
                // 3 mm tolerance, inside and outside.
                let on = t[0] * 0.3 + t[1] * 0.3 + t[2] * 0.4;
                let p = on + (Vec3::new(next(), next(), next()) - 0.5) * 0.04;
                let want = push_out(&tree, p, 0.1);
                let mut hint = NO_HINT;
                assert_eq!(push_out_hinted(&tree, p, 0.1, &mut hint), want, "{p}");
                let left = hint;
                // Where a closest point was measured (not in a voxel known
                // outside), the hint is its triangle.
                if left != NO_HINT {
                    let reach = if tree.closed { f32::INFINITY } else { 0.1 };
                    let c = closest_point_on_mesh(&tree, p, reach).map(|c| c.triangle);
                    assert_eq!(Some(left), c, "{p}");
                    walked += 1;
                }
                let random = (next() * tree.triangles.len() as f32) as u32;
                for mut h in [left, random, left] {
                    let before = h;
                    assert_eq!(push_out_hinted(&tree, p, 0.1, &mut h), want, "{p} hint {h}");
                    hinted_none += usize::from(h == before && want.is_none());
                }
            }
        }
        assert!(
            hinted_none > 1000 && walked > 3000,
            "{hinted_none} {walked}"
        );
    }

    /// A vertex 1 cm inside a tessellated ball, moved in steps of 1e-6 m
    /// across the plane halfway between two faces that share an edge, at
    /// eight edges: its target moves by at most a few times its step.
    /// With the closest point alone it jumped at the plane (`PUSH_BLEND_M`;
    /// this test failed then: 0.7 mm in one step, 702 times the step).
    #[test]
    fn the_push_turns_smoothly_between_two_faces() {
        let tree = ObbTree::build(&sphere(0.6, 3), 32);
        for e in crate::collision::test_edges::edges(&tree, 37, 8) {
            let start = e.mid + e.inward * 0.01;
            let step = 1e-6;
            let (mut worst, mut last) = (0.0f32, None::<Vec3>);
            for k in -200..=200 {
                let p = start + e.across * (k as f32 * step);
                let q = push_out(&tree, p, 0.1).expect("1 cm inside");
                if let Some(prev) = last {
                    worst = worst.max(q.distance(prev) / step);
                }
                last = Some(q);
            }
            assert!(
                worst < 5.0,
                "edge of triangle {}: the target moved {worst} times the step",
                e.triangle
            );
        }
    }

    /// A lone open sheet. By the sheet rule, what lies behind it within the
    /// open depth goes back to it, what lies in front or deeper stays. By
    /// the winding rule a flat sheet has no inside: its root box is flat,
    /// and the inside fades to 0 at the box's faces (`winding::root_fade`).
    #[test]
    fn open_sheet_pushes_what_lies_just_behind_it_by_the_sheet_rule() {
        let mut mesh = cuboid(Vec3::ONE);
        // Keep the top face only (+y): an open sheet facing up.
        mesh.indices
            .retain(|t| t.iter().all(|&i| mesh.positions[i as usize].y > 0.5));
        let mut tree = ObbTree::build(&mesh, 8);
        assert!(!tree.closed);
        let q = push_out(&tree, Vec3::new(0.2, 0.95, 0.1), 0.2).unwrap();
        assert!((q.y - (1.0 - CONTACT_TOLERANCE_M)).abs() < 1e-5, "{q}");
        assert!(push_out(&tree, Vec3::new(0.2, 1.05, 0.1), 0.2).is_none());
        assert!(push_out(&tree, Vec3::new(0.2, 0.5, 0.1), 0.2).is_none());
        tree.enable_winding();
        assert!(push_out(&tree, Vec3::new(0.2, 0.95, 0.1), 0.2).is_none());
    }

    /// A bowl (a sphere with its cap above y = 0.3 left out) by the winding
    /// rule: a point deep in it goes out towards the bowl, nearly all the
    /// way in one push (the factor is 1 there) and the rest in the next;
    /// a point well above the hole, or outside, stays.
    #[test]
    fn a_bowls_hollow_is_inside_by_the_winding_rule() {
        let mesh = crate::collision::winding::test_support::bowl_mesh(0.3);
        let mut tree = ObbTree::build(&mesh, 10);
        assert!(penetration(&tree, Vec3::new(0.0, -0.5, 0.0), 0.1).is_none());
        tree.enable_winding();
        let mut p = Vec3::new(0.1, -0.5, 0.0);
        let (_, depth) = penetration(&tree, p, 0.0).expect("in the bowl");
        assert!(depth > 0.4, "{depth}");
        for _ in 0..30 {
            let Some(q) = push_out(&tree, p, 0.0) else {
                break;
            };
            p = q;
        }
        assert!(
            (p.length() - (1.0 - CONTACT_TOLERANCE_M)).abs() < 0.01,
            "{p}"
        );
        assert!(push_out(&tree, Vec3::new(0.0, 0.9, 0.0), 0.0).is_none());
        assert!(push_out(&tree, Vec3::new(1.5, -0.5, 0.0), 0.0).is_none());
    }

    /// The beetle (an open mesh: no floor, open seams): a point in the
    /// middle of its body, farther than a blade segment from every sheet,
    /// is inside by the winding rule and goes out. By the sheet rule
    /// ("behind the closest sheet, within a segment of it") it is outside,
    /// and grass stands in the car.
    #[test]
    fn the_hollow_of_an_open_car_body_is_inside() {
        let dir = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../scenes/meshes/beetle.obj"
        );
        let Ok(mesh) = crate::object::obj::load_obj(std::path::Path::new(dir)) else {
            panic!("{dir} not readable");
        };
        let mut tree = ObbTree::build(&mesh, 12);
        assert!(!tree.closed);
        let (lo, hi) = mesh.bounds().unwrap();
        let middle = (lo + hi) * 0.5;
        assert!(penetration(&tree, middle, 0.05 * (hi - lo).max_element()).is_none());
        tree.enable_winding();
        let (_, depth) = penetration(&tree, middle, f32::INFINITY).expect("inside the car");
        assert!(depth > 0.05 * (hi - lo).min_element(), "{depth}");
        assert!(push_out(&tree, middle, f32::INFINITY).is_some());
        // Well outside: nothing.
        assert!(penetration(&tree, hi + (hi - lo), f32::INFINITY).is_none());
    }

    /// A tent: two sheets meeting at a sharp ridge along x (40° apart at
    /// the top, so the faces' normals point more than 90° apart), in the
    /// mesh order given.
    fn tent(flip_order: bool) -> ObbTree {
        let (s, c) = (20f32.to_radians().sin(), 20f32.to_radians().cos());
        let positions = vec![
            Vec3::new(-1.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0 - c, s),
            Vec3::new(1.0, 1.0 - c, s),
            Vec3::new(-1.0, 1.0 - c, -s),
            Vec3::new(1.0, 1.0 - c, -s),
        ];
        // Counter-clockwise seen from outside: +z side, then -z side.
        let mut indices = vec![[0, 2, 3], [0, 3, 1], [1, 5, 4], [1, 4, 0]];
        if flip_order {
            indices.reverse();
        }
        ObbTree::build(&TriMesh { positions, indices }, 8)
    }

    /// Points just outside and just inside a sharp fold of an open mesh,
    /// whose closest surface point is on the ridge: outside and inside
    /// whichever of the two faces the walk finds first (the angle-weighted
    /// pseudo-normal, `obb::pseudo_normals`). With one face's normal, the
    /// point outside is "behind" the other face, and the answer turned on
    /// the mesh order (this test failed for one of the two orders).
    #[test]
    fn an_open_fold_has_one_outside_whatever_face_is_found_first() {
        let (s, c) = (20f32.to_radians().sin(), 20f32.to_radians().cos());
        let (n_pos, n_neg) = (Vec3::new(0.0, s, c), Vec3::new(0.0, s, -c));
        assert!(n_pos.dot(n_neg) < 0.0);
        let ridge = Vec3::new(0.3, 1.0, 0.0);
        for flip in [false, true] {
            let tree = tent(flip);
            assert!(!tree.closed);
            for (a, b) in [(n_pos, n_neg), (n_neg, n_pos)] {
                // In the ridge's region (a sum of both normals, mostly a):
                // outside, though behind b's plane.
                let out = ridge + (a + b * 0.1) * 0.02;
                assert!((out - ridge).dot(b) < 0.0);
                assert!(
                    penetration(&tree, out, 0.2).is_none(),
                    "order flipped {flip}: {out} counted inside"
                );
                // Below the ridge, behind both faces: inside (nearest to
                // a face, nearer than the ridge).
                let inside = ridge - (a + b) * 0.02;
                let (_, depth) = penetration(&tree, inside, 0.2).expect("inside the tent");
                assert!(depth > 0.0 && depth < inside.distance(ridge), "{depth}");
            }
        }
    }
}
