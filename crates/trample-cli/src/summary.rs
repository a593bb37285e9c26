//! `summary.json`: what a run did and how long each part took.

use serde::Serialize;
use std::collections::BTreeMap;
use trample::StepTimings;
use trample::scene::Scene;
use trample::step::{BladeClass, Simulation};

/// min / median / mean / 90th and 99th percentiles / max of a series,
/// milliseconds. The percentiles are nearest-rank (the smallest value with
/// at least that share of the series at or below it): what a frame-time
/// budget cares about, where a median hides the hitches.
#[derive(Serialize, Debug, Default, Clone, Copy)]
pub struct Stats {
    pub min: f64,
    pub median: f64,
    pub mean: f64,
    pub p90: f64,
    pub p99: f64,
    pub max: f64,
}

impl Stats {
    /// Statistics of `v` (all zero when empty).
    pub fn of(v: &[f64]) -> Self {
        if v.is_empty() {
            return Self::default();
        }
        let mut s = v.to_vec();
        s.sort_by(f64::total_cmp);
        let median = if s.len() % 2 == 1 {
            s[s.len() / 2]
        } else {
            0.5 * (s[s.len() / 2 - 1] + s[s.len() / 2])
        };
        // Nearest rank: the ⌈p·n⌉-th smallest, in integers (90·n / 100).
        let rank = |percent: usize| s[(percent * s.len()).div_ceil(100).max(1) - 1];
        Self {
            min: s[0],
            median,
            mean: s.iter().sum::<f64>() / s.len() as f64,
            p90: rank(90),
            p99: rank(99),
            max: s[s.len() - 1],
        }
    }
}

/// Collects every step's timings.
#[derive(Default)]
pub struct Recorder {
    pub steps: Vec<StepTimings>,
}

impl Recorder {
    /// Step times, milliseconds.
    pub fn step_ms(&self) -> Stats {
        Stats::of(&self.steps.iter().map(|t| t.total_ms).collect::<Vec<_>>())
    }

    /// Median of each stage, milliseconds, by stage name.
    pub fn stages_ms(&self) -> BTreeMap<&'static str, f64> {
        let mut out = BTreeMap::new();
        if let Some(first) = self.steps.first() {
            for (i, (name, _)) in first.stages().iter().enumerate() {
                let v: Vec<f64> = self.steps.iter().map(|t| t.stages()[i].1).collect();
                out.insert(*name, Stats::of(&v).median);
            }
        }
        out
    }
}

/// The steps of one phase of the far objects' turns (`far_every` above 1):
/// those whose frame modulo `far_every` is `phase`, so the far objects of
/// one turn (`trample::step::passes::far_schedule`). Turns that carry
/// unlike work show here as phases whose step times differ: the hitches a
/// frame budget sees in `step_ms.p90`.
#[derive(Serialize, Debug, Clone)]
pub struct FarPhase {
    /// `frame % far_every` of its steps.
    pub phase: u32,
    /// How many steps of the run it holds.
    pub steps: usize,
    /// Their step times, milliseconds.
    pub step_ms: Stats,
    /// Bodies its steps stepped in far passes, on average.
    pub far_bodies_mean: f64,
    /// Blades its steps' narrow phases tested, on average (the CPU path;
    /// 0 on the GPU path).
    pub narrow_candidates_mean: f64,
    /// Blades its steps' contact responses moved, on average (the CPU
    /// path; 0 on the GPU path).
    pub contact_blades_mean: f64,
}

/// The mean over `steps` of a count each step keeps (0 with no step).
fn mean_count<'a>(
    steps: impl ExactSizeIterator<Item = &'a StepTimings>,
    count: fn(&StepTimings) -> u32,
) -> f64 {
    let n = steps.len().max(1);
    steps.map(|t| f64::from(count(t))).sum::<f64>() / n as f64
}

/// The phases of the far turns of the steps `steps` (the run's, from frame
/// 0) with `far_every`: one per phase, in order; none with `far_every` ≤ 1.
pub fn far_phases(steps: &[StepTimings], far_every: u32) -> Vec<FarPhase> {
    if far_every <= 1 {
        return Vec::new();
    }
    (0..far_every)
        .map(|phase| {
            let of: Vec<&StepTimings> = steps
                .iter()
                .skip(phase as usize)
                .step_by(far_every as usize)
                .collect();
            let mean = |count| mean_count(of.iter().copied(), count);
            FarPhase {
                phase,
                steps: of.len(),
                step_ms: Stats::of(&of.iter().map(|t| t.total_ms).collect::<Vec<_>>()),
                far_bodies_mean: mean(|t| t.far_bodies),
                narrow_candidates_mean: mean(|t| t.narrow_candidates),
                contact_blades_mean: mean(|t| t.contact_blades),
            }
        })
        .collect()
}

