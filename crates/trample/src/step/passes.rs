//! Far objects stepped less often (ours, issue 16; beside DESIGN §7's
//! step, resting on §6's frame-rate independence): how a step is split into
//! passes over the bodies.
//!
//! With `sim.far_every = k > 1`, a body that can be posed at any time
//! ([`Body::may_step_far`]) and whose root box lies wholly farther than
//! `sim.far_beyond_m` from the camera (horizontally) touches the grass only
//! on the steps where `(frame + id) % k == 0` — the far bodies take turns,
//! so each step carries about `1/k` of them — and then over all the time
//! since it last did. A step runs:
//!
//! - its **main pass**: the step's `dt` from `time`, over the bodies that
//!   are not far (every body when `k = 1`: the step as it always was), with
//!   the levels of detail, the view, the transitions and the recovery —
//!   what happens once per elapsed time;
//! - one **far pass** per distinct start among the far bodies due this step
//!   (usually one, `k` steps back; a body that just became far starts
//!   later): those bodies alone, from the end of the last step they took
//!   part in to the end of this one, sub-stepped for their own travel
//!   (DESIGN §9, and no farther than `sim.far_travel_m` a sub-step, so that
//!   the patch a body presses flat is not left dotted): collision, forces
//!   (Eq. 2), propagation (Eq. 4), bending (Eq. 5–7, the displacement
//!   `F · h` with the pass's `h`) and contact.
//!
//! Far bodies not due this step do not touch the grass. A body that sat
//! out steps and is near now (the camera came, or it did) catches up in a
//! pass of its own from where it stopped, and steps with the others after.
//! A turn is a coarser step for that body, so its track is no farther from
//! the every-frame one than that of the whole field stepped at `k · dt`
//! (the bending is frame-rate independent, DESIGN §6, the closer the finer
//! the step; the travel bound brings it closer: measured in
//! `tests/sim_far_objects.rs`), laid `k` frames at a time where the camera
//! sees it as ground or billboards. A blade a far body holds is not held on
//! the steps between (it recovers there as any blade when `recovery_s` is
//! finite, and is pressed again on the next turn). Both paths run the
//! passes planned here (STYLE rule 9): the CPU in
//! [`super::Simulation::step`], the GPU path in its own outer loop.

use super::body::Body;
use super::simulation::Simulation;
use super::stages::{SubstepPlan, plan_substeps_of};
use glam::Vec3;

/// One pass of a step over some of the bodies (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Pass {
    /// Per body, in [`Simulation::bodies`] order: whether its colliders
    /// take part in this pass.
    pub active: Vec<bool>,
    /// When the pass starts, seconds of simulation time.
    pub start: f64,
    /// How long it lasts, seconds.
    pub dt: f32,
    /// The step's main pass (levels of detail, view, transitions and
    /// recovery run in it, once per step); `false` for a far pass.
    pub main: bool,
    /// Its sub-steps ([`super::stages::plan_substeps`] for its bodies).
    pub plan: SubstepPlan,
}

impl Pass {
    fn new(sim: &Simulation, active: Vec<bool>, start: f64, dt: f32, main: bool) -> Self {
        let max_travel = if main {
            f32::INFINITY
        } else {
            sim.params.far_travel_m
        };
        let plan = plan_substeps_of(sim, Some(&active), start, dt, max_travel);
        Self {
            active,
            start,
            dt,
            main,
            plan,
        }
    }

    /// The length of each of its sub-steps, seconds.
    #[must_use]
    pub fn h(&self) -> f32 {
        self.dt / self.plan.substeps as f32
    }

    /// When its sub-step `i` (1-based) ends, seconds.
    #[must_use]
    pub fn substep_time(&self, i: u32) -> f32 {
        (self.start + f64::from(self.h()) * f64::from(i)) as f32
    }

    /// How many bodies take part.
    #[must_use]
    pub fn bodies(&self) -> usize {
        self.active.iter().filter(|&&a| a).count()
    }

    /// Whether body `i` takes part.
    #[must_use]
    pub fn has(&self, i: usize) -> bool {
        self.active.get(i).copied().unwrap_or(false)
    }
}

/// Whether `body` lies wholly farther than `beyond` metres from `eye`,
/// horizontally: its root box's centre, less the box's half diagonal
/// (its bounding sphere), is farther than that.
#[must_use]
pub fn is_far(body: &Body, eye: Vec3, beyond: f32) -> bool {
    let root = &body.world_root;
    let d = (root.center.x - eye.x).hypot(root.center.z - eye.z) - root.half_diagonal();
    d > beyond
}

/// The passes of a step of `dt` seconds (see the module docs): the main
/// pass first, then the far passes by start time.
#[must_use]
pub fn plan_passes(sim: &Simulation, dt: f32) -> Vec<Pass> {
    let n = sim.bodies.len();
    let every = u64::from(sim.params.far_every.max(1));
    let end = sim.time + f64::from(dt);
    let mut main = vec![true; n];
    let mut due: Vec<(f64, usize)> = Vec::new();
    let eye = sim.eye();
    for (i, body) in sim.bodies.iter().enumerate() {
        let far = every > 1 && body.may_step_far() && is_far(body, eye, sim.params.far_beyond_m);
        // A body that sat out steps (far, waiting for its turn) and is near
        // now catches up at once, from where it stopped.
        let behind = body.stepped_to < sim.time;
        if !far && !behind {
            continue;
        }
        main[i] = false;
        let turn = !far || (sim.frame + u64::from(body.id.0)).is_multiple_of(every);
        if turn && body.stepped_to < end {
            due.push((body.stepped_to, i));
        }
    }
    let mut passes = vec![Pass::new(sim, main, sim.time, dt, true)];
    due.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    for group in due.chunk_by(|a, b| a.0 == b.0) {
        let start = group[0].0;
        let mut active = vec![false; n];
        for &(_, i) in group {
            active[i] = true;
        }
        passes.push(Pass::new(sim, active, start, (end - start) as f32, false));
    }
    passes
}

/// How many bodies the far passes of `passes` step (every pass but the
/// first, the main one): [`crate::StepTimings::far_bodies`].
#[must_use]
pub fn far_bodies(passes: &[Pass]) -> u32 {
    passes.iter().skip(1).map(Pass::bodies).sum::<usize>() as u32
}
