//! Tilted boxes beside each node's box (ours, issue 16 item 5): a tighter
//! volume over a curved patch at the cost of a few more face tests.
//!
//! A deep node of a curved mesh (a sphere's cap, a knot's tube) holds a
//! patch that bulges: its box's thin axis is about the patch's normal, and
//! the box is as thick as the bulge, so its corners are mostly empty. Beside
//! the box, each node keeps [`EXTRA_BOXES`] boxes around the same triangles
//! along the box's axes turned: the thin axis tilted by ±[`TILT_DEG`]
//! towards each of the two longer axes (four boxes: a roof over the patch
//! that cuts the box's edges off), and the two longer axes turned 45° about
//! the thin one (one box: an octagon seen along the normal). A node's
//! volume is the intersection of its box and these; each holds the node's
//! triangles, so the intersection does too and no exact hit is missed.
//!
//! Each extra box shares one axis with the node's box (the axis it turns
//! about) and takes the box's extent along it; along its two turned axes it
//! keeps the exact extents of the triangles' corners, measured in the node
//! box's frame ([`crate::obb::Obb::to_box`]) and turned there, plus the
//! box's own padding ([`super::fit::padding`]). So a node stores only two
//! intervals per extra box ([`NodeSlabs`]), and the tests
//! (`collision::segment_slabs`) turn the segment the box test has already
//! moved into the box's frame.
//!
//! Measured (BENCHMARKS.md, "Session 18"): false positives at precision 7
//! fall from 7.0 % to about 2 % on the default sphere and from 20.3 % to
//! about 10 % on the knot.

use glam::Vec3;

use super::Obb;
use super::fit::padding;

/// How far the thin axis is tilted towards each longer axis, degrees
/// (measured against ±10° and ±20°: BENCHMARKS.md, "Session 17").
pub const TILT_DEG: f32 = 15.0;

/// sin 15°, the tilt's sine (the same literal in `segment_obb.wgsl`).
pub const TILT_SIN: f32 = 0.258_819_04;
/// cos 15°.
pub const TILT_COS: f32 = 0.965_925_8;
/// sin 45° = cos 45°: the octagon's turn.
pub const TURN_45: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// Extra boxes per node.
pub const EXTRA_BOXES: usize = 5;

/// Extra box `j`'s turn, relative to the node's thin axis `k`: it turns box
/// axes `(k + p) % 3` and `(k + q) % 3` (p, q) by the angle of sine `s`
/// and cosine `c`: in the box frame, a point `x` has turned coordinates
/// `a = c x_p + s x_q`, `b = c x_q − s x_p`; the third axis is kept.
pub const TURNS: [(usize, usize, f32, f32); EXTRA_BOXES] = [
    (0, 1, TILT_SIN, TILT_COS),
    (0, 1, -TILT_SIN, TILT_COS),
    (0, 2, TILT_SIN, TILT_COS),
    (0, 2, -TILT_SIN, TILT_COS),
    (1, 2, TURN_45, TURN_45),
];

/// A node's extra boxes, in its box's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeSlabs {
    /// The box axis the extra boxes turn from ([`TURNS`]): the thinnest
    /// (the first of equal ones), 0, 1 or 2.
    pub thin: u32,
    /// Per extra box: the centre and half extent of its first turned
    /// coordinate `a`, then of its second `b` (see [`TURNS`]), metres,
    /// relative to the box's centre; half extents padded.
    pub faces: [[f32; 4]; EXTRA_BOXES],
}

/// The box axis the extra boxes of a box with half extents `half` turn
/// from: the thinnest, the first of equal ones.
#[must_use]
pub fn thin_axis(half: Vec3) -> usize {
    if half.x <= half.y && half.x <= half.z {
        0
    } else if half.y <= half.z {
        1
    } else {
        2
    }
}

/// Extra box `j`'s turn ([`TURNS`]) for a node whose thin axis is `thin`:
/// the box axes it turns `p`, `q`, the one it keeps `r`, and the sine and
/// cosine of the turn. `thin` and `j` are taken modulo 3 and
/// [`EXTRA_BOXES`].
#[must_use]
#[inline]
pub fn turn(thin: usize, j: usize) -> (usize, usize, usize, f32, f32) {
    let (p, q, s, c) = TURNS[j % EXTRA_BOXES];
    let thin = thin % 3;
    let (p, q) = ((thin + p) % 3, (thin + q) % 3);
    (p, q, 3 - p - q, s, c)
}