/// What `simulate` writes to `summary.json` (and `run` writes with its render
/// times added): the run's size, step times and what the objects touched.
#[derive(Serialize)]
pub struct SimSummary {
    pub scene: String,
    pub blades: usize,
    pub segments: usize,
    pub frames: u64,
    pub precision: u32,
    pub dt_s: f32,
    pub backend: &'static str,
    /// The GPU adapter of the GPU path (`--backend`), absent on the CPU path.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adapter: Option<String>,
    pub threads: usize,
    pub simulated_s: f64,
    pub build_ms: f64,
    pub wall_s: f64,
    pub step_ms: Stats,
    pub stages_ms: BTreeMap<&'static str, f64>,
    /// How `stages_ms` were measured: `"wall"`, a clock around each stage
    /// (the CPU path; the GPU path's profiling mode on a device without
    /// timestamp queries, where each stage is submitted and waited for on
    /// its own); `"timestamp"`, GPU timestamp queries between the stages,
    /// read back once per step; `"none"`, not measured (`run` on the GPU
    /// path: the stages read 0).
    pub stage_timing: &'static str,
    pub dbg_blades: u32,
    pub pbg_blades: u32,
    pub generations: u32,
    pub displaced_blades: u32,
    pub lod_cells: trample::field::LodCounts,
    pub classes: BTreeMap<&'static str, usize>,
    /// `sim.far_every`: far objects touch the grass every this many steps
    /// (1: every object every step).
    pub far_every: u32,
    /// `sim.far_outside_view`: objects out of the camera's view take turns
    /// too (with `far_every` above 1).
    pub far_outside_view: bool,
    /// Bodies stepped in far passes a step, on average over the run (0
    /// with `far_every = 1`).
    pub far_bodies_mean: f64,
    /// With `far_every` above 1, the steps of each phase of the far
    /// objects' turns ([`FarPhase`]: whether the turns carry like work);
    /// empty otherwise.
    pub far_turns: Vec<FarPhase>,
    /// Sub-steps a step was split into near the camera, on average over
    /// the run: the most its main pass or a near pass of faster objects
    /// took (DESIGN §9; each object near the camera is sub-stepped for its
    /// own speed, `trample::step::passes`).
    pub substeps_mean: f64,
    /// Tiles a step whose narrow phase objects at rest took from what they
    /// kept (`sim.reuse_at_rest`), on average over the run.
    pub reused_tiles_mean: f64,
    /// Blades a step the contact response of objects at rest left without
    /// a query, on average over the run.
    pub reused_blades_mean: f64,
    /// Steps in which an object needed more than `sim.max_substeps` sub-steps.
    pub substeps_clamped_steps: u64,
    /// The first such step, in words (null when none).
    pub first_substep_clamp: Option<String>,
    /// Memory estimate of the field before the run, MiB.
    pub memory_estimate_mib: f64,
    /// Peak resident memory of the process (Linux `VmHWM`), MiB; null elsewhere.
    pub peak_rss_mib: Option<f64>,
}

impl SimSummary {
    /// The summary of `sim` after `frames` steps recorded in `rec`.
    pub fn new(
        scene: &Scene,
        sim: &Simulation,
        frames: u64,
        threads: usize,
        build_ms: f64,
        wall_s: f64,
        rec: &Recorder,
    ) -> Self {
        let count = |c: BladeClass| sim.class.iter().filter(|&&x| x == c).count();
        let last = rec.steps.last().cloned().unwrap_or_default();
        let mean = |count| mean_count(rec.steps.iter(), count);
        Self {
            scene: scene.source.clone(),
            blades: sim.field.blades.count,
            segments: sim.field.blades.segments,
            frames,
            precision: sim.params.precision,
            dt_s: sim.params.dt_s,
            backend: "cpu",
            adapter: None,
            threads,
            simulated_s: sim.time,
            build_ms,
            wall_s,
            step_ms: rec.step_ms(),
            stages_ms: rec.stages_ms(),
            // The CPU path's clocks; the GPU path's callers say theirs.
            stage_timing: "wall",
            dbg_blades: last.dbg_blades,
            pbg_blades: last.pbg_blades,
            generations: last.generations,
            displaced_blades: last.displaced_blades,
            lod_cells: sim.timings.lod,
            classes: BTreeMap::from([
                ("untouched", count(BladeClass::Untouched)),
                ("direct", count(BladeClass::Direct)),
                ("propagated", count(BladeClass::Propagated)),
            ]),
            far_every: sim.params.far_every,
            far_outside_view: sim.params.far_outside_view,
            far_bodies_mean: mean(|t| t.far_bodies),
            far_turns: far_phases(&rec.steps, sim.params.far_every),
            substeps_mean: mean(|t| t.substeps),
            reused_tiles_mean: mean(|t| t.reused_tiles),
            reused_blades_mean: mean(|t| t.reused_blades),
            substeps_clamped_steps: sim.substep_clamps,
            first_substep_clamp: sim.first_substep_clamp.as_ref().map(ToString::to_string),
            // The estimate the build made (grass maps, the strides' clock);
            // the field's formula for a simulation made without the builder.
            memory_estimate_mib: sim
                .memory_estimate_bytes
                .unwrap_or_else(|| scene.file.field.memory_estimate_bytes())
                as f64
                / 1024f64.powi(2),
            peak_rss_mib: peak_rss_mib(),
        }
    }
}

