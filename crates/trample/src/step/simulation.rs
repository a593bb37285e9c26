//! The simulation state and `Simulation::step` (DESIGN §7).

use super::blade_class::BladeClass;
use super::body::{Body, BodyId};
use super::params::{SimError, SimParams, check_dt};
use super::passes::{Pass, plan_passes_with};
use super::stages;
use super::timings::StepTimings;
use crate::camera::{Camera, CameraView};
use crate::field::{Field, LodParams};
use crate::force::propagation::NO_GENERATION;
use glam::{Vec3, Vec3A};
use std::time::Instant;

/// Reusable per-blade and per-cell work memory of a step.
#[derive(Clone, Debug, Default)]
pub(crate) struct Scratch {
    /// The recovery's work slots (`recover`), kept from step to step: a
    /// slot is loaded before it is read, so the memory is not cleared (a
    /// crowd's trails keep ~15 MB of it in use a step).
    pub recover_work: Vec<Vec3A>,
    /// Force on each blade this sub-step (world, m/s); ZERO outside `touched`.
    pub force: Vec<Vec3>,
    /// Contact weight of each blade this sub-step: the sum over objects and
    /// segments of the segments' weights ([`crate::collision::contact_blade`]);
    /// Eq. 5's `num` (DESIGN §6) and how firmly an object holds the blade
    /// (recovery waits while it is ≥ 1). 0 outside `touched`.
    pub weight: Vec<f32>,
    /// The largest weight of one object on each blade this sub-step (which
    /// object's track settings the blade follows); 0 outside `touched`.
    pub owner_weight: Vec<f32>,
    /// Per blade, bit `k`: segment `k` touched some object this sub-step
    /// (the contact response starts at the lowest); 0 outside `touched`.
    pub mask: Vec<u32>,
    /// Blades whose `force`/`weight`/`generation` were set in the latest sub-step.
    pub touched: Vec<u32>,
    /// Blades away from rest (recovered each step): ascending up to
    /// `displaced_sorted`, then the blades appended since
    /// ([`super::stages::mark_displaced`]). Recovery, which walks the set,
    /// puts it in order first ([`Scratch::sort_displaced`]); with tracks
    /// that last (no recovery) nothing walks it, and nothing sorts it.
    pub displaced: Vec<u32>,
    /// How many of `displaced`'s first blades are in order (the rest were
    /// appended since): what [`Scratch::sort_displaced`] merges into.
    pub displaced_sorted: usize,
    /// `displaced` as a flag per blade.
    pub displaced_flag: Vec<bool>,
    /// Slow blades recover in strides (`SimParams::recovery_stride_m` > 0;
    /// empty otherwise): per blade, its clock `[owed, wait]` — the
    /// recovery time it owes since it was last relaxed, and how much it
    /// must owe before it is relaxed again
    /// ([`crate::recovery::stride_wait`]), seconds ([`super::recover`]).
    /// `[0, 0]` for a blade at rest and for one an object just moved
    /// ([`super::stages::mark_displaced`]): relaxed at the next step. One
    /// pair a blade, as the GPU path's `vec2` clock: the two are read
    /// together.
    pub recover_clock: Vec<[f32; 2]>,
    /// Cells whose billboard slope is away from rest: ascending up to
    /// `bent_sorted`, then the cells bent since. Put in order
    /// ([`Scratch::sort_bent`]) where the set is filtered: in the paper's
    /// mode's recovery, and when a cell came back to rest.
    pub bent_cells: Vec<u32>,
    /// How many of `bent_cells`' first cells are in order.
    pub bent_sorted: usize,
    /// `bent_cells` as a flag per cell.
    pub bent_flag: Vec<bool>,
    /// Blades the step's far passes moved, whose cells follow them after
    /// the step's last pass ([`super::stages::far_cells`]).
    pub far_changed: Vec<u32>,
    /// The cells whose level of detail changed in the latest sub-step
    /// ([`crate::field::classify_cells`]), kept so that its memory is
    /// reused.
    pub lod_changes: Vec<crate::field::LodChange>,
}

