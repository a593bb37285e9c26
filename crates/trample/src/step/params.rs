//! `[sim]` table: parameters of the method, with units, defaults and why.

use serde::{Deserialize, Serialize};

/// Parameters of the simulation step.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimParams {
    /// Time step of one frame, seconds. Default 1/60 (a 60 Hz game loop).
    pub dt_s: f32,
    /// Collision precision: depth of the OBB tree at which a segment test
    /// stops (root = 1, paper range 1–7; up to 32). Default 3, the paper's
    /// setting in its Fig. 10–11 experiments.
    pub precision: u32,
    /// Decay factor `att` of propagation (Eq. 4), in [0, 1]. Default 0.5:
    /// each generation carries half the force of its parent.
    pub att: f32,
    /// Threshold `L` of propagation (Definitions 2–3), m/s: a blade whose
    /// energy |F| is below it propagates no further. Default 0.25.
    pub threshold: f32,
    /// Safety cap on generations of propagation (≤ 254). Default 32.
    pub max_generations: u32,
    /// Constant `a` of the weight function P(x) (Eq. 7). Default 1.
    pub weight_a: f32,
    /// Constant `b` of the weight function P(x) (Eq. 7). Default 2: with
    /// n = 4 the tip moves 1.24× the offset-base vector, the root segment 0.12×.
    pub weight_b: f32,
    /// Recovery time constant, seconds (ours; the paper's future work). A
    /// bent blade relaxes towards rest as exp(−t/τ), and within
    /// [`crate::recovery::RECOVERY_TAIL_M`] of rest at the speed it has
    /// there. Default `inf`: the paper's lasting track.
    pub recovery_s: f32,
    /// How much more slowly a flattened blade recovers: τ·(1 + trail·flatness).
    /// Default 2: a flattened trail lingers three times as long.
    pub trail: f32,
    /// Most sub-steps one step may be split into when an object moves
    /// farther than its own thickness in one step (DESIGN §9). Default 16:
    /// at 60 steps/s a 1 m ball may go 960 m/s before it is clamped. Beyond
    /// it the step runs with `max_substeps` sub-steps, the object may skip
    /// blades, and the step is counted (`Simulation::substep_clamps`; the
    /// CLI warns once). It bounds the cost of one step.
    pub max_substeps: u32,
    /// Largest memory the field may take, GiB; a larger field is refused
    /// before anything is allocated. Default 8.
    pub memory_limit_gib: f32,
    /// Apply the transition rules between levels of detail (Eq. 9–13).
    /// Default `true`. `false` exists to show what they are for: a trampled
    /// cell that leaves geometry then gets an upright billboard, and one that
    /// comes back gets its blades as they were (the renderer's no-popping
    /// test measures the difference).
    pub transitions: bool,
    /// The contact response (ours, DESIGN §5 "Contact"): every blade vertex
    /// found inside an object is moved to its surface, whatever the object's
    /// speed, and a blade an object holds does not recover. Default `true`.
    /// `false` is the paper: Eq. 2 alone, so an object that stands still
    /// leaves the grass through it.
    pub contact: bool,
    /// Thickness of the contact shell, metres (ours, DESIGN §5 "a continuous
    /// response"): the OBB-tree boxes are grown by it for the simulation's
    /// narrow phase, and a segment's contact weight rises from 0 at the
    /// grown box's surface to 1 at this depth into it, so a grazing contact
    /// bends a blade a little instead of fully. Default 0.005: about half a
    /// blade's width (a blade's centre line touches an object this far
    /// before its surface). In (0, 0.5].
    pub contact_shell_m: f32,
    /// Where an object leaves a track (ours, DESIGN §2 "Simulation is not
    /// drawing"). Default `true`: every blade an object touches is simulated
    /// whatever the level of detail of its cell; billboards take their slope
    /// from their cell's blades (Eq. 11–12) and ground-texture cells a
    /// flatness, so a track made far away is there, as made, when the
    /// camera comes close. `false` is the paper: only geometric cells are
    /// simulated, billboards are bent by Eq. 8 and a cell coming back to
    /// geometry gets its billboard's offset on its last segment (Eq. 13).
    pub track_everywhere: bool,
    /// Far objects stepped less often (ours, issue 16; beside DESIGN §7's
    /// step, resting on §6's frame-rate independence): a body (on its scene
    /// path or driven by the host; articulated and animated ones too, their
    /// wheels and skin moving once a turn: [`crate::step::Body::pose_for_pass`])
    /// whose colliders' root boxes lie wholly farther than
    /// [`SimParams::far_beyond_m`] from the camera (horizontally) touches
    /// the grass every `far_every`-th step only — the bodies take turns,
    /// each given the turn with the least work so far, and given it again
    /// when its speed changes ([`crate::step::passes::far_schedule`]), so
    /// each step carries a share
    /// of them — and then over all the
    /// time since it last did: its track is the one the whole field gets
    /// stepped at `far_every · dt` (the displacement `F · h` of DESIGN §6
    /// is frame-rate independent; [`crate::step::passes`]). Likewise the
    /// blades of a patch lying wholly beyond `far_beyond_m` recover
    /// (`recovery_s`) every `far_every`-th step only, patches taking turns,
    /// over all the time since the patch last did
    /// ([`crate::step::recovery_turns`]). Default 1: every object and every
    /// blade every step. 1..=64. Turns save the CPU path's work; the GPU
    /// path's step costs about a chain of dispatches a sub-step however
    /// few blades each moves, and turns add sub-steps (a far pass each,
    /// sub-stepped for its bodies' travel): on an NVIDIA H200 the herd
    /// steps in 22 ms at 16 against 4.8 ms at 1 (BENCHMARKS.md, session 70).
    pub far_every: u32,
    /// How far from the camera, metres (horizontally, to the nearest point
    /// of a body's root box's bounding sphere; to the nearest point of a
    /// patch's box), a body or a patch counts as far (see
    /// [`SimParams::far_every`]). Default 30: the default level of detail's
    /// end of billboards, beyond which the grass is drawn as ground.
    /// Finite, >= 0.
    pub far_beyond_m: f32,
    /// How far a body may move in one sub-step of its far turn, metres
    /// (besides DESIGN §9's own thickness; [`crate::step::passes`]): a
    /// turn covers `far_every` frames of travel, and a body presses the
    /// grass flat only where its pinned patch passes (`deform::contact`;
    /// about 0.2 m across under a 1 m ball), so longer sub-steps leave a
    /// dotted, less flattened track. Default 0.25: at `far_every = 8` the
    /// far tracks keep 88 % of the every-frame flattening (`inf`: 73 %, and
    /// cheaper: BENCHMARKS.md, "Session 14"). Each body is sub-stepped for
    /// its own travel, whatever the bodies sharing its turn need
    /// ([`crate::step::passes::plan_passes`]): on `scenes/herd_small.toml`
    /// at `far_every = 4` the far tracks lie flat for 81 % of the blades
    /// the every-step run lays flat, 88 % at 0.2; on `scenes/herd.toml` at
    /// `far_every = 16`, 60 % at 0.25 and 68 % at 0.2, which costs the
    /// step ~23 % more there (BENCHMARKS.md, "Session 68" and "Session
    /// 69"): the default keeps the herd's step near its 16 ms budget, a
    /// host that wants flatter far tracks sets 0.2. > 0, or `inf` for no
    /// bound.
    pub far_travel_m: f32,
    /// Bodies out of the camera's view take turns too (ours): with
    /// `far_every` above 1, a body near the camera whose colliders' root
    /// boxes, grown by the reach of the grass they can bend (the longest
    /// blade and the contact shell), lie wholly outside the view frustum
    /// (behind the camera, beside it, beyond its far plane) steps every
    /// `far_every`-th step as a far body does ([`SimParams::far_every`];
    /// [`crate::step::passes::is_out_of_view`]) — what a game does with
    /// the animation of the characters it does not see; likewise the
    /// blades of a patch whose box lies outside the frustum recover in
    /// turns ([`crate::step::recovery_turns`]; the rule:
    /// [`crate::step::far_rule::FarRule`]). When the camera turns onto a
    /// body or a patch, it catches up at once, in the step that first sees
    /// it. Default `false`: only distance makes a body or a patch far.
    /// Nothing changes with `far_every = 1`.
    pub far_outside_view: bool,
    /// Colliders at rest reuse their work (ours, `step::at_rest`): while
    /// an object's pose and velocities stay the same bits from one sub-step
    /// to the next, its narrow phase takes the hits it kept for each tile
    /// whose blades did not change, and its contact response leaves
    /// without a query each blade it left as it found it and that is still
    /// those bits. The same answers bit for bit; a parked object then costs
    /// a comparison of the blades under it instead of its queries. Default
    /// `true`; `false` runs every query every sub-step.
    pub reuse_at_rest: bool,
    /// Slow blades recover in strides (ours, issue 16;
    /// [`crate::recovery::stride_wait`]), metres: a displaced blade whose
    /// recovery moves it slowly is relaxed only when it has owed enough
    /// time to move about this far, and then over all that time (at most
    /// [`crate::recovery::RECOVERY_WAIT_MAX_S`] of it), so that a long
    /// trail's blades, most of them creeping back a fraction of a
    /// millimetre a frame, cost their relaxation, their cell and their
    /// upload only every few frames. A blade an object moves recovers at
    /// the next step again. In a trail left behind no vertex is ever more
    /// than about two strides from where the every-step recovery puts it.
    /// Default 0.0005: half a
    /// millimetre, under a pixel at half a metre at 1080p (a crowd's
    /// trails cost half as much: BENCHMARKS.md, "Session 43"). 0: every
    /// displaced blade every step (bit for bit the recovery without
    /// strides). In [0, 0.05].
    pub recovery_stride_m: f32,
}