/// Writes `value` as pretty JSON to `path` atomically (a temporary file
/// beside it, renamed).
pub fn write_json(path: &std::path::Path, value: &impl Serialize) -> anyhow::Result<()> {
    use anyhow::Context;
    let text = serde_json::to_string_pretty(value)?;
    trample::npy::write_atomic(path, text.as_bytes())
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// Peak resident memory of this process, MiB: `VmHWM` of
/// `/proc/self/status` (Linux); `None` where that cannot be read.
pub fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_of_a_series() {
        let s = Stats::of(&[3.0, 1.0, 2.0, 10.0]);
        assert_eq!((s.min, s.median, s.mean, s.max), (1.0, 2.5, 4.0, 10.0));
        assert_eq!(Stats::of(&[5.0]).median, 5.0);
        assert_eq!((s.p90, s.p99), (10.0, 10.0));
        // 1 … 200 ms: nearest rank 180 and 198.
        let v: Vec<f64> = (1..=200).rev().map(f64::from).collect();
        let s = Stats::of(&v);
        assert_eq!((s.min, s.p90, s.p99, s.max), (1.0, 180.0, 198.0, 200.0));
        let s = Stats::of(&[5.0]);
        assert_eq!((s.p90, s.p99), (5.0, 5.0));
    }

    /// Ten steps at `far_every = 4`: phases 0 and 1 hold three steps each
    /// (frames 0, 4, 8 and 1, 5, 9), 2 and 3 two; each phase's figures are
    /// those of its own steps alone.
    #[test]
    fn far_phases_split_the_steps_by_frame_modulo_far_every() {
        let steps: Vec<StepTimings> = (0..10u32)
            .map(|f| StepTimings {
                total_ms: f64::from(f),
                far_bodies: f % 4,
                narrow_candidates: 100 * (f % 4),
                contact_blades: f,
                ..StepTimings::default()
            })
            .collect();
        assert!(far_phases(&steps, 1).is_empty(), "no turns");
        let phases = far_phases(&steps, 4);
        assert_eq!(phases.len(), 4);
        assert_eq!(
            phases
                .iter()
                .map(|p| (p.phase, p.steps))
                .collect::<Vec<_>>(),
            [(0, 3), (1, 3), (2, 2), (3, 2)]
        );
        assert_eq!(phases[0].step_ms.median, 4.0, "frames 0, 4, 8");
        assert_eq!((phases[1].step_ms.min, phases[1].step_ms.max), (1.0, 9.0));
        assert_eq!(phases[3].step_ms.mean, 5.0, "frames 3 and 7");
        for p in &phases {
            assert_eq!(p.far_bodies_mean, f64::from(p.phase));
            assert_eq!(p.narrow_candidates_mean, 100.0 * f64::from(p.phase));
        }
        assert_eq!(phases[2].contact_blades_mean, 4.0, "frames 2 and 6");
        // Fewer steps than phases: the last phases hold none.
        let few = far_phases(&steps[..2], 4);
        assert_eq!(
            few.iter().map(|p| p.steps).collect::<Vec<_>>(),
            [1, 1, 0, 0]
        );
        assert_eq!(few[3].far_bodies_mean, 0.0);
    }

    #[test]
    fn peak_rss_is_read_on_linux() {
        let mib = peak_rss_mib().expect("/proc/self/status has VmHWM");
        assert!(mib > 1.0 && mib < 1e6, "{mib}");
    }
}
