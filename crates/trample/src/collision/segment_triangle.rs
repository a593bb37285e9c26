//! Segment vs triangle: the exact test under the reference of DESIGN §4
//! ("an exact segment–triangle reference").
//!
//! T. Möller, B. Trumbore, *Fast, minimum storage ray/triangle intersection*,
//! JGT 2(1), 1997, restricted to the segment's parameter range, computed in
//! `f64` from the `f32` inputs so that rounding (~1e-16) is far below the
//! tolerance. A segment lying in the triangle's plane is decided by a 2D
//! overlap test in that plane.
//!
//! Two flavours:
//! - [`segment_hits_triangle`]: closed triangle and closed segment, widened
//!   by [`TOLERANCE`], so a segment through an edge shared by two triangles
//!   is counted (by both), and a segment that ends on the surface touches it;
//! - [`segment_crosses_triangle_interior`]: strict, for counting crossings of
//!   a ray (inside test of [`crate::collision::exact`]), where an edge hit
//!   must not be counted twice.

use glam::{DVec2, DVec3, Vec3};

/// Widening of the inclusive test, as a fraction of the triangle's
/// barycentric range and of the segment's parameter range: far above `f64`
/// rounding (~1e-16 relative) and far below the OBB padding (1e-5 of a
/// box's size, [`crate::obb::fit::padding`]), so every segment this test
/// reports also meets every box around the triangle.
pub const TOLERANCE: f64 = 1e-9;

/// `|det|` below this fraction of `|segment| × |normal|` (the sine of the
/// angle between segment and plane) means "parallel to the plane".
const PARALLEL: f64 = 1e-12;

/// True when the closed segment `p0–p1` meets the closed triangle `tri`,
/// boundary included with a relative [`TOLERANCE`]. A segment lying in the
/// triangle's plane counts when it overlaps the triangle; a zero-length
/// segment counts when the point lies on the triangle. Degenerate (zero
/// area) triangles and non-finite inputs give `false`. No allocation.
///
/// See also [`segment_crosses_triangle_interior`].
#[must_use]
#[inline]
pub fn segment_hits_triangle(p0: Vec3, p1: Vec3, tri: &[Vec3; 3]) -> bool {
    let Some(s) = Setup::new(p0, p1, tri) else {
        return false;
    };
    match s.crossing() {
        Some((u, v, t)) => {
            u >= -TOLERANCE
                && v >= -TOLERANCE
                && u + v <= 1.0 + TOLERANCE
                && (-TOLERANCE..=1.0 + TOLERANCE).contains(&t)
        }
        None => s.coplanar_overlap(),
    }
}

/// True when the segment `p0–p1` crosses the open triangle `tri` at a point
/// strictly inside both (no tolerance, `0 < t < 1`). Parallel segments,
/// degenerate triangles and non-finite inputs give `false`. Used to count
/// the crossings of a ray with a closed surface, where an edge or vertex hit
/// (which a slightly skewed ray makes a measure-zero event) must not be
/// counted by both triangles.
#[must_use]
#[inline]
pub fn segment_crosses_triangle_interior(p0: Vec3, p1: Vec3, tri: &[Vec3; 3]) -> bool {
    let Some(s) = Setup::new(p0, p1, tri) else {
        return false;
    };
    match s.crossing() {
        Some((u, v, t)) => u > 0.0 && v > 0.0 && u + v < 1.0 && t > 0.0 && t < 1.0,
        None => false,
    }
}

/// The quantities both tests share, in `f64`.
struct Setup {
    /// Segment start and direction `p1 − p0`.
    p: DVec3,
    d: DVec3,
    /// Triangle corner `a` and edges `b − a`, `c − a`.
    a: DVec3,
    e1: DVec3,
    e2: DVec3,
    /// Unnormalised normal `e1 × e2` and its length.
    n: DVec3,
    n_len: f64,
    /// Longest triangle edge.
    scale: f64,
}

impl Setup {
    /// `None` for non-finite inputs or a zero-area triangle.
    #[inline]
    fn new(p0: Vec3, p1: Vec3, tri: &[Vec3; 3]) -> Option<Self> {
        if !(p0.is_finite() && p1.is_finite() && tri.iter().all(|c| c.is_finite())) {
            return None;
        }
        let [a, b, c] = tri.map(Vec3::as_dvec3);
        let (e1, e2) = (b - a, c - a);
        let n = e1.cross(e2);
        let n_len = n.length();
        let scale = e1.length().max(e2.length()).max((c - b).length());
        // Zero area, to rounding: sin(angle) of the corner below 1e-12.
        if n_len.is_nan() || n_len <= PARALLEL * scale * scale {
            return None;
        }
        let p = p0.as_dvec3();
        Some(Self {
            p,
            d: p1.as_dvec3() - p,
            a,
            e1,
            e2,
            n,
            n_len,
            scale,
        })
    }

