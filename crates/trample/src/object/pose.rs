//! A rigid pose with its velocities.

use glam::{EulerRot, Quat, Vec3};

/// Where an object is at one instant, and how fast it moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// World position of the object's local origin, metres.
    pub position: Vec3,
    /// World-from-local rotation.
    pub rotation: Quat,
    /// Linear velocity of the local origin, m/s.
    pub velocity: Vec3,
    /// Angular velocity, rad/s, world frame.
    pub angular_velocity: Vec3,
}

/// `q` made a unit quaternion, the rotation a host means by it: any finite,
/// non-zero quaternion, however small or large (scaled to its largest
/// component first, so that neither its length's square underflows nor
/// overflows); `None` for a zero or non-finite one, which names no rotation
/// (glam's `normalize` would make it NaN or zero, a pose that hits nothing
/// and draws nowhere).
#[must_use]
pub fn unit_rotation(q: Quat) -> Option<Quat> {
    // Ordinary sizes: glam's own, the same bits as before this check.
    let n = q.normalize();
    if n.is_finite() && n.length_squared() > 0.5 {
        return Some(n);
    }
    let v = glam::Vec4::from(q);
    let m = v.abs().max_element();
    if !(m.is_finite() && m > 0.0) {
        return None;
    }
    let u = (v / m).normalize();
    u.is_finite().then(|| Quat::from_vec4(u))
}

impl Pose {
    /// A pose at rest at `position`.
    #[must_use]
    pub fn at_rest(position: Vec3) -> Self {
        Self {
            position,
            rotation: Quat::IDENTITY,
            velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
        }
    }

    /// Local point → world point.
    #[must_use]
    pub fn to_world(&self, p: Vec3) -> Vec3 {
        self.position + self.rotation * p
    }

    /// World point → local point.
    #[must_use]
    pub fn to_local(&self, p: Vec3) -> Vec3 {
        self.rotation.inverse() * (p - self.position)
    }

    /// Velocity of the material point at world position `p`: `v + ω × (p − c)`.
    /// Its length is the contact point speed used in Eq. 2 (DESIGN §3).
    #[must_use]
    pub fn point_velocity(&self, p: Vec3) -> Vec3 {
        self.velocity + self.angular_velocity.cross(p - self.position)
    }

    /// The fastest any point of `obb` (a box in the local frame) moves by
    /// the pose's spin alone, m/s: the largest `|ω × R·c|` over the box's
    /// corners `c` (a convex function of the point, so its largest value
    /// over the box is at a corner). That is `|ω|` times the corner's
    /// distance from the rotation axis **through the local origin**, not
    /// through the box's centre: a box offset from the origin (a mesh
    /// anchored at its bottom and rolled, a part that pivots about one end)
    /// sweeps faster than its half diagonal says, and a box turning about
    /// an axis along its longest side slower. Not finite when `ω` or the
    /// box is not (NaN propagates).
    #[must_use]
    pub fn spin_speed(&self, obb: &crate::obb::Obb) -> f32 {
        obb.corners()
            .iter()
            .map(|&c| self.angular_velocity.cross(self.rotation * c).length())
            .fold(0.0, |most, s| if s.is_nan() || s > most { s } else { most })
    }
}

/// The rotation of scene-file Euler angles `[yaw, pitch, roll]` in degrees:
/// yaw about y, then pitch about the turned x, then roll about the turned z,
/// i.e. R = R_y(yaw) R_x(pitch) R_z(roll). Used by `rotation_deg` of objects
/// and of keyframes.
#[must_use]
pub fn rotation_from_euler_deg(degrees: [f32; 3]) -> Quat {
    let [yaw, pitch, roll] = degrees.map(f32::to_radians);
    Quat::from_euler(EulerRot::YXZ, yaw, pitch, roll)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::obb::Obb;
    use crate::test_rng::XorShift;

    /// A host's quaternion of any finite, non-zero size is the rotation it
    /// points at; a zero or non-finite one is none (glam's `normalize`
    /// gave NaN for zero and 1e-30, and zero for 1e30).
    #[test]
    fn unit_rotation_takes_any_non_zero_size_and_refuses_zero() {
        let turn = Quat::from_rotation_y(0.7);
        for scale in [1.0, 1e-30, 1e-40, 1e30, 3e38] {
            let q = Quat::from_vec4(glam::Vec4::from(turn) * scale);
            let u = unit_rotation(q).unwrap();
            assert!(u.abs_diff_eq(turn, 1e-6), "{scale}: {u}");
        }
        assert_eq!(unit_rotation(Quat::IDENTITY), Some(Quat::IDENTITY));
        for bad in [
            Quat::from_xyzw(0.0, 0.0, 0.0, 0.0),
            Quat::from_xyzw(f32::NAN, 0.0, 0.0, 1.0),
            Quat::from_xyzw(0.0, f32::INFINITY, 0.0, 1.0),
        ] {
            assert_eq!(unit_rotation(bad), None, "{bad}");
        }
    }

    /// No point of the box moves faster by the spin than `spin_speed`, and
    /// a corner moves that fast; for a box offset from the origin that is
    /// more than `|ω|` times its half diagonal (the bound before, which let
    /// a part pivoting about one end sweep past blades between sub-steps).
    #[test]
    fn spin_speed_bounds_every_point_of_the_box_and_is_met_at_a_corner() {
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
        let mut offset_faster = 0;
        for _ in 0..500 {
            let u = rng.vec(-1.0, 1.0).normalize();
            let v = u.any_orthonormal_vector();
            let obb = Obb {
                center: rng.vec(-2.0, 2.0),
                axes: [u, v, u.cross(v)],
                half: rng.vec(0.01, 1.0),
            };
            let pose = Pose {
                position: rng.vec(-5.0, 5.0),
                rotation: Quat::from_axis_angle(
                    rng.vec(-1.0, 1.0).normalize(),
                    rng.range(0.0, 6.0),
                ),
                velocity: rng.vec(-3.0, 3.0),
                angular_velocity: rng.vec(-10.0, 10.0),
            };
            let bound = pose.spin_speed(&obb);
            let spin = |local: Vec3| {
                let world = pose.to_world(local);
                (pose.point_velocity(world) - pose.velocity).length()
            };
            let mut most = 0.0f32;
            for _ in 0..200 {
                let f = rng.vec(-1.0, 1.0);
                let p = obb.center
                    + obb.axes[0] * (f.x * obb.half.x)
                    + obb.axes[1] * (f.y * obb.half.y)
                    + obb.axes[2] * (f.z * obb.half.z);
                most = most.max(spin(p));
            }
            let corners = obb.corners().map(spin);
            let at_corner = corners.iter().copied().fold(0.0, f32::max);
            assert!(most <= bound * (1.0 + 1e-5) + 1e-6, "{most} > {bound}");
            assert!((at_corner - bound).abs() <= 1e-4 * bound.max(1.0));
            let old = pose.angular_velocity.length() * obb.half_diagonal();
            offset_faster += usize::from(bound > old * 1.01);
        }
        // Boxes away from the origin spin faster than the old bound said.
        assert!(offset_faster > 100, "{offset_faster}");
        let nan = Pose {
            angular_velocity: Vec3::new(f32::NAN, 0.0, 0.0),
            ..Pose::at_rest(Vec3::ZERO)
        };
        assert!(
            nan.spin_speed(&Obb {
                center: Vec3::ZERO,
                axes: [Vec3::X, Vec3::Y, Vec3::Z],
                half: Vec3::ONE
            })
            .is_nan()
        );
    }
}
