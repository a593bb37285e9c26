//! Segment vs a node's volume: its box and its tilted boxes
//! ([`crate::obb::slabs`], ours, issue 16 item 5).
//!
//! The segment is moved into the node box's frame once (as the box test of
//! [`super::segment_obb`] does); each tilted box turns two of its
//! coordinates ([`turned`]'s rotation) and is
//! then an axis-aligned box there, tested with the same separating-axis
//! test. A segment meets a node when it meets its box and each tilted box,
//! each on its own (what the prototype measured: BENCHMARKS.md, "Session
//! 17"). The GPU twin is `hits_node` (with `hits_tilted`) in
//! `object.wgsl`, in the same order.
//!
//! Used by the yes/no walk of the narrow phase (`collide_segment`, the
//! paper's hit at a precision). The simulation's weighted contact walk
//! (`contact_segment`) still decides with the boxes alone: its weights
//! must stay continuous and a state a few ulp away must stay a few ulp
//! away, and the tilted boxes in its depths broke that on the default
//! scene (BENCHMARKS.md, "Session 18").

use glam::{Vec3, Vec3A};

use super::segment_obb::{hits_centred_local, to_box_frame};
use crate::obb::Obb;
use crate::obb::slabs::{EXTRA_BOXES, NodeSlabs, turned};

/// Segment `c ± h` (node box frame) in the frame of tilted box `j` of `s`
/// ([`turned`]'s coordinates, less the box's centre), and that box's half
/// extents (the node box's are `e`).
#[inline]
fn in_tilted(c: Vec3A, h: Vec3A, e: Vec3A, s: &NodeSlabs, j: usize) -> [Vec3A; 3] {
    let thin = s.thin as usize;
    let (ca, cb, r) = turned(c.to_array(), thin, j);
    let (ha, hb, _) = turned(h.to_array(), thin, j);
    let [mid_a, half_a, mid_b, half_b] = s.faces[j];
    [
        Vec3A::new(ca - mid_a, cb - mid_b, c[r]),
        Vec3A::new(ha, hb, h[r]),
        Vec3A::new(half_a, half_b, e[r]),
    ]
}

/// True when segment `c ± h` (node box frame) meets every tilted box of
/// `s`; touching counts; NaN gives `false`.
#[inline]
fn hits_tilted_local(c: Vec3A, h: Vec3A, e: Vec3A, s: &NodeSlabs) -> bool {
    (0..EXTRA_BOXES).all(|j| {
        let [c, h, e] = in_tilted(c, h, e, s, j);
        hits_centred_local(c, h, e)
    })
}

/// True when segment `centre ± half` (parent frame, as
/// `segment_obb::centred` gives it) meets the node's box `obb` and
/// each of its tilted boxes `slabs` (`None`: the box alone); touching
/// counts; non-finite ends give `false`. Each box is tested on its own, so
/// a segment that meets them all but not their intersection also counts
/// (conservative: no hit of a triangle is lost). The box is tested first:
/// most segments a walk tests miss it.
#[must_use]
#[inline]
pub fn segment_hits_node(centre: Vec3A, half: Vec3A, obb: &Obb, slabs: Option<&NodeSlabs>) -> bool {
    let (c, h) = to_box_frame(centre, half, obb);
    let e = Vec3A::from(obb.half);
    hits_centred_local(c, h, e) && slabs.is_none_or(|s| hits_tilted_local(c, h, e, s))
}

