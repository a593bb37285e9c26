//! Driven bodies (ours): a body whose pose the caller sets step by step —
//! the viewer's arrow-key driving — instead of a path.
//!
//! A path's pose is a pure function of time ([`crate::object::Motion::pose_at`]);
//! a driven body instead goes, over the next step, from where it is to a
//! pose the caller chooses. Its sub-step poses are interpolated between the
//! two (position linearly, rotation by slerp) and its velocities are the
//! displacement and turn over the step, so the force of Eq. 2 matches what
//! the body really sweeps through and sub-stepping (DESIGN §9) sees its
//! true travel. Bodies that are never driven behave exactly as before.
//!
//! A host moving its own objects (issue 14) says for each frame which of
//! two things happened: the body *moved* there ([`Simulation::move_body`]:
//! it sweeps the grass between the two poses, as above) or it *jumped*
//! there ([`Simulation::teleport_body`]: a respawn, a cut, a level load).
//! A teleport does not sweep: the body is at the new pose at once, at
//! rest; no sub-step lies between the two places and the jump is no
//! velocity, so Eq. 2 gets no force from it. The grass it lands in is
//! held as under any body standing still (the contact response turns
//! segments out of it); nothing between the two places is touched.

use super::bodies::BodyError;
use super::body::BodyId;
use super::simulation::Simulation;
use crate::object::{Pose, unit_rotation};
use glam::{Quat, Vec3};

/// How far past the end of a drive, as a fraction of its step, a pose
/// still has the drive's velocity ([`Drive::pose_at`]), besides four ulps
/// of the end time: above the rounding of sub-step times, below the next
/// step's first sub-step (a step over at most 1024 sub-steps,
/// `sim.max_substeps`' limit).
pub const DRIVE_END_SLACK: f32 = 1e-4;

/// One step of a driven body: from `from` at time `t0` to `to` at `t1`
/// (seconds, `t1 > t0`). Set by [`Simulation::drive`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drive {
    /// Pose at the start of the step.
    pub from: Pose,
    /// Pose at its end (its velocities are ignored: see [`Drive::pose_at`]).
    pub to: Pose,
    /// Start time, seconds.
    pub t0: f32,
    /// End time, seconds.
    pub t1: f32,
}

impl Drive {
    /// The pose at time `t`: before `t0` the start pose, after `t1` the end
    /// pose at rest, in between (`t1` included) position lerped and
    /// rotation slerped, with the constant linear and angular velocity that
    /// carry `from` to `to` over `[t0, t1]`. The step's last sub-step is
    /// posed at `t1` give or take an ulp (the sub-step times are summed in
    /// f64, `t1` in f32): up to [`DRIVE_END_SLACK`] of the step past `t1`
    /// the body still moves (it arrives moving, and Eq. 2 pushes in that
    /// sub-step whichever way the rounding went); later, the next step's
    /// sub-steps when it is not driven again, it is at rest.
    #[must_use]
    pub fn pose_at(&self, t: f32) -> Pose {
        let span = self.t1 - self.t0;
        let slack = 4.0 * f32::EPSILON * self.t1.abs() + DRIVE_END_SLACK * span;
        if span.is_nan() || span <= 0.0 || t > self.t1 + slack {
            return Pose {
                velocity: Vec3::ZERO,
                angular_velocity: Vec3::ZERO,
                ..self.to
            };
        }
        let s = ((t - self.t0) / span).clamp(0.0, 1.0);
        let velocity = (self.to.position - self.from.position) / span;
        let turn = (self.to.rotation * self.from.rotation.inverse()).normalize();
        // The shorter way round (q and -q are the same rotation).
        let turn = if turn.w < 0.0 { -turn } else { turn };
        let (axis, angle) = turn.to_axis_angle();
        let angular_velocity = if angle.abs() > 1e-7 {
            axis * (angle / span)
        } else {
            Vec3::ZERO
        };
        Pose {
            position: self.from.position.lerp(self.to.position, s),
            rotation: self.from.rotation.slerp(self.to.rotation, s),
            velocity,
            angular_velocity,
        }
    }
}

