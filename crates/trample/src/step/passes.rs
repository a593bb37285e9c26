//! Far objects stepped less often (ours, issue 16; beside DESIGN §7's
//! step, resting on §6's frame-rate independence): how a step is split into
//! passes over the bodies.
//!
//! With `sim.far_every = k > 1`, a body (any: [`Body::may_step_far`]; an
//! articulated or animated one's rig runs on from its last turn,
//! [`Body::pose_for_pass`]) whose colliders' root boxes lie wholly farther
//! than `sim.far_beyond_m` from the camera (horizontally) — or, with
//! `sim.far_outside_view`, wholly out of its view, grown by the reach of
//! the grass it bends ([`is_out_of_view`]) — touches the grass only
//! on the steps where `(frame + turn) % k == 0` — the far bodies take
//! turns, so each step carries about `1/k` of them — and then over all the
//! time since it last did. A body's `turn` ([`far_schedule`]) is given when
//! it becomes far, and again after a turn at which its speed asks for more
//! or fewer sub-steps than when it was given it (it sped up, slowed down,
//! stopped or started), and kept otherwise: the one whose far pass has the
//! least work with it ([`far_work`]: each body's ground times its own
//! sub-steps, a body standing still counting [`AT_REST_SHARE`] of its
//! ground, weighed by how much of its shape reaches down into the grass:
//! [`far_shape_weight`], [`super::far_shape`]), so that each step carries
//! about `1/k` of the far bodies' work and not only of their number (the
//! herd at `k = 16`, two cores, 240 steps: by body id, a turn's steps took
//! 10.9 to 22.5 ms on average and 31–36 steps took over 20 ms; by each
//! body's ground times its own sub-steps, 12.3 to 18.5 ms and 2–4 steps:
//! BENCHMARKS.md, session 27; since session 68 each body runs its own
//! sub-steps, where before the bodies of a turn shared its fastest's and
//! the load counted that, session 29). A step runs:
//!
//! - its **main pass**: the step's `dt` from `time`, over the bodies that
//!   are not far (every body when `k = 1`: the step as it always was) and
//!   need the fewest sub-steps, with the levels of detail, the view, the
//!   transitions and the recovery — what happens once per elapsed time;
//! - one **near pass** per number of sub-steps that other near bodies need
//!   (fewest first): the same `dt` from `time`, those bodies alone, each
//!   sub-stepped for its own travel (DESIGN §9) as a far pass is
//!   (collision, forces, propagation, bending, contact). A body is
//!   sub-stepped for its own speed, not for the fastest body's anywhere on
//!   the field: before, one character turning on the spot (its spin at the
//!   half diagonal is a fast travel) split the whole step in five, every
//!   character and the recovery with it (the `crowd` example, 64
//!   characters over a meadow, two cores: in its second and third seconds
//!   the step's 90th percentile was 21–30 ms against medians of 6–9 ms;
//!   now 7–12 ms; BENCHMARKS.md, session 42).
//!   A blade such a body holds recovers in the main pass, which runs first,
//!   and is pressed again in the body's pass (as a blade a far body holds);
//!   with a finite `recovery_s` that is a fraction `1 − exp(−dt/τ)` of its
//!   bend a step, put back by the body's contact before the step ends;
//! - one **far pass** per distinct start among the far bodies due this step
//!   (usually one, `k` steps back; a body that just became far starts
//!   later) and per number of sub-steps they need, fewest first: those
//!   bodies alone, from the end of the last step they took part in to the
//!   end of this one, sub-stepped for their own travel (DESIGN §9, and no
//!   farther than `sim.far_travel_m` a sub-step, so that the patch a body
//!   presses flat is not left dotted; a slow body is not carried through a
//!   fast one's sub-steps: on the herd at `k = 16` that was 15 % of the
//!   far passes' work, and pressed those bodies' tracks flatter — 65 % of
//!   the every-step run's flat blades then, 60 % now; BENCHMARKS.md,
//!   session 68): collision, forces
//!   (Eq. 2), propagation (Eq. 4), bending (Eq. 5–7, the displacement
//!   `F · h` with the pass's `h`) and contact.
//!
//! Far bodies not due this step do not touch the grass. A body that sat
//! out steps and is near now (the camera came, or turned onto it, or the
//! body came) catches up in a pass of its own from where it stopped, and
//! steps with the others after.
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