/// [`segment_hits_node`] for segment `p0–p1`.
#[must_use]
pub fn segment_hits_node_ends(p0: Vec3, p1: Vec3, obb: &Obb, slabs: Option<&NodeSlabs>) -> bool {
    let (centre, half) = super::segment_obb::centred(p0, p1);
    segment_hits_node(centre, half, obb, slabs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::obb::ObbTree;
    use crate::test_rng::XorShift;

    /// A segment with both ends drawn in the box `o` scaled by `spread`
    /// about its centre (in units of its half diagonal).
    fn segment_near(rng: &mut XorShift, o: &Obb, spread: f32) -> (Vec3, Vec3) {
        let size = o.half.length();
        let mut pick = || {
            let mut r = || rng.range(-spread, spread);
            o.center + Vec3::new(r(), r(), r()) * size
        };
        (pick(), pick())
    }

    /// How deep box-frame point `x` lies in the node's box (entry 0) and in
    /// each tilted box (entries 1..), each grown by `shell` (the reference,
    /// by the definition).
    fn point_depths(x: Vec3, obb: &Obb, s: &NodeSlabs, shell: f32) -> [f32; EXTRA_BOXES + 1] {
        let q = obb.to_box(x);
        let mut d = [(obb.half + shell - q.abs()).min_element(); EXTRA_BOXES + 1];
        for j in 0..EXTRA_BOXES {
            let (a, b, r) = turned(q.to_array(), s.thin as usize, j);
            let [ma, ha, mb, hb] = s.faces[j];
            d[j + 1] = (ha + shell - (a - ma).abs())
                .min(hb + shell - (b - mb).abs())
                .min(obb.half[r] + shell - q[r].abs());
        }
        d
    }

    fn sphere_tree() -> ObbTree {
        ObbTree::build(&crate::object::shapes::sphere(1.0, 3), 8)
    }

    /// The hit test says whether the segment reaches into the box and into
    /// every tilted box: it agrees with a dense sampling of the segment
    /// against the boxes' definitions, away from ties, for segments near
    /// the nodes of a sphere's tree.
    #[test]
    fn hits_agree_with_sampling_the_boxes() {
        let tree = sphere_tree();
        let mut rng = XorShift(0x1234_5678_9abc_def1);
        let (mut hits, mut misses) = (0, 0);
        for (i, node) in tree.nodes.iter().enumerate().filter(|(_, n)| n.depth >= 5) {
            let s = &tree.slabs[i];
            let o = &node.obb;
            let size = o.half.length();
            for _ in 0..6 {
                let (p0, p1) = segment_near(&mut rng, o, 1.5);
                let steps = 2000;
                // The least over the boxes of the segment's deepest reach
                // into each: positive when it meets every box.
                let reach = (0..=steps)
                    .map(|k| point_depths(p0.lerp(p1, k as f32 / steps as f32), o, s, 0.0))
                    .fold([f32::NEG_INFINITY; EXTRA_BOXES + 1], |a, d| {
                        std::array::from_fn(|j| a[j].max(d[j]))
                    })
                    .into_iter()
                    .fold(f32::INFINITY, f32::min);
                let slope = (p1 - p0).length() / steps as f32;
                if reach.abs() > slope + 1e-5 * size.max(1.0) {
                    let hit = segment_hits_node_ends(p0, p1, o, Some(s));
                    assert_eq!(hit, reach > 0.0, "node {i}: {p0} {p1} reach {reach}");
                    if hit {
                        hits += 1;
                    } else {
                        misses += 1;
                    }
                }
            }
        }
        assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
    }

    /// Some segments meet a node's box and miss its volume: the tilted
    /// boxes cut (the point of them); none of them crosses a triangle.
    #[test]
    fn the_tilted_boxes_turn_away_box_hits_that_cross_no_triangle() {
        let tree = sphere_tree();
        let mut rng = XorShift(0x0bad_cafe_f00d_d00d);
        let mut cut = 0;
        for (i, node) in tree.nodes.iter().enumerate().filter(|(_, n)| n.depth == 7) {
            let o = &node.obb;
            for _ in 0..20 {
                let (p0, p1) = segment_near(&mut rng, o, 1.2);
                let in_box = segment_hits_node_ends(p0, p1, o, None);
                let in_volume = segment_hits_node_ends(p0, p1, o, Some(&tree.slabs[i]));
                assert!(in_box || !in_volume, "the volume is inside the box");
                if in_box && !in_volume {
                    cut += 1;
                    let first = node.first_tri as usize;
                    for t in &tree.triangles[first..first + node.tri_count as usize] {
                        assert!(
                            !crate::collision::segment_triangle::segment_hits_triangle(p0, p1, t),
                            "node {i}: a segment through a triangle was turned away"
                        );
                    }
                }
            }
        }
        assert!(cut > 50, "only {cut} box hits turned away");
    }

    /// Non-finite ends miss.
    #[test]
    fn non_finite_ends_miss() {
        let tree = sphere_tree();
        let (o, s) = (&tree.nodes[3].obb, &tree.slabs[3]);
        for bad in [Vec3::NAN, Vec3::INFINITY, Vec3::new(0.0, f32::NAN, 0.0)] {
            assert!(!segment_hits_node_ends(bad, o.center, o, Some(s)));
            assert!(!segment_hits_node_ends(o.center, bad, o, Some(s)));
        }
    }
}