impl Default for SimParams {
    fn default() -> Self {
        Self {
            dt_s: 1.0 / 60.0,
            precision: 3,
            att: 0.5,
            threshold: 0.25,
            max_generations: 32,
            weight_a: 1.0,
            weight_b: 2.0,
            recovery_s: f32::INFINITY,
            trail: 2.0,
            max_substeps: 16,
            memory_limit_gib: 8.0,
            transitions: true,
            contact: true,
            contact_shell_m: 0.005,
            track_everywhere: true,
            far_every: 1,
            far_beyond_m: 30.0,
            far_travel_m: 0.25,
            far_outside_view: false,
            reuse_at_rest: true,
            recovery_stride_m: 0.0005,
        }
    }
}

/// Highest precision accepted: deeper than any tree the builder makes for a
/// mesh of up to 2^31 triangles.
pub const MAX_PRECISION: u32 = 32;

/// A `[sim]` value out of range. The message names the key.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("sim.{key} = {value}: {allowed}")]
pub struct SimError {
    /// Key under `[sim]`.
    pub key: &'static str,
    /// The offending value.
    pub value: String,
    /// What is allowed.
    pub allowed: &'static str,
}

impl SimParams {
    /// Checks every value; the first bad one is reported.
    pub fn validate(&self) -> Result<(), SimError> {
        let err = |key, value: f64, allowed| {
            Err(SimError {
                key,
                value: fmt(value),
                allowed,
            })
        };
        check_dt(self.dt_s)?;
        if !(1..=MAX_PRECISION).contains(&self.precision) {
            return err(
                "precision",
                f64::from(self.precision),
                "must be 1..=32 (the paper uses 1..=7)",
            );
        }
        if !(0.0..=1.0).contains(&self.att) {
            return err("att", f64::from(self.att), "must be in [0, 1]");
        }
        if !(self.threshold.is_finite() && self.threshold > 0.0) {
            return err(
                "threshold",
                f64::from(self.threshold),
                "must be a finite number > 0 (m/s)",
            );
        }
        if !(1..=254).contains(&self.max_generations) {
            return err(
                "max_generations",
                f64::from(self.max_generations),
                "must be 1..=254",
            );
        }
        if !(self.weight_a.is_finite() && self.weight_a > 0.0) {
            return err(
                "weight_a",
                f64::from(self.weight_a),
                "must be a finite number > 0",
            );
        }
        if !(self.weight_b.is_finite() && self.weight_b > 0.0) {
            return err(
                "weight_b",
                f64::from(self.weight_b),
                "must be a finite number > 0",
            );
        }
        if self.recovery_s.is_nan() || self.recovery_s <= 0.0 {
            return err(
                "recovery_s",
                f64::from(self.recovery_s),
                "must be > 0 seconds, or inf for a lasting track",
            );
        }
        if !(self.trail.is_finite() && self.trail >= 0.0) {
            return err(
                "trail",
                f64::from(self.trail),
                "must be a finite number >= 0",
            );
        }
        if !(1..=1024).contains(&self.max_substeps) {
            return err(
                "max_substeps",
                f64::from(self.max_substeps),
                "must be 1..=1024",
            );
        }
        if !(self.contact_shell_m > 0.0 && self.contact_shell_m <= 0.5) {
            return err(
                "contact_shell_m",
                f64::from(self.contact_shell_m),
                "must be in (0, 0.5] metres",
            );
        }
        if !(1..=64).contains(&self.far_every) {
            return err(
                "far_every",
                f64::from(self.far_every),
                "must be 1..=64 (1: every object every step)",
            );
        }
        if !(self.far_beyond_m.is_finite() && self.far_beyond_m >= 0.0) {
            return err(
                "far_beyond_m",
                f64::from(self.far_beyond_m),
                "must be a finite distance >= 0 metres",
            );
        }
        if self.far_travel_m.is_nan() || self.far_travel_m <= 0.0 {
            return err(
                "far_travel_m",
                f64::from(self.far_travel_m),
                "must be > 0 metres, or inf for no bound",
            );
        }
        if !(0.0..=0.05).contains(&self.recovery_stride_m) {
            return err(
                "recovery_stride_m",
                f64::from(self.recovery_stride_m),
                "must be in [0, 0.05] metres (0: every displaced blade recovers every step)",
            );
        }
        if !(self.memory_limit_gib.is_finite() && self.memory_limit_gib > 0.0) {
            return err(
                "memory_limit_gib",
                f64::from(self.memory_limit_gib),
                "must be a finite number > 0",
            );
        }
        Ok(())
    }
}

/// Checks a time step: finite and > 0.
pub fn check_dt(dt: f32) -> Result<(), SimError> {
    if dt.is_finite() && dt > 0.0 && dt <= 10.0 {
        Ok(())
    } else {
        Err(SimError {
            key: "dt_s",
            value: fmt(f64::from(dt)),
            allowed: "must be a finite number of seconds in (0, 10]",
        })
    }
}

fn fmt(v: f64) -> String {
    if v.fract() == 0.0 && v.is_finite() && v.abs() < 1e15 {
        format!("{v:.0}")
    } else {
        // Values come from f32 fields: print them as the file wrote them.
        format!("{}", v as f32)
    }
}