use super::at_rest::is_still;
use super::body::Body;
use super::far_rule::FarRule;
use super::simulation::Simulation;
use super::stages::{SubstepPlan, body_substeps, plan_of_needs};

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
    /// recovery run in it, once per step); `false` for a far pass and for
    /// a pass of faster near bodies.
    pub main: bool,
    /// A pass over bodies near the camera, over the step's own time: the
    /// main pass, or a pass of near bodies that need more sub-steps than
    /// the main pass's ([`plan_passes`]); `false` for a far pass.
    pub near: bool,
    /// Its sub-steps: the most its bodies need
    /// (`stages::body_substeps`, `stages::plan_of_needs`).
    pub plan: SubstepPlan,
}

impl Pass {
    /// A pass over the bodies of `group` (`(body index, sub-steps it
    /// needs before max_substeps)`, [`by_need`]), `dt` seconds from
    /// `start`, running the most sub-steps any of them needs
    /// (`stages::plan_of_needs`).
    fn of_group(
        sim: &Simulation,
        group: &[(usize, u32)],
        start: f64,
        dt: f32,
        (main, near): (bool, bool),
    ) -> Self {
        let mut active = vec![false; sim.bodies.len()];
        for &(i, _) in group {
            active[i] = true;
        }
        Self {
            active,
            start,
            dt,
            main,
            near,
            plan: plan_of_needs(group.iter().copied(), sim.params.max_substeps),
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

pub use super::far_rule::{is_far, is_out_of_view};

/// The passes of a step of `dt` seconds (see the module docs): the main
/// pass first, then the far passes by start time.
#[must_use]
pub fn plan_passes(sim: &Simulation, dt: f32) -> Vec<Pass> {
    plan_passes_with(sim, dt, &far_turns(sim))
}

/// [`plan_passes`] with the far bodies' turns already found
/// ([`far_turns`] of `sim`: what [`Simulation::begin_step`] keeps).
pub(crate) fn plan_passes_with(sim: &Simulation, dt: f32, turns: &[Option<u32>]) -> Vec<Pass> {
    let n = sim.bodies.len();
    let every = u64::from(sim.params.far_every.max(1));
    let end = sim.time + f64::from(dt);
    let mut main = vec![true; n];
    let mut due: Vec<(f64, usize)> = Vec::new();
    for (i, body) in sim.bodies.iter().enumerate() {
        let far = turns.get(i).copied().flatten().is_some();
        // A body that sat out steps (far, waiting for its turn) and is near
        // now catches up at once, from where it stopped.
        let behind = body.stepped_to < sim.time;
        if !far && !behind {
            continue;
        }
        main[i] = false;
        let turn = turns
            .get(i)
            .copied()
            .flatten()
            .is_none_or(|t| (sim.frame + u64::from(t)).is_multiple_of(every));
        if turn && body.stepped_to < end {
            due.push((body.stepped_to, i));
        }
    }
    let mut passes = near_passes(sim, &main, dt);
    due.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    for group in due.chunk_by(|a, b| a.0 == b.0) {
        let start = group[0].0;
        let dt = (end - start) as f32;
        // Each body sub-stepped for its own travel: one pass per number of
        // sub-steps, fewest first (a slow body is not carried through a
        // fast one's sub-steps).
        let needs = group.iter().map(|&(_, i)| {
            let k = body_substeps(sim, &sim.bodies[i], start, dt, sim.params.far_travel_m);
            (i, k)
        });
        for same in by_need(sim, needs) {
            passes.push(Pass::of_group(sim, &same, start, dt, (false, false)));
        }
    }
    passes
}

/// The passes over the near bodies `near` marks (see the module docs): the
/// main pass over those that need the fewest sub-steps, then, when others
/// need more, a pass over each group that needs the same number, fewest
/// first.
fn near_passes(sim: &Simulation, near: &[bool], dt: f32) -> Vec<Pass> {
    let needs = (0..near.len()).filter(|&i| near[i]).map(|i| {
        let k = body_substeps(sim, &sim.bodies[i], sim.time, dt, f32::INFINITY);
        (i, k)
    });
    let mut groups = by_need(sim, needs).into_iter();
    // The main pass runs even with no body (the levels of detail, the
    // view, the transitions and the recovery).
    let first = groups.next().unwrap_or_default();
    let mut passes = vec![Pass::of_group(sim, &first, sim.time, dt, (true, true))];
    passes.extend(groups.map(|g| Pass::of_group(sim, &g, sim.time, dt, (false, true))));
    passes
}

/// The bodies of `needs` (`(body index, sub-steps it needs)`, as
/// [`body_substeps`] gives them) in groups that run the same number of
/// sub-steps (at most `max_substeps`), fewest first, each in body order.
fn by_need(
    sim: &Simulation,
    needs: impl IntoIterator<Item = (usize, u32)>,
) -> Vec<Vec<(usize, u32)>> {
    let max = sim.params.max_substeps.max(1);
    let mut needs: Vec<(u32, usize, u32)> = needs
        .into_iter()
        .map(|(i, k)| (k.clamp(1, max), i, k))
        .collect();
    needs.sort_unstable();
    needs
        .chunk_by(|a, b| a.0 == b.0)
        .map(|g| g.iter().map(|&(_, i, k)| (i, k)).collect())
        .collect()
}

/// The sub-steps a step's near passes took ([`Pass::near`]: the main pass
/// and those of faster near bodies), the most of them, and the most their
/// bodies needed before `max_substeps`: [`crate::StepTimings::substeps`]
/// and [`crate::StepTimings::substeps_needed`].
#[must_use]
pub fn near_substeps(passes: &[Pass]) -> (u32, u32) {
    passes.iter().filter(|p| p.near).fold((1, 1), |(s, n), p| {
        (s.max(p.plan.substeps), n.max(p.plan.needed))
    })
}

/// Each body's turn among the far bodies this step (see the module docs):
/// `None` for a body that is not far (or with `sim.far_every` ≤ 1),
/// otherwise `Some(t)`, `t < far_every`: it steps on the frames where
/// `(frame + t) % far_every == 0` ([`far_schedule`] without the sub-steps).
#[must_use]
pub fn far_turns(sim: &Simulation) -> Vec<Option<u32>> {
    far_schedule(sim)
        .into_iter()
        .map(|s| s.map(|s| s.turn))
        .collect()
}

/// A far body's place among the far turns ([`far_schedule`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FarTurn {
    /// Its turn: it steps on the frames where `(frame + turn) % far_every
    /// == 0`; `turn < far_every`.
    pub turn: u32,
    /// The travel of a turn at its speed when it was given `turn`
    /// ([`FarWork::travel`]): it keeps `turn` while its sub-steps stay
    /// those of this travel, or its travel stays within
    /// [`FAR_TRAVEL_BAND`] of it.
    pub travel: f64,
    /// Whether it stood still when it was given `turn` ([`FarWork::still`]):
    /// it keeps `turn` while that stays so.
    pub still: bool,
    /// Its shape's weight when it was given `turn`
    /// ([`super::far_shape::shape_weight`] of its grass-reaching share):
    /// what its ground counts for in its turn's load until it is given one
    /// again (a walk of its trees, so asked only then).
    pub weight: f64,
}

/// How far, in sub-steps, a far body's travel a turn may drift from what
/// it was when it was given its turn before it is given one again, when
/// its sub-steps changed ([`far_schedule`]): a body at a steady speed whose
/// travel sits on a whole number of sub-steps (float noise crossing it)
/// keeps its turn.
pub const FAR_TRAVEL_BAND: f64 = 0.25;

impl FarTurn {
    /// Whether a body given this turn, now with `work`, keeps it.
    fn holds(&self, work: &FarWork) -> bool {
        work.still == self.still
            && (work.substeps() == substeps_of(self.travel)
                || (work.travel - self.travel).abs() < FAR_TRAVEL_BAND)
    }
}

/// Each body's [`FarTurn`] this step: `None` for a body that is not far
/// (or with `sim.far_every` ≤ 1). A far body keeps the turn it had while
/// its speed asks for the sub-steps it had when given it (or its travel a
/// turn stays within [`FAR_TRAVEL_BAND`] of what it was). The bodies that
/// just became far, and those whose sub-steps changed (a body that sped
/// up, slowed down, stopped or started: it changed its pass's load) and
/// that took their turn on the last step, are given theirs largest first
/// (by [`far_cost`]), each the turn whose load is least once it joins
/// (ties: the turn it had, then the first). A turn's load is what its far
/// passes do: each body's ground times its own sub-steps
/// ([`FarWork::cost`]; each body runs its own sub-steps, in a pass with
/// the bodies of its turn that need as many: [`plan_passes`]), weighed by
/// its shape ([`FarTurn::weight`], found when it is given its turn). A body whose
/// speed changed waits for its turn before it moves, so no body waits
/// more than `far_every` steps between two turns. A function of the
/// simulation's state alone, so that [`plan_passes`] and
/// [`Simulation::begin_step`] (which keeps the turns in the bodies) agree.
#[must_use]
pub fn far_schedule(sim: &Simulation) -> Vec<Option<FarTurn>> {
    far_schedule_with(sim, &FarRule::of(sim))
}

/// [`far_schedule`] by the far rule `rule` ([`FarRule::of`] of `sim`: what
/// [`Simulation::begin_step`] finds once for the bodies and the patches).
pub(crate) fn far_schedule_with(sim: &Simulation, rule: &FarRule) -> Vec<Option<FarTurn>> {
    let every = sim.params.far_every.max(1);
    let mut turns = vec![None; sim.bodies.len()];
    if every == 1 {
        return turns;
    }
    // Per turn: the ground its bodies' narrow phases test over a turn.
    let mut load = vec![0.0f64; every as usize];
    let mut placing = Vec::new();
    for (i, body) in sim.bodies.iter().enumerate() {
        if !(body.may_step_far() && rule.body(body)) {
            continue;
        }
        let work = far_work(sim, body);
        let kept = body.far_turn.filter(|t| t.turn < every);
        match kept {
            Some(t) if t.holds(&work) || body.stepped_to < sim.time => {
                turns[i] = Some(t);
                load[t.turn as usize] += work.cost() * t.weight;
            }
            _ => placing.push((work, far_shape_weight(sim, body, &work), i, kept)),
        }
    }
    let cost = |(work, weight, ..): &(FarWork, f64, usize, Option<FarTurn>)| work.cost() * weight;
    placing.sort_by(|a, b| cost(b).total_cmp(&cost(a)).then(a.2.cmp(&b.2)));
    for (work, weight, i, had) in placing {
        let moved = |t: usize| had.is_none_or(|h| h.turn != t as u32);
        let t = (0..every as usize)
            .min_by(|&a, &b| {
                load[a]
                    .total_cmp(&load[b])
                    .then(moved(a).cmp(&moved(b)))
                    .then(a.cmp(&b))
            })
            .expect("far_every > 1 turns");
        load[t] += work.cost() * weight;
        turns[i] = Some(FarTurn {
            turn: t as u32,
            travel: work.travel,
            still: work.still,
            weight,
        });
    }
    turns
}

/// What a far body's turn is taken to cost ([`FarWork::cost`] of
/// [`far_work`]): the ground its root box can reach, m² (a quarter of it
/// standing still), times the sub-steps of a turn at its speed.
/// An estimate from the pose alone, so the same on every machine and
/// thread count.
/// Weighed by its shape ([`far_shape_weight`]).
#[must_use]
pub fn far_cost(sim: &Simulation, body: &Body) -> f64 {
    let work = far_work(sim, body);
    work.cost() * far_shape_weight(sim, body, &work)
}

/// The weight of a far body's ground in its turn's load: its shape's
/// ([`super::far_shape::shape_weight`] of the share of its reach ground,
/// `work.area`, under the final nodes of its trees that reach into the
/// grass, [`super::far_shape::grass_reach_share`]); on the herd a solid
/// box weighs 1.5 times a cow on four legs.
#[must_use]
pub fn far_shape_weight(sim: &Simulation, body: &Body, work: &FarWork) -> f64 {
    super::far_shape::shape_weight(super::far_shape::grass_reach_share(sim, body, work.area))
}

/// A far body's share of a far pass ([`far_work`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FarWork {
    /// The ground its root box can reach, m²: the box's horizontal
    /// rectangle grown by a blade's length and the contact shell, as the
    /// narrow phase's candidates are, averaged over the box's headings (a
    /// far body keeps its turn while it turns: the herd's beetle car covers
    /// 1.8 times more ground turned 45° than along the world's axes).
    /// Finite, ≥ 0.
    pub area: f64,
    /// The travel of a turn at its speed now — `far_every` steps of the
    /// scene's `dt_s` — in `far_travel_m`: finite, ≥ 0
    /// ([`FarWork::substeps`]). The speed is the pose's, or that of the
    /// farthest vertex of a mesh the host animates
    /// ([`Simulation::set_body_vertices`]) when that is faster.
    pub travel: f64,
    /// Whether it stands still now, so that its narrow phase and contact
    /// response take their answers from the sub-step before
    /// (`sim.reuse_at_rest`): every collider's velocity and spin zero, and
    /// not animated. Such a body's ground counts at [`AT_REST_SHARE`].
    pub still: bool,
}

/// What a body standing still costs a sub-step against one moving over the
/// same ground (`sim.reuse_at_rest`: it compares the blades it kept instead
/// of testing them): the herd parked steps in 22.2 ms where the herd
/// moving takes 92.4 ms (every object every step, two cores: 0.24;
/// BENCHMARKS.md, session 30).
pub const AT_REST_SHARE: f64 = 0.25;

impl FarWork {
    /// The ground it counts for in its pass's load: its `area`, at
    /// [`AT_REST_SHARE`] when it stands still.
    #[must_use]
    pub fn ground(&self) -> f64 {
        if self.still {
            self.area * AT_REST_SHARE
        } else {
            self.area
        }
    }