/// The turned coordinates `(a, b)` of box-frame point `x` for extra box `j`
/// of a node whose thin axis is `thin`, and the index of the kept axis.
#[must_use]
#[inline]
pub fn turned(x: [f32; 3], thin: usize, j: usize) -> (f32, f32, usize) {
    let (p, q, r, s, c) = turn(thin, j);
    (c * x[p] + s * x[q], c * x[q] - s * x[p], r)
}

impl NodeSlabs {
    /// The extra boxes of the node whose box is `obb` around the corners
    /// `points` (its triangles' corners, or their distinct positions). With
    /// no point, boxes that hold all of `obb`.
    #[must_use]
    pub fn fit(obb: &Obb, points: impl Iterator<Item = Vec3>) -> Self {
        let thin = thin_axis(obb.half);
        let mut lo = [[f32::INFINITY; 2]; EXTRA_BOXES];
        let mut hi = [[f32::NEG_INFINITY; 2]; EXTRA_BOXES];
        for p in points {
            let x = obb.to_box(p).to_array();
            for j in 0..EXTRA_BOXES {
                let (a, b, _) = turned(x, thin, j);
                lo[j] = [lo[j][0].min(a), lo[j][1].min(b)];
                hi[j] = [hi[j][0].max(a), hi[j][1].max(b)];
            }
        }
        let pad = padding(obb.half.max_element(), obb.center);
        let whole = obb.half.length() + pad;
        let mut faces = [[0.0, whole, 0.0, whole]; EXTRA_BOXES];
        for (j, face) in faces.iter_mut().enumerate() {
            if lo[j][0] <= hi[j][0] && lo[j][1] <= hi[j][1] {
                let mid = |k: usize| (lo[j][k] + hi[j][k]) * 0.5;
                let half = |k: usize| (hi[j][k] - lo[j][k]) * 0.5 + pad;
                *face = [mid(0), half(0), mid(1), half(1)];
            }
        }
        Self {
            thin: thin as u32,
            faces,
        }
    }

    /// Extra box `j` of the node whose box is `obb`, as a box of its own
    /// (object frame, right-handed axes: the two turned ones, then the kept
    /// one): for drawing, and for peers that test boxes (the parry3d
    /// benchmarks).
    #[must_use]
    pub fn tilted_obb(&self, obb: &Obb, j: usize) -> Obb {
        let (p, q, r, s, c) = turn(self.thin as usize, j);
        let a = obb.axes[p] * c + obb.axes[q] * s;
        let b = obb.axes[q] * c - obb.axes[p] * s;
        // a × b = axes[p] × axes[q]: axes[r] when q follows p, else −axes[r].
        let kept = if (q + 3 - p) % 3 == 1 {
            obb.axes[r]
        } else {
            -obb.axes[r]
        };
        let [ma, ha, mb, hb] = self.faces[j % EXTRA_BOXES];
        Obb {
            center: obb.center + a * ma + b * mb,
            axes: [a, b, kept],
            half: Vec3::new(ha, hb, obb.half[r]),
        }
    }

    /// True when box-frame point `x` lies in every extra box (their kept
    /// axes are the node box's, not checked here), with `slack` metres of
    /// tolerance: what [`super::ObbTree::validate`] checks the corners with.
    #[must_use]
    pub fn holds(&self, x: [f32; 3], slack: f32) -> bool {
        (0..EXTRA_BOXES).all(|j| {
            let (a, b, _) = turned(x, self.thin as usize, j);
            let [ma, ha, mb, hb] = self.faces[j];
            (a - ma).abs() <= ha + slack && (b - mb).abs() <= hb + slack
        })
    }
}

/// Every node's [`NodeSlabs`] around its triangles (same indices as
/// `nodes`). O(triangles × depth).
#[must_use]
pub fn fit_slabs(nodes: &[super::ObbNode], triangles: &[[Vec3; 3]]) -> Vec<NodeSlabs> {
    nodes
        .iter()
        .map(|n| {
            let first = n.first_tri as usize;
            let tris = triangles
                .get(first..first + n.tri_count as usize)
                .unwrap_or(&[]);
            NodeSlabs::fit(&n.obb, tris.iter().flatten().copied())
        })
        .collect()
}