impl Simulation {
    /// Drives body `index` over the next step of `dt` seconds: it moves from
    /// its current pose to `position` with `rotation` (world from local),
    /// sweeping the grass on the way. Call it before each [`Simulation::step`]
    /// of that `dt`; between calls the body stays where it was left, at rest.
    /// [`Simulation::release`] gives it back to its path. Returns `false`
    /// (and does nothing) when there is no such body, a value is not
    /// finite or `rotation` is zero ([`unit_rotation`]; any other size is
    /// normalised). See also [`Simulation::move_body`], the same by
    /// [`BodyId`].
    pub fn drive(&mut self, index: usize, position: Vec3, rotation: Quat, dt: f32) -> bool {
        let now = self.time as f32;
        let Some(body) = self.bodies.get_mut(index) else {
            return false;
        };
        let Some(rotation) = unit_rotation(rotation) else {
            return false;
        };
        if !(position.is_finite() && dt.is_finite() && dt > 0.0) {
            return false;
        }
        // A body that sat out steps (far from the camera, waiting for its
        // turn: `sim.far_every`) goes from where its last turn left it, in
        // a straight line through the moves it sat out, so that its turn
        // sweeps the way it went (`step::passes`).
        let (from, t0) = if body.stepped_to < self.time {
            let t = body.stepped_to as f32;
            (body.pose_at(t), t)
        } else {
            (body.pose, now)
        };
        body.drive = Some(Drive {
            from,
            to: Pose {
                position,
                rotation,
                velocity: Vec3::ZERO,
                angular_velocity: Vec3::ZERO,
            },
            t0,
            t1: now + dt,
        });
        true
    }

    /// The host moves body `id` over the next step of `dt` seconds to
    /// `position` with `rotation` (world from local), sweeping the grass on
    /// the way ([`Simulation::drive`] by id). Call it before each
    /// [`Simulation::step`] of that `dt`; a body not moved in a step stays
    /// where it was, at rest.
    ///
    /// # Errors
    /// [`BodyError`] (and nothing changes) for an unknown id, a value that
    /// is not finite (or `dt ≤ 0`) or a zero `rotation`.
    pub fn move_body(
        &mut self,
        id: BodyId,
        position: Vec3,
        rotation: Quat,
        dt: f32,
    ) -> Result<(), BodyError> {
        let index = self.index_of(id)?;
        if self.drive(index, position, rotation, dt) {
            Ok(())
        } else {
            Err(BodyError::NotFinite {
                id,
                what: format!("position = {position}, rotation = {rotation}, dt = {dt}"),
                extra: "; dt > 0 and the rotation not zero",
            })
        }
    }

    /// Puts body `id` at `position` with `rotation` (world from local) at
    /// once, without sweeping the grass in between: no sub-step is taken
    /// along the jump, and the body is at rest there (no velocity, so no
    /// Eq. 2 force from the jump). It stays there until moved again
    /// ([`Simulation::move_body`], which then starts from here) or released
    /// to its path ([`Simulation::release`]).
    ///
    /// # Errors
    /// [`BodyError`] (and nothing changes) for an unknown id, a value that
    /// is not finite or a zero `rotation`.
    pub fn teleport_body(
        &mut self,
        id: BodyId,
        position: Vec3,
        rotation: Quat,
    ) -> Result<(), BodyError> {
        let index = self.index_of(id)?;
        let unit = unit_rotation(rotation).filter(|_| position.is_finite());
        let Some(rotation) = unit else {
            return Err(BodyError::NotFinite {
                id,
                what: format!("position = {position}, rotation = {rotation}"),
                extra: "; the rotation not zero",
            });
        };
        let t = self.time as f32;
        let pose = Pose {
            position,
            rotation,
            velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
        };
        let body = &mut self.bodies[index];
        // An empty span: `Drive::pose_at` is `to` at rest at every time.
        body.drive = Some(Drive {
            from: pose,
            to: pose,
            t0: t,
            t1: t,
        });
        body.set_time(t);
        Ok(())
    }