    /// The sub-steps of a turn at its speed now, at most `far_travel_m` of
    /// travel each: the ceiling of `travel`, at least 1.
    #[must_use]
    pub fn substeps(&self) -> f64 {
        substeps_of(self.travel)
    }

    /// `ground · substeps`: the ground its narrow phase tests over a turn.
    #[must_use]
    pub fn cost(&self) -> f64 {
        self.ground() * self.substeps()
    }
}

/// (cos, sin) of the headings the ground a root box reaches is averaged
/// over: a quarter turn (a rectangle's bounds repeat every 90°) in eight
/// equal steps, `k · 90° / 8`. Written out rather than computed, so that
/// the estimate does not depend on the platform's `sin` and `cos`.
const FAR_HEADINGS: [(f32, f32); 8] = [
    (1.0, 0.0),
    (0.980_785_3, 0.195_090_32),
    (0.923_879_5, 0.382_683_43),
    (0.831_469_6, 0.555_570_24),
    (0.707_106_77, 0.707_106_77),
    (0.555_570_24, 0.831_469_6),
    (0.382_683_43, 0.923_879_5),
    (0.195_090_32, 0.980_785_3),
];

/// What a far body does in a far pass (see [`FarWork`]): the turns of
/// [`far_schedule`] balance these. Measured on the herd at `far_every =
/// 16` (BENCHMARKS.md, session 29, when a turn's bodies shared its fastest
/// body's sub-steps): a turn's sub-steps times its bodies' ground follows
/// the blades its narrow phase tests (correlation 0.99 over the 16 turns).
#[must_use]
pub fn far_work(sim: &Simulation, body: &Body) -> FarWork {
    let reach = sim.field.max_blade_length + sim.params.contact_shell_m;
    let root = &body.world_root;
    let corners = root.corners().map(|c| c - root.center);
    let mut area = 0.0f64;
    for &(cos, sin) in &FAR_HEADINGS {
        let (mut x, mut z) = (0.0f32, 0.0f32);
        for d in &corners {
            x = x.max((d.x * cos - d.z * sin).abs());
            z = z.max((d.x * sin + d.z * cos).abs());
        }
        area += f64::from(2.0 * (x + reach)) * f64::from(2.0 * (z + reach));
    }
    area /= FAR_HEADINGS.len() as f64;
    // The pose's speed, or the host's mesh's (its farthest vertex), as
    // the sub-steps count the faster of the two (`stages.rs`).
    let mesh_speed = body
        .rig
        .host
        .as_ref()
        .map_or(0.0, |h| h.speed_at(sim.time as f32));
    let travel = f64::from(body.pose.velocity.length().max(mesh_speed))
        * f64::from(sim.params.dt_s)
        * f64::from(sim.params.far_every);
    let travel = travel / f64::from(sim.params.far_travel_m);
    let travel = if travel.is_finite() {
        travel.max(0.0)
    } else {
        0.0
    };
    let still =
        super::at_rest::may_reuse(&sim.params, body) && body.colliders().all(|c| is_still(c.pose));
    FarWork {
        area: if area.is_finite() { area.max(0.0) } else { 0.0 },
        travel,
        still,
    }
}

/// The sub-steps of a turn that travels `travel` (in `far_travel_m`): its
/// ceiling, at least 1.
fn substeps_of(travel: f64) -> f64 {
    travel.ceil().max(1.0)
}

/// How many bodies the far passes of `passes` step (every pass but the
/// near ones, [`Pass::near`]): [`crate::StepTimings::far_bodies`].
#[must_use]
pub fn far_bodies(passes: &[Pass]) -> u32 {
    passes
        .iter()
        .filter(|p| !p.near)
        .map(Pass::bodies)
        .sum::<usize>() as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn work(travel: f64) -> FarWork {
        FarWork {
            area: 1.0,
            travel,
            still: false,
        }
    }

    /// A body keeps its turn while its sub-steps stay those it was given
    /// it with, and also while its travel stays within the band: float
    /// noise across a whole number of sub-steps (3 → 3 + 1e-12: 3 → 4
    /// sub-steps) does not move it, a change of speed does, and so does
    /// coming to a standstill (its work falls to [`AT_REST_SHARE`]).
    #[test]
    fn a_turn_holds_within_its_sub_steps_or_the_travel_band() {
        let given = |travel| FarTurn {
            turn: 0,
            travel,
            still: false,
            weight: 1.0,
        };
        assert!(given(3.0).holds(&work(3.0)));
        assert!(given(3.0).holds(&work(3.0 + 1e-12)), "noise across 3");
        assert!(given(3.0 + 1e-12).holds(&work(3.0)), "noise across 3");
        assert!(given(2.1).holds(&work(2.9)), "the same 3 sub-steps");
        assert!(!given(3.0).holds(&work(3.3)), "sped up: 3 → 4 sub-steps");
        assert!(!given(3.3).holds(&work(2.9)), "slowed down: 4 → 3");
        assert!(given(0.0).holds(&work(0.9)), "1 sub-step either way");
        assert!(!given(0.0).holds(&work(1.5)), "stopped to moving: 1 → 2");
        assert!(!given(1.5).holds(&work(0.0)), "moving to stopped: 2 → 1");
        let parked = FarWork {
            still: true,
            ..work(0.0)
        };
        assert!(!given(0.0).holds(&parked), "to still: reused, cheaper");
        assert_eq!(parked.cost(), AT_REST_SHARE);
    }
}