impl Scratch {
    /// Puts the displaced blades in order: those appended since the last
    /// time merged into the ordered ones ([`super::stages::merge_appended`]),
    /// without a pass over the whole set (it holds the lasting track).
    pub(crate) fn sort_displaced(&mut self) {
        super::stages::merge_appended(&mut self.displaced, self.displaced_sorted);
        self.displaced_sorted = self.displaced.len();
    }

    /// Puts the bent cells in order, as [`Scratch::sort_displaced`] the
    /// displaced blades.
    pub(crate) fn sort_bent(&mut self) {
        super::stages::merge_appended(&mut self.bent_cells, self.bent_sorted);
        self.bent_sorted = self.bent_cells.len();
    }

    /// Keeps the bent cells for which `keep(cell, its flag)` is true, in
    /// order (put in order first), and clears the flags of the others: the
    /// one way cells leave the set.
    pub(crate) fn retain_bent(&mut self, mut keep: impl FnMut(usize, bool) -> bool) {
        self.sort_bent();
        let flags = &mut self.bent_flag;
        self.bent_cells.retain(|&c| {
            let c = c as usize;
            let kept = keep(c, flags[c]);
            flags[c] &= kept;
            kept
        });
        self.bent_sorted = self.bent_cells.len();
    }
}

/// A grass field, the objects moving through it, and the camera whose eye
/// sets the level of detail.
#[derive(Clone, Debug)]
pub struct Simulation {
    /// The field (blades, cells, terrain).
    pub field: Field,
    /// The objects.
    pub bodies: Vec<Body>,
    /// The scene's camera (its eye is the LOD viewpoint unless a host view
    /// is set: [`Simulation::set_view`]).
    pub camera: Camera,
    /// LOD distances.
    pub lod: LodParams,
    /// Method parameters.
    pub params: SimParams,
    /// Simulated time, seconds.
    pub time: f64,
    /// Steps taken.
    pub frame: u64,
    /// Per blade: what happened to it over the whole run.
    pub class: Vec<BladeClass>,
    /// Per blade: generation in the latest sub-step (0 = DBG, 1.. = PBG,
    /// `NO_GENERATION` = untouched), for debug views.
    pub generation: Vec<u8>,
    /// Per patch: inside the view frustum at the end of the last step.
    pub visible: Vec<bool>,
    /// The scene's camera at the end of the last step (see
    /// [`Simulation::eye`] and [`Simulation::view_proj`] for the camera in
    /// charge, which may be the host's).
    pub view: CameraView,
    /// Timers and counts of the last step.
    pub timings: StepTimings,
    /// Steps so far in which an object needed more sub-steps than
    /// `params.max_substeps` allows (and may have skipped blades).
    pub substep_clamps: u64,
    /// The first of those steps, for a one-time warning.
    pub first_substep_clamp: Option<SubstepClamp>,
    /// Wind drawn over the grass by renderers (DESIGN §6): not part of the
    /// simulation state, which shows the interaction alone. Default: calm.
    pub wind: crate::wind::WindParams,
    /// Per blade: whose track settings its recovery follows (ours, DESIGN
    /// §6): 1 + the index of the body that last pressed it firmly (a contact
    /// weight of at least [`super::stages::DBG_WEIGHT`]; blades reached by
    /// propagation inherit from the blade that pushed them), or 0 for
    /// `[sim]`'s `recovery_s` and `trail` (also for bodies past index 254).
    pub track_owner: Vec<u8>,
    pub(crate) scratch: Scratch,
    /// Which patches recover this step, and over how long (far ones in
    /// turns with `params.far_every > 1`; [`Simulation::recovery_scale`]).
    pub(crate) recovery_turns: super::recovery_turns::RecoveryTurns,
    /// The host's camera, in charge of LOD and culling when set.
    pub(crate) host_view: Option<super::view::HostView>,
    /// The memory the field needs at most, bytes, as its builder
    /// estimated it before building
    /// ([`crate::builder::SimulationBuilder::memory_estimate_bytes`]: the
    /// blades the grass maps let grow, the strides' clock); `None` for a
    /// simulation assembled with [`Simulation::new`] alone.
    pub memory_estimate_bytes: Option<u64>,
    /// The id the next added body gets.
    pub(crate) next_body_id: u32,
}