    /// Möller–Trumbore: barycentric `(u, v)` of the point where the
    /// segment's line meets the plane, and its parameter `t` on the segment
    /// (`p + t d`). `None` when the segment is parallel to the plane (or has
    /// zero length).
    #[inline]
    fn crossing(&self) -> Option<(f64, f64, f64)> {
        let pvec = self.d.cross(self.e2);
        let det = self.e1.dot(pvec);
        if det.is_nan() || det.abs() <= PARALLEL * self.d.length() * self.n_len {
            return None;
        }
        let inv = 1.0 / det;
        let s = self.p - self.a;
        let u = s.dot(pvec) * inv;
        let qvec = s.cross(self.e1);
        let v = self.d.dot(qvec) * inv;
        let t = self.e2.dot(qvec) * inv;
        Some((u, v, t))
    }

    /// For a segment parallel to the plane: both endpoints within
    /// tolerance of the plane and the segment overlapping the triangle in
    /// it (projected on the coordinate plane most orthogonal to the normal).
    fn coplanar_overlap(&self) -> bool {
        let q = self.p + self.d;
        let d_len = self.d.length();
        let tol = TOLERANCE * (self.scale + d_len);
        let dist = |x: DVec3| (x - self.a).dot(self.n) / self.n_len;
        if dist(self.p).abs() > tol || dist(q).abs() > tol {
            return false;
        }
        // Drop the coordinate along which the normal is largest.
        let an = self.n.abs();
        let drop = if an.x >= an.y && an.x >= an.z {
            0
        } else if an.y >= an.z {
            1
        } else {
            2
        };
        let flat = |x: DVec3| match drop {
            0 => DVec2::new(x.y, x.z),
            1 => DVec2::new(x.z, x.x),
            _ => DVec2::new(x.x, x.y),
        };
        let tri = [flat(self.a), flat(self.a + self.e1), flat(self.a + self.e2)];
        let (p2, q2) = (flat(self.p), flat(q));
        let eps = TOLERANCE * (self.scale + d_len) * (self.scale + d_len);
        point_in_triangle_2d(p2, &tri, eps)
            || point_in_triangle_2d(q2, &tri, eps)
            || tri.iter().any(|&c| point_on_segment_2d(c, p2, q2, eps))
            || (0..3).any(|k| segments_cross_2d(p2, q2, tri[k], tri[(k + 1) % 3], eps))
    }
}

/// Twice the signed area of (a, b, c): > 0 when counter-clockwise.
#[inline]
fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// `p` inside or on the 2D triangle `t` (either winding), within `eps` of
/// twice-area.
fn point_in_triangle_2d(p: DVec2, t: &[DVec2; 3], eps: f64) -> bool {
    let sign = orient(t[0], t[1], t[2]).signum();
    (0..3).all(|k| sign * orient(t[k], t[(k + 1) % 3], p) >= -eps)
}

/// `c` on the 2D segment `p–q` (within `eps` of twice-area, and between the
/// endpoints).
fn point_on_segment_2d(c: DVec2, p: DVec2, q: DVec2, eps: f64) -> bool {
    let d = q - p;
    let t = (c - p).dot(d);
    orient(p, q, c).abs() <= eps && t >= -eps && t <= d.length_squared() + eps
}

/// The 2D segments `p–q` and `a–b` properly straddle each other (each one's
/// endpoints on both sides of the other's line, within `eps`). Collinear
/// overlaps are left to the endpoint tests of the caller.
fn segments_cross_2d(p: DVec2, q: DVec2, a: DVec2, b: DVec2, eps: f64) -> bool {
    let (o1, o2) = (orient(p, q, a), orient(p, q, b));
    let (o3, o4) = (orient(a, b, p), orient(a, b, q));
    if o1.abs() <= eps && o2.abs() <= eps {
        return false;
    }
    let straddles = |x: f64, y: f64| (x <= eps && y >= -eps) || (x >= -eps && y <= eps);
    straddles(o1, o2) && straddles(o3, o4)
}
