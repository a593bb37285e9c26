//! View-frustum culling per patch (paper §3.1: patches are "the unit of view
//! frustum culling"). Culling decides what the renderer draws; the
//! simulation keeps running in culled patches so a track made out of view is
//! still there when the camera turns (ours).

use super::layout::{FieldLayout, Patch};
use super::strips::strip_ranges;
use glam::{Mat4, Vec3, Vec4};

/// The six planes of a view frustum, pointing inwards (`n·p + d ≥ 0` inside).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frustum {
    /// left, right, bottom, top, near, far as (n, d).
    pub planes: [Vec4; 6],
}

impl Frustum {
    /// Planes of a view-projection matrix with clip z in [0, 1] (wgpu/D3D
    /// convention; Gribb & Hartmann's extraction).
    #[must_use]
    pub fn from_view_proj(m: Mat4) -> Self {
        let (r0, r1, r2, r3) = (m.row(0), m.row(1), m.row(2), m.row(3));
        let planes = [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2].map(|p| {
            let len = p.truncate().length();
            if len > 0.0 { p / len } else { p }
        });
        Self { planes }
    }

    /// False only when the box is wholly outside one plane (conservative).
    #[must_use]
    pub fn intersects_aabb(&self, min: Vec3, max: Vec3) -> bool {
        self.planes.iter().all(|p| {
            let n = p.truncate();
            // The box corner farthest along the plane normal.
            let v = Vec3::select(n.cmpge(Vec3::ZERO), max, min);
            n.dot(v) + p.w >= 0.0
        })
    }
}

impl Frustum {
    /// Whether the ball of `radius` around `centre` lies wholly outside one
    /// of the planes (so nothing in it is visible). Conservative the other
    /// way: a ball outside the frustum only near a corner, between two
    /// planes, is not found outside.
    #[must_use]
    pub fn ball_outside(&self, centre: Vec3, radius: f32) -> bool {
        self.planes
            .iter()
            .any(|p| p.truncate().dot(centre) + p.w < -radius)
    }
}

/// Where a box lies against a frustum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Wholly outside one plane: nothing in it is visible.
    Outside,
    /// Wholly inside every plane: everything in it is visible.
    Inside,
    /// Neither: its parts must be tested.
    Straddles,
}

impl Frustum {
    /// Where the box `min..max` lies: [`Side::Outside`] exactly when
    /// [`Self::intersects_aabb`] is false; [`Side::Inside`] when even the
    /// corner least along each plane's normal is inside it. Both are decided
    /// with the same float expression as [`Self::intersects_aabb`], which is
    /// monotone in the corner's coordinates: a box inside this one gets the
    /// same answer from [`Self::intersects_aabb`] whenever this is not
    /// [`Side::Straddles`].
    #[must_use]
    pub fn side_of_aabb(&self, min: Vec3, max: Vec3) -> Side {
        let mut inside = true;
        for p in &self.planes {
            let n = p.truncate();
            let far = Vec3::select(n.cmpge(Vec3::ZERO), max, min);
            if n.dot(far) + p.w < 0.0 {
                return Side::Outside;
            }
            let near = Vec3::select(n.cmpge(Vec3::ZERO), min, max);
            inside &= n.dot(near) + p.w >= 0.0;
        }
        if inside {
            Side::Inside
        } else {
            Side::Straddles
        }
    }
}

/// Marks each patch of `layout` visible or not (`visible[p]`); returns how
/// many are visible. Strip by strip ([`super::strips`],
/// `layout.strip_aabbs`): a strip wholly inside or outside the frustum
/// settles its patches at once, so the cost follows the frustum's sides
/// (1,024 strip tests on a 128 × 128-patch field, plus 16 patch tests per
/// strip a side cuts). The same marks as [`cull_patches_each`] (tested).
pub fn cull_patches(layout: &FieldLayout, frustum: &Frustum, visible: &mut Vec<bool>) -> u32 {
    let patches = &layout.patch_list;
    visible.clear();
    visible.resize(patches.len(), false);
    let mut count = 0;
    for (range, &(lo, hi)) in strip_ranges(layout.patches).zip(&layout.strip_aabbs) {
        match frustum.side_of_aabb(lo, hi) {
            Side::Outside => {}
            Side::Inside => {
                count += range.len() as u32;
                visible[range].fill(true);
            }
            Side::Straddles => {
                for (v, p) in visible[range.clone()].iter_mut().zip(&patches[range]) {
                    *v = frustum.intersects_aabb(p.aabb_min, p.aabb_max);
                    count += u32::from(*v);
                }
            }
        }
    }
    count
}