/// A step in which an object moved too far for `sim.max_substeps` (DESIGN
/// §9, ours). The step ran with `max_substeps` sub-steps: each moved the
/// object `needed / max_substeps` times its own thickness, so it may have
/// skipped blades. The step is not refused — a real-time loop must go on —
/// but it is counted ([`Simulation::substep_clamps`]) and the first one is
/// kept ([`Simulation::first_substep_clamp`]) so that tools warn once (the
/// CLI prints it and writes the count to `summary.json`).
#[derive(Clone, Debug, PartialEq)]
pub struct SubstepClamp {
    /// Frame index of the step (0 = the first step).
    pub frame: u64,
    /// Simulated time at the start of the step, seconds.
    pub time_s: f64,
    /// Name of the object that needed the most sub-steps.
    pub object: String,
    /// Sub-steps it needed.
    pub needed: u32,
    /// Sub-steps run (`sim.max_substeps`).
    pub max_substeps: u32,
}

impl std::fmt::Display for SubstepClamp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "frame {} (t = {:.3} s): object \"{}\" moves {} times its own thickness in one step but sim.max_substeps = {}; it may skip blades (raise sim.max_substeps or lower dt)",
            self.frame, self.time_s, self.object, self.needed, self.max_substeps
        )
    }
}

impl Simulation {
    /// Assembles a simulation at time 0; the bodies get ids 0, 1, ... in
    /// order. Parameters must already be valid: this does not check them
    /// ([`crate::builder::SimulationBuilder::build`] does, then calls it).
    #[must_use]
    pub fn new(
        field: Field,
        bodies: Vec<Body>,
        camera: Camera,
        lod: LodParams,
        params: SimParams,
    ) -> Self {
        let blades = field.blades.count;
        let cells = field.layout.cell_count();
        let mut bodies = bodies;
        for (i, body) in bodies.iter_mut().enumerate() {
            body.id = BodyId(i as u32);
        }
        let next_body_id = bodies.len() as u32;
        let positions: Vec<Vec3> = bodies.iter().map(|b| b.pose.position).collect();
        let view = camera.view_at(0.0, &positions);
        let mut sim = Self {
            field,
            bodies,
            camera,
            lod,
            params,
            time: 0.0,
            frame: 0,
            class: vec![BladeClass::Untouched; blades],
            generation: vec![NO_GENERATION; blades],
            visible: Vec::new(),
            view,
            timings: StepTimings::default(),
            substep_clamps: 0,
            first_substep_clamp: None,
            wind: crate::wind::WindParams::default(),
            track_owner: vec![0; blades],
            scratch: Scratch {
                // Zeroed pages from the allocator, not written: a step
                // touches the forces of the blades it lists only, so the
                // rest of the field's never take memory (0.2 GB on the
                // 16.8 M-blade herd; `vec!` would write every one).
                force: bytemuck::zeroed_vec(blades),
                weight: vec![0.0; blades],
                owner_weight: vec![0.0; blades],
                mask: vec![0; blades],
                displaced_flag: vec![false; blades],
                bent_flag: vec![false; cells],
                ..Scratch::default()
            },
            recovery_turns: super::recovery_turns::RecoveryTurns::default(),
            host_view: None,
            memory_estimate_bytes: None,
            next_body_id,
        };
        // Levels of detail and culling for the starting viewpoint, so a
        // simulation that is drawn before its first step shows the right thing.
        sim.classify_at_rest();
        sim.cull();
        sim
    }

