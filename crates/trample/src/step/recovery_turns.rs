//! Far blades recover in turns (ours, issue 16; DESIGN §6 and §7): with
//! `sim.far_every = k > 1`, the blades of a patch lying wholly farther
//! than `sim.far_beyond_m` from the camera (horizontally, its box) — or,
//! with `sim.far_outside_view`, whose box lies outside the view frustum
//! ([`super::far_rule::FarRule`]) — recover only every k-th step, and
//! then over all the time since the patch last recovered — as far bodies
//! take turns ([`super::passes`]). A crowd
//! leaving finite trails over a meadow keeps tens of thousands of blades
//! recovering, each relaxed, its cell recomputed and its vertices listed
//! for upload every step; far from the camera a turn of k steps is not
//! seen, and the work there is divided by k.
//!
//! The plan is made once a step in [`super::Simulation::begin_step`], so the
//! CPU path and the GPU path (which uploads [`RecoveryTurns::scale`])
//! recover the same blades by the same time. Patch `p` takes its turn on
//! the steps where `(frame + p) % k == 0`, so neighbouring patches share
//! the work out over the k steps. A patch that comes near (or into view)
//! recovers at once all the time it owes; one that goes far waits for its
//! turn. The
//! recovery is frame-rate independent (`exp(−dt/τ)`, and its tail to first
//! order), so a far patch's blades are where they would be had they
//! recovered every step, at each of its turns; between turns they lag by
//! at most `k − 1` steps of recovery. A blade displaced between two turns
//! recovers at the next one over the patch's whole time since the last:
//! up to `k − 1` steps early, the price of keeping one clock a patch. (In
//! the paper's mode the bent billboards' slopes still recover every step:
//! one vector a cell.)

use super::far_rule::FarRule;
use crate::field::FieldLayout;

/// This step's recovery time of every patch, as a multiple of the step.
#[derive(Clone, Debug, Default)]
pub struct RecoveryTurns {
    /// Per patch: the simulated time up to which its blades have
    /// recovered, seconds (set at the first planned step).
    recovered_to: Vec<f64>,
    /// Per patch: what each sub-step's recovery time `h` is multiplied by
    /// this step: exactly 1 near the camera; 0 for a far patch waiting for
    /// its turn; on a far patch's turn, the time since it last recovered
    /// over the step's `dt` (`k` while it stays far). Empty when no patch
    /// takes turns this step.
    scale: Vec<f32>,
}

impl RecoveryTurns {
    /// Plans the step of `dt` seconds from `time` (its start), frame
    /// `frame`: which patches of `layout` recover, and over how long, with
    /// `far_every = k` and the patches `rule` finds far. With `k ≤ 1`, or
    /// no patch far, every patch recovers every step ([`RecoveryTurns::scale`] is
    /// `None`).
    pub fn plan(
        &mut self,
        layout: &FieldLayout,
        rule: &FarRule,
        far_every: u32,
        frame: u64,
        time: f64,
        dt: f32,
    ) {
        self.scale.clear();
        let patches = &layout.patch_list;
        if far_every <= 1 {
            self.recovered_to.clear();
            return;
        }
        if self.recovered_to.len() != patches.len() {
            self.recovered_to = vec![time; patches.len()];
        }
        let end = time + f64::from(dt);
        let k = u64::from(far_every);
        self.scale.reserve(patches.len());
        for (p, (patch, recovered_to)) in patches.iter().zip(&mut self.recovered_to).enumerate() {
            let far = rule.patch(patch.aabb_min, patch.aabb_max);
            let s = if far && !(frame + p as u64).is_multiple_of(k) {
                0.0
            } else if *recovered_to == time {
                // Recovered up to this step: the step itself, exactly.
                1.0
            } else {
                ((end - *recovered_to) / f64::from(dt)) as f32
            };
            if s != 0.0 {
                *recovered_to = end;
            }
            self.scale.push(s);
        }
        if self.scale.iter().all(|&s| s == 1.0) {
            self.scale.clear();
        }
    }

    /// Per patch, in storage order: what each sub-step's recovery time is
    /// multiplied by this step (1 near the camera, 0 for a far patch
    /// waiting for its turn, the time it owes over `dt` on its turn); `None`
    /// when every patch recovers every step.
    #[must_use]
    pub fn scale(&self) -> Option<&[f32]> {
        (!self.scale.is_empty()).then_some(self.scale.as_slice())
    }
}