    /// Body `index` follows its path again (from its pose at the current
    /// time: it jumps there). No-op for an unknown index.
    pub fn release(&mut self, index: usize) {
        let t = self.time as f32;
        if let Some(body) = self.bodies.get_mut(index) {
            body.drive = None;
            body.set_time(t);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    #[test]
    fn driven_pose_interpolates_and_carries_the_step_velocity() {
        let from = Pose::at_rest(Vec3::ZERO);
        let to = Pose {
            rotation: Quat::from_rotation_y(0.5),
            ..Pose::at_rest(Vec3::new(1.0, 0.0, 2.0))
        };
        let d = Drive {
            from,
            to,
            t0: 1.0,
            t1: 1.5,
        };
        let mid = d.pose_at(1.25);
        assert!((mid.position - Vec3::new(0.5, 0.0, 1.0)).length() < 1e-6);
        assert!((mid.velocity - Vec3::new(2.0, 0.0, 4.0)).length() < 1e-5);
        assert!((mid.angular_velocity - Vec3::Y).length() < 1e-5);
        assert_eq!(d.pose_at(0.0).position, Vec3::ZERO);
        let end = d.pose_at(2.0);
        assert_eq!(end.position, to.position);
        assert_eq!(end.velocity, Vec3::ZERO);
    }

    #[test]
    fn a_driven_ball_goes_where_it_is_driven_and_bends_the_grass() {
        let mut sim = Scene::parse(SMALL, "small", std::path::Path::new("."))
            .unwrap()
            .build()
            .unwrap();
        let dt = sim.params.dt_s;
        let start = sim.bodies[0].pose.position;
        // 2 m/s along +x for 30 steps, turning.
        for i in 1..=30 {
            let p = start + Vec3::X * (2.0 * dt * i as f32);
            assert!(sim.drive(0, p, Quat::from_rotation_y(0.01 * i as f32), dt));
            sim.step(dt).unwrap();
            assert!((sim.bodies[0].pose.position - p).length() < 1e-5);
        }
        // The grass along its track is pressed down: tips lowered by 5 cm or
        // more (measured 2026-11-23: 21 blades, the deepest by 11 cm), and
        // only there: every such blade's root within the ball's radius plus
        // a blade's height (0.3 + 0.45 m) of the segment the ball's centre
        // swept, x in [-0.5, 0.5] at z = 0 (measured: 0.30 m at most).
        let bl = &sim.field.blades;
        let pressed: Vec<usize> = (0..bl.count)
            .filter(|&b| bl.tip_lowering(b) >= 0.05)
            .collect();
        assert!(
            pressed.len() >= 10,
            "only {} tips lowered by 5 cm along the ball's track",
            pressed.len()
        );
        for &b in &pressed {
            let root = bl.rest_vertex(b, 0);
            let on_path = Vec3::new(root.x.clamp(-0.5, 0.5), root.y, 0.0);
            let off = Vec3::from(root).distance(on_path);
            assert!(off <= 0.75, "blade {b} pressed down {off} m off the track");
        }
        // Not driven any more: it stays, at rest.
        let here = sim.bodies[0].pose.position;
        sim.step(dt).unwrap();
        assert_eq!(sim.bodies[0].pose.position, here);
        assert_eq!(sim.bodies[0].pose.velocity, Vec3::ZERO);
        // Released: back on its path (static here: where it started).
        sim.release(0);
        assert_eq!(sim.bodies[0].pose.position, start);
        assert!(!sim.drive(7, Vec3::ZERO, Quat::IDENTITY, dt));
        assert!(!sim.drive(0, Vec3::NAN, Quat::IDENTITY, dt));
    }

    #[test]
    fn an_undriven_scene_is_unchanged() {
        let mut a = Scene::parse(MOVING, "moving", std::path::Path::new("."))
            .unwrap()
            .build()
            .unwrap();
        let mut b = a.clone();
        a.run(20).unwrap();
        // Release of a body that was never driven changes nothing.
        b.release(0);
        b.run(20).unwrap();
        assert_eq!(a.blade_vertices(), b.blade_vertices());
    }

    const SMALL: &str = r#"
[field]
patches = [2, 2]
cells_per_patch = 16
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.3 }
path = { kind = "static", position = [-0.5, 0.2, 0.0] }
[camera]
path = { kind = "static", position = [0.0, 3.0, 4.0] }
"#;

    const MOVING: &str = r#"
[field]
patches = [2, 2]
cells_per_patch = 16
[[objects]]
name = "ball"
shape = { kind = "sphere", radius_m = 0.3 }
path = { kind = "line", from = [-1.5, 0.2, 0.0], to = [1.5, 0.2, 0.0], duration_s = 1.0 }
"#;
}

#[cfg(test)]
mod drive_end_tests {
    use super::*;

    /// The step's last sub-step is posed at `t1` give or take an ulp: the
    /// body arrives moving whichever way the rounding went (Eq. 2 pushes
    /// in that sub-step), and is at rest from the next step's first
    /// sub-step on.
    #[test]
    fn a_drive_arrives_moving_and_rests_after() {
        let rest = Pose {
            position: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            velocity: Vec3::ZERO,
            angular_velocity: Vec3::ZERO,
        };
        let (t0, dt) = (12.345_f32, 1.0 / 60.0);
        let d = Drive {
            from: rest,
            to: Pose {
                position: Vec3::new(0.05, 0.0, 0.0),
                ..rest
            },
            t0,
            t1: t0 + dt,
        };
        let v = 0.05 / (d.t1 - d.t0);
        for t in [
            d.t1.next_down(),
            d.t1,
            d.t1.next_up(),
            d.t1.next_up().next_up(),
        ] {
            let p = d.pose_at(t);
            assert!((p.velocity.x - v).abs() < 1e-3 * v, "at {t}: {p:?}");
            assert!((p.position.x - 0.05).abs() < 1e-5);
        }
        // The next step's first sub-step, even at 1024 sub-steps a step.
        let p = d.pose_at(d.t1 + dt / 1024.0);
        assert_eq!(p.velocity, Vec3::ZERO);
        assert_eq!(p.position, d.to.position);
    }
}