    /// Advances the simulation by `dt` seconds: poses → LOD and culling →
    /// broad phase → narrow phase → DBG forces (Eq. 2) → propagation (Eq. 4)
    /// → deformation (Eq. 5–8) → transitions (Eq. 9–13) → recovery. A fast
    /// object is sub-stepped so it cannot skip blades (DESIGN §9), up to
    /// `params.max_substeps`; beyond, the step is taken with that many and
    /// recorded as a [`SubstepClamp`].
    pub fn step(&mut self, dt: f32) -> Result<&StepTimings, SimError> {
        let start = Instant::now();
        let mut tm = StepTimings::default();
        let t_pose = Instant::now();
        let passes = self.begin_step(dt)?;
        tm.poses_ms += ms(t_pose);
        (tm.substeps, tm.substeps_needed) = super::passes::near_substeps(&passes);
        tm.far_bodies = super::passes::far_bodies(&passes);
        // The sub-steps run on one of the pool's threads (rayon::scope): each
        // stage's parallel loop then forks from a worker, not from outside
        // the pool (a wake-up and a blocking wait per loop, a dozen a
        // sub-step: measured 10 % of the default scene's step).
        rayon::scope(|_| {
            for pass in &passes {
                let h = pass.h();
                for i in 1..=pass.plan.substeps {
                    stages::substep(self, pass, pass.substep_time(i), h, &mut tm);
                }
            }
            stages::far_cells(self, &mut tm);
        });
        let t_cull = Instant::now();
        tm.visible_patches = self.end_step(dt);
        tm.lod_ms += ms(t_cull);
        tm.displaced_blades = self.scratch.displaced.len() as u32;
        tm.total_ms = ms(start);
        self.timings = tm;
        Ok(&self.timings)
    }

    /// The start of a step of `dt` seconds, shared by the CPU path
    /// ([`Simulation::step`]) and the GPU path (STYLE rule 9: the loop both
    /// run is written once): checks `dt`, plans the step's passes over the
    /// bodies ([`super::passes::plan_passes`]: the main pass, then a pass
    /// per group of near bodies that need more sub-steps than it, then a far
    /// pass per group of far bodies due this step when `sim.far_every > 1`,
    /// each far body keeping its turn until its speed changes,
    /// [`super::passes::far_schedule`]; and, likewise, which far patches'
    /// blades recover this step, [`super::recovery_turns`])
    /// and each pass's sub-steps (the most its bodies need, each body's
    /// found once: `stages::body_substeps`), forgets the
    /// blades and cells the last step changed, and, when a pass's plan is
    /// clamped, counts it ([`Simulation::substep_clamps`]) and keeps the
    /// first ([`Simulation::first_substep_clamp`]). Run each pass's
    /// sub-steps `1 ..= pass.plan.substeps`, ending at
    /// [`Pass::substep_time`], in order, then [`Simulation::end_step`].
    ///
    /// # Errors
    /// [`SimError`] for a `dt` that is not a finite number of seconds in (0, 10].
    pub fn begin_step(&mut self, dt: f32) -> Result<Vec<Pass>, SimError> {
        check_dt(dt)?;
        self.field.clear_changes();
        // One far rule for the bodies' turns and the patches'.
        let rule = super::far_rule::FarRule::of(self);
        let schedule = super::passes::far_schedule_with(self, &rule);
        let turns: Vec<Option<u32>> = schedule.iter().map(|s| s.map(|s| s.turn)).collect();
        let passes = plan_passes_with(self, dt, &turns);
        for (body, s) in self.bodies.iter_mut().zip(schedule) {
            body.far_turn = s;
        }
        self.recovery_turns.plan(
            &self.field.layout,
            &rule,
            self.params.far_every,
            self.frame,
            self.time,
            dt,
        );
        for pass in &passes {
            let plan = pass.plan;
            if plan.needed > plan.substeps {
                self.substep_clamps += 1;
                if self.first_substep_clamp.is_none() {
                    self.first_substep_clamp = Some(SubstepClamp {
                        frame: self.frame,
                        time_s: self.time,
                        object: plan
                            .fastest
                            .map(|i| self.bodies[i].object.name.clone())
                            .unwrap_or_default(),
                        needed: plan.needed,
                        max_substeps: plan.substeps,
                    });
                }
            }
        }
        let end = self.time + f64::from(dt);
        for (i, body) in self.bodies.iter_mut().enumerate() {
            if passes.iter().any(|p| p.has(i)) {
                body.stepped_to = end;
            }
        }
        Ok(passes)
    }