/// Marks each patch visible or not, testing every patch; returns how many
/// are visible. The reference of [`cull_patches`].
pub fn cull_patches_each(patches: &[Patch], frustum: &Frustum, visible: &mut Vec<bool>) -> u32 {
    visible.clear();
    visible.extend(
        patches
            .iter()
            .map(|p| frustum.intersects_aabb(p.aabb_min, p.aabb_max)),
    );
    visible.iter().filter(|v| **v).count() as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::camera::rh::{proj::directx::perspective, view::look_at_mat4};

    #[test]
    fn boxes_in_front_are_visible_behind_are_not() {
        let view = look_at_mat4(
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, -10.0),
            Vec3::Y,
        );
        let proj = perspective(60f32.to_radians(), 1.5, 0.1, 100.0);
        let f = Frustum::from_view_proj(proj * view);
        assert!(f.intersects_aabb(Vec3::new(-1.0, 0.0, -11.0), Vec3::new(1.0, 1.0, -9.0)));
        assert!(
            !f.intersects_aabb(Vec3::new(-1.0, 0.0, 9.0), Vec3::new(1.0, 1.0, 11.0)),
            "behind"
        );
        assert!(
            !f.intersects_aabb(Vec3::new(-1.0, 0.0, -300.0), Vec3::new(1.0, 1.0, -200.0)),
            "beyond far"
        );
        assert!(
            !f.intersects_aabb(Vec3::new(50.0, 0.0, -11.0), Vec3::new(52.0, 1.0, -9.0)),
            "far right"
        );
        // A box around the eye is visible.
        assert!(f.intersects_aabb(
            Vec3::splat(-1.0) + Vec3::Y * 2.0,
            Vec3::splat(1.0) + Vec3::Y * 2.0
        ));
    }

    /// A ball found outside is outside: for random cameras and balls,
    /// every point sampled in a ball `ball_outside` reports is outside the
    /// frustum (the plane-side test of the clip-space cube, `intersects_aabb`
    /// on the point); balls inside or straddling are not reported, and
    /// both answers occur.
    #[test]
    fn a_ball_found_outside_has_no_point_inside() {
        let mut rng = crate::test_rng::XorShift(0x243f_6a88_85a3_08d3);
        let (mut outside, mut not) = (0, 0);
        for _ in 0..200 {
            let eye = rng.vec(-20.0, 20.0);
            let at = eye + rng.vec(-1.0, 1.0).normalize_or(Vec3::X) * 10.0;
            let view = look_at_mat4(eye, at, Vec3::Y);
            let proj = perspective(rng.range(0.3, 2.0), rng.range(0.5, 2.5), 0.1, 80.0);
            let f = Frustum::from_view_proj(proj * view);
            for _ in 0..50 {
                let centre = eye + rng.vec(-40.0, 40.0);
                let radius = rng.range(0.0, 6.0);
                let out = f.ball_outside(centre, radius);
                // A centre inside every plane: never reported.
                assert!(
                    !(out && f.intersects_aabb(centre, centre)),
                    "{centre} inside"
                );
                if !out {
                    not += 1;
                    continue;
                }
                outside += 1;
                for _ in 0..64 {
                    let p = centre + rng.vec(-1.0, 1.0).clamp_length_max(1.0) * radius;
                    assert!(
                        !f.intersects_aabb(p, p),
                        "{p} of the ball at {centre} (radius {radius}) is inside"
                    );
                }
            }
        }
        assert!(outside > 1000 && not > 1000, "{outside} outside, {not} not");
    }
}