pub use super::far_rule::patch_is_far;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::{Field, FieldParams, Terrain};
    use glam::Vec3;

    fn layout() -> FieldLayout {
        let params = FieldParams {
            patches: [8, 2],
            cells_per_patch: 4,
            ..FieldParams::default()
        };
        let field = Field::generate(&params, Terrain::Flat(0.0)).expect("field");
        field.layout
    }

    /// Near patches recover every step by exactly the step; far ones on
    /// every k-th step, each by the time since it last did, so that over
    /// any run every patch has recovered for all the time, and a patch
    /// that comes near catches up at once.
    #[test]
    fn far_patches_take_turns_and_owe_no_time() {
        let layout = layout();
        let n = layout.patch_list.len();
        let mut turns = RecoveryTurns::default();
        let (dt, k) = (1.0 / 60.0, 4u32);
        let far_eye = Vec3::new(1000.0, 0.0, 0.0);
        let mut owed = vec![0.0f64; n];
        let mut time = 0.0f64;
        for frame in 0..40u64 {
            // Frames 20..30: the camera in the middle, every patch near.
            let eye = if (20..30).contains(&frame) {
                Vec3::ZERO
            } else {
                far_eye
            };
            turns.plan(
                &layout,
                &FarRule::by_distance(eye, 30.0),
                k,
                frame,
                time,
                dt,
            );
            let scale = turns.scale();
            // Every patch near: none takes turns, once the near ones have
            // caught up (frame 20).
            assert_eq!(scale.is_none(), (21..30).contains(&frame), "{frame}");
            let s = |p: usize| scale.map_or(1.0, |s| s[p]);
            if let Some(s) = scale {
                assert_eq!(s.len(), n);
            }
            let on = (0..n).filter(|&p| s(p) != 0.0).count();
            if !(20..30).contains(&frame) {
                // A quarter of the patches take their turn a step.
                assert_eq!(on, n / 4, "{frame}");
            } else {
                assert_eq!(on, n, "{frame}");
            }
            for (p, owed) in owed.iter_mut().enumerate() {
                *owed += f64::from(dt);
                if s(p) != 0.0 {
                    assert!((20..30).contains(&frame) || (frame + p as u64).is_multiple_of(4));
                    let got = f64::from(s(p)) * f64::from(dt);
                    assert!((got - *owed).abs() < 1e-6, "{frame} {p}");
                    *owed = 0.0;
                }
                assert!(*owed < f64::from(k) * f64::from(dt) - 1e-9);
            }
            if frame == 30 {
                // Back far after frames near: a turn owes one step.
                assert!((0..n).all(|p| s(p) == 0.0 || (s(p) - 1.0).abs() < 1e-4));
            }
            if frame == 20 {
                // Near again: the patches that waited catch up at once.
                assert!((0..n).any(|p| s(p) > 1.5));
            }
            time += f64::from(dt);
        }
        // With far_every = 1 nothing takes turns.
        turns.plan(
            &layout,
            &FarRule::by_distance(far_eye, 30.0),
            1,
            40,
            time,
            dt,
        );
        assert!(turns.scale().is_none());
    }

    /// With `sim.far_outside_view` the patches out of the camera's view
    /// take turns however near (their boxes, which hold their blades,
    /// outside the frustum), those in view recover every step, and a patch
    /// the camera turns onto catches up at once.
    #[test]
    fn patches_out_of_view_take_turns_when_asked() {
        use crate::step::HostView;
        let layout = layout();
        let n = layout.patch_list.len();
        let (dt, k) = (1.0 / 60.0, 4u32);
        // In the middle of the field, 1 m up, looking along +x or −x.
        let eye = Vec3::new(0.0, 1.0, 0.0);
        let rule = |towards: f32| {
            let view = HostView::look_at(
                eye,
                eye + Vec3::new(towards, -0.5, 0.0),
                0.9,
                1.5,
                0.1,
                100.0,
            )
            .expect("view");
            FarRule {
                view: Some(view.frustum()),
                ..FarRule::by_distance(eye, 30.0)
            }
        };
        let seen = |rule: &FarRule, p: usize| {
            let patch = &layout.patch_list[p];
            rule.view
                .expect("a view")
                .intersects_aabb(patch.aabb_min, patch.aabb_max)
        };
        let (ahead, behind) = (rule(1.0), rule(-1.0));
        let out = (0..n).filter(|&p| !seen(&ahead, p)).count();
        assert!(out > 2 && out < n - 2, "{out} of {n} out of view");
        let mut turns = RecoveryTurns::default();
        let mut time = 0.0f64;
        for frame in 0..12u64 {
            // Frames 8..: the camera turned round.
            let rule = if frame < 8 { &ahead } else { &behind };
            turns.plan(&layout, rule, k, frame, time, dt);
            let scale = turns.scale().expect("some patches take turns");
            for (p, &s) in scale.iter().enumerate() {
                if seen(rule, p) {
                    // Every step; at the turn, a patch that waited
                    // catches up on the time it owes.
                    assert!(s >= 1.0 - 1e-6, "{frame}: patch {p} in view, {s}");
                } else {
                    assert_eq!(
                        s != 0.0,
                        (frame + p as u64).is_multiple_of(u64::from(k)),
                        "{frame}: patch {p} out of view takes its turn"
                    );
                }
            }
            if frame == 8 {
                assert!(scale.iter().any(|&s| s > 1.5), "catching up");
            }
            time += f64::from(dt);
        }
        // Without the view, every patch is near: none takes turns.
        turns.plan(&layout, &FarRule::by_distance(eye, 30.0), k, 12, time, dt);
        turns.plan(
            &layout,
            &FarRule::by_distance(eye, 30.0),
            k,
            13,
            time + f64::from(dt),
            dt,
        );
        assert!(turns.scale().is_none());
    }
}