    /// The end of a step of `dt` seconds (see [`Simulation::begin_step`]):
    /// time and frame advance, the sets of changed blades and cells are
    /// sorted ([`Simulation::changed_blades`]), and the patches are culled
    /// for the camera in charge ([`Simulation::cull`]). Returns how many
    /// patches are visible.
    pub fn end_step(&mut self, dt: f32) -> u32 {
        self.time += f64::from(dt);
        self.frame += 1;
        self.field.sort_changes();
        self.cull()
    }

    /// Runs `frames` steps of the scene's `dt`.
    pub fn run(&mut self, frames: u64) -> Result<(), SimError> {
        for _ in 0..frames {
            self.step(self.params.dt_s)?;
        }
        Ok(())
    }

    /// Every blade's vertices in storage order, blade-major: `(blades, n+1, 3)`
    /// float32 (the `--dump-blades` layout).
    #[must_use]
    pub fn blade_vertices(&self) -> Vec<f32> {
        let bl = &self.field.blades;
        let mut out = Vec::with_capacity(bl.count * (bl.segments + 1) * 3);
        for b in 0..bl.count {
            for k in 0..=bl.segments {
                out.extend_from_slice(&bl.vertex(b, k).to_array());
            }
        }
        out
    }

    /// Number of blades not at their rest shape (bit for bit) now.
    ///
    /// Counts the displaced set ([`Simulation::rescan_displaced`] rebuilds
    /// it from the field): only blades the step really moved enter it, and
    /// recovery removes them once they are exactly at rest again.
    #[must_use]
    pub fn blades_away_from_rest(&self) -> usize {
        let bl = &self.field.blades;
        self.scratch
            .displaced
            .iter()
            .filter(|&&b| !bl.is_at_rest(b as usize))
            .count()
    }

    /// Per patch, in storage order, this step's recovery time as a multiple
    /// of each sub-step's `h` ([`super::recovery_turns`]: 1 near the
    /// camera, 0 for a far patch waiting for its turn, on its turn the time
    /// it owes over the step); `None` when every patch recovers every step
    /// (`params.far_every = 1`, or no patch far). Planned by
    /// [`Simulation::begin_step`].
    #[must_use]
    pub fn recovery_scale(&self) -> Option<&[f32]> {
        self.recovery_turns.scale()
    }

    /// The recovery parameters of a blade whose [`Simulation::track_owner`]
    /// is `owner` (DESIGN §6): the body's `track` settings where it has them,
    /// `[sim]`'s otherwise.
    #[must_use]
    pub fn recovery_params(&self, owner: u8) -> crate::recovery::RecoveryParams {
        let track = (owner as usize)
            .checked_sub(1)
            .and_then(|i| self.bodies.get(i))
            .map(|b| b.object.track)
            .unwrap_or_default();
        crate::recovery::RecoveryParams {
            recovery_s: track.recovery_s.unwrap_or(self.params.recovery_s),
            trail: track.trail.unwrap_or(self.params.trail),
        }
    }
}

/// Milliseconds since `t`.
pub(crate) fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}