impl super::ObbTree {
    /// Fits every node's tilted boxes ([`ObbTree::slabs`](super::ObbTree::slabs))
    /// around its triangles as they are now; none for a nested tree. What
    /// [`super::ObbTree::build`] does, for a tree whose tilted boxes were
    /// dropped (a refit keeps only those a tree has).
    pub fn fit_slabs(&mut self) {
        self.slabs = if self.nested {
            Vec::new()
        } else {
            fit_slabs(&self.nodes, &self.triangles)
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::obb::ObbTree;

    /// The constants are the angles they name.
    #[test]
    fn the_turns_are_the_angles_they_name() {
        let (s, c) = TILT_DEG.to_radians().sin_cos();
        assert!((s - TILT_SIN).abs() <= f32::EPSILON, "{s}");
        assert!((c - TILT_COS).abs() <= f32::EPSILON, "{c}");
        assert!((TURN_45 - 45f32.to_radians().sin()).abs() <= f32::EPSILON);
    }

    /// Every corner of every node's triangles lies in its extra boxes, and
    /// the extra boxes cut the box: over a sphere's deep nodes, the volume
    /// of their intersection is smaller than the box's (sampled).
    #[test]
    fn extra_boxes_hold_their_triangles_and_cut_the_box() {
        let mesh = crate::object::shapes::sphere(1.0, 3);
        let tree = ObbTree::build(&mesh, 8);
        assert_eq!(tree.slabs.len(), tree.nodes.len());
        let mut inside = 0usize;
        let mut total = 0usize;
        for (i, node) in tree.nodes.iter().enumerate() {
            let s = &tree.slabs[i];
            let first = node.first_tri as usize;
            for t in &tree.triangles[first..first + node.tri_count as usize] {
                for &c in t {
                    assert!(s.holds(node.obb.to_box(c).to_array(), 0.0), "node {i}");
                }
            }
            if node.depth == 7 {
                // A grid of points in the box: how many the extra boxes keep.
                let n = 9;
                for g in 0..n * n * n {
                    let f = |k: usize| -1.0 + 2.0 * (k as f32 + 0.5) / n as f32;
                    let x = [f(g % n), f(g / n % n), f(g / n / n)];
                    let x = [
                        x[0] * node.obb.half.x,
                        x[1] * node.obb.half.y,
                        x[2] * node.obb.half.z,
                    ];
                    total += 1;
                    inside += usize::from(s.holds(x, 0.0));
                }
            }
        }
        assert!(total > 0);
        let kept = inside as f64 / total as f64;
        assert!(
            kept < 0.9,
            "the extra boxes keep {kept} of the depth-7 boxes"
        );
    }

    /// The tilted boxes as boxes of their own: right-handed, and a point is
    /// in one exactly when [`NodeSlabs::holds`]'s test of that box says so
    /// (away from its faces).
    #[test]
    fn tilted_boxes_as_boxes_agree_with_the_intervals() {
        let tree = ObbTree::build(&crate::object::shapes::knot(2.0), 8);
        let mut rng = crate::test_rng::XorShift(0x5eed_0123_4567_89ab);
        for (i, node) in tree.nodes.iter().enumerate().step_by(7) {
            let s = &tree.slabs[i];
            for j in 0..EXTRA_BOXES {
                let t = s.tilted_obb(&node.obb, j);
                assert!(
                    (t.axes[0].cross(t.axes[1]) - t.axes[2]).length() < 1e-5,
                    "node {i} box {j}"
                );
                for _ in 0..20 {
                    let x = node.obb.center
                        + Vec3::new(
                            rng.range(-1.5, 1.5),
                            rng.range(-1.5, 1.5),
                            rng.range(-1.5, 1.5),
                        ) * node.obb.half.length();
                    let q = t.to_box(x);
                    let margin = (t.half - q.abs()).min_element();
                    if margin.abs() < 1e-4 {
                        continue;
                    }
                    let (a, b, r) = turned(node.obb.to_box(x).to_array(), s.thin as usize, j);
                    let [ma, ha, mb, hb] = s.faces[j];
                    let inside = (a - ma).abs() <= ha
                        && (b - mb).abs() <= hb
                        && node.obb.to_box(x)[r].abs() <= node.obb.half[r];
                    assert_eq!(margin > 0.0, inside, "node {i} box {j}");
                }
            }
        }
    }

    /// No point: boxes that hold the whole box.
    #[test]
    fn no_point_gives_boxes_around_the_whole_box() {
        let obb = Obb {
            center: Vec3::ONE,
            axes: [Vec3::X, Vec3::Y, Vec3::Z],
            half: Vec3::new(1.0, 2.0, 0.5),
        };
        let s = NodeSlabs::fit(&obb, std::iter::empty());
        assert_eq!(s.thin, 2);
        for x in [[1.0, 2.0, 0.5], [-1.0, -2.0, 0.5], [1.0, -2.0, -0.5]] {
            assert!(s.holds(x, 0.0));
        }
    }
}
