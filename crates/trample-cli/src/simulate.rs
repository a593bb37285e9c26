//! `trample simulate`: run a scene without rendering.

use crate::backend::Backend;
use crate::common::{SimOverrides, load_scene, npy_f32, npy_u8, out_dir, set_threads};
use crate::output::Outputs;
use crate::summary::{Recorder, SimSummary};
use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `trample simulate` (a contract: later tools and checks rely on them).
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML); none = the embedded default scene.
    pub scene: Option<PathBuf>,
    /// Frames to simulate (default: the scene's `[run] frames`, 300). 0 = the rest state.
    #[arg(long)]
    pub frames: Option<u64>,
    /// Time step, seconds (overrides `[sim] dt_s`).
    #[arg(long, allow_negative_numbers = true)]
    pub dt: Option<f32>,
    /// Collision precision, OBB-tree depth 1..=32 (overrides `[sim] precision`).
    #[arg(long)]
    pub precision: Option<u32>,
    /// Worker threads, 1..=1024 (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Largest memory the field may take, GiB (overrides `[sim] memory_limit_gib`).
    #[arg(long, allow_negative_numbers = true)]
    pub memory_limit_gib: Option<f32>,
    /// Step objects far from the camera (beyond `[sim] far_beyond_m`) only
    /// every K-th step, taking turns, each over the time since its last
    /// (overrides `[sim] far_every`; 1 = every object every step).
    #[arg(long, value_name = "K")]
    pub far_every: Option<u32>,
    /// With far objects taking turns (`--far-every` or `[sim] far_every`
    /// above 1), objects out of the camera's view take turns too, however
    /// near (sets `[sim] far_outside_view`).
    #[arg(long)]
    pub far_outside_view: bool,
    /// Output folder for summary.json.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Write every blade's vertices after the last frame: .npy float32 (blades, n+1, 3).
    #[arg(long)]
    pub dump_blades: Option<PathBuf>,
    /// Write each blade's class: .npy uint8 (blades,): 0 untouched, 1 DBG, 2 PBG only.
    #[arg(long)]
    pub dump_classes: Option<PathBuf>,
    /// Write a top-down picture of the track (PNG): green standing, straw
    /// bent, soil flattened; red tint = hit directly, blue = propagation only.
    #[arg(long)]
    pub track_png: Option<PathBuf>,
    /// Simulation path: cpu = the reference (default); auto = the GPU on a
    /// hardware adapter, else the CPU; gpu = the GPU path (also on a
    /// software adapter). Not auto by default: probing for an adapter costs
    /// start-up time and tens of MiB (Mesa's drivers), which would skew the
    /// CPU path's figures (summary.json's times and peak memory).
    #[arg(long, value_enum, default_value_t = Backend::Cpu)]
    pub backend: Backend,
}

/// Runs the subcommand.
pub fn run(a: &Args) -> Result<()> {
    let threads = set_threads(a.threads)?;
    let flags = SimOverrides {
        precision: a.precision,
        dt: a.dt,
        memory_limit_gib: a.memory_limit_gib,
        far_every: a.far_every,
        far_outside_view: a.far_outside_view,
    };
    let scene = load_scene(a.scene.as_deref(), flags)?;
    let out = out_dir(&a.out)?;
    let summary_path = out.join("summary.json");
    let mut paths: Vec<(&str, &std::path::Path)> = vec![("--out", &summary_path)];
    for (flag, p) in [
        ("--dump-blades", &a.dump_blades),
        ("--dump-classes", &a.dump_classes),
        ("--track-png", &a.track_png),
    ] {
        if let Some(p) = p {
            paths.push((flag, p));
        }
    }
    Outputs::preflight(&paths)?;
    let frames = a.frames.unwrap_or(scene.file.run.frames);

    let clock = Instant::now();
    let mut sim = scene.build()?;
    let build_ms = clock.elapsed().as_secs_f64() * 1e3;
    eprintln!(
        "trample: {} — {} blades x {} segments, {} object(s), precision {}, {} thread(s)",
        scene.source,
        sim.field.blades.count,
        sim.field.blades.segments,
        sim.bodies.len(),
        sim.params.precision,
        threads
    );

    let bar = ProgressBar::new(frames);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames, {per_sec}, eta {eta} {msg}")
            .expect("static template"),
    );
    let mut rec = Recorder::default();
    let dt = sim.params.dt_s;
    let gpu = crate::backend::choose(a.backend)?;
    let mut clock = Instant::now();
    let mut adapter = None;
    let mut stage_timing = "wall";
    if let Some(gpu) = &gpu {
        // A scene the GPU path cannot run is the user's choice to make:
        // `gpu` stops, `auto` takes the CPU path. A failure during the run
        // (device lost, out of memory) falls back to the CPU path either way.
        let supported = trample_gpu::GpuSimulation::supports(&gpu.device, &sim);
        if supported.is_ok() {
            bar.suspend(|| crate::backend::note_far_turns(sim.params.far_every));
        }
        match supported {
            Err(e) if a.backend != Backend::Auto => {
                return Err(anyhow::anyhow!("--backend gpu: GPU path: {e}"));
            }
            Err(e) => bar.suspend(|| eprintln!("trample: GPU path: {e}; CPU path")),
            Ok(()) => match crate::gpu_run::simulate_on_gpu(gpu, sim.clone(), frames, &bar) {
                Ok((s, r)) => {
                    (sim, rec) = (s, r);
                    adapter = Some(gpu.adapter_name());
                    // What `GpuSimulation`'s profiling mode used on this device.
                    stage_timing = trample_gpu::StageTiming::for_device(&gpu.device).name();
                }
                Err(e) => {
                    bar.suspend(|| {
                        eprintln!("trample: {e:#}; falling back to the CPU path from frame 0");
                    });
                    bar.reset();
                    clock = Instant::now();
                }
            },
        }
    }
    for _ in 0..if adapter.is_some() { 0 } else { frames } {
        let clamps_before = sim.substep_clamps;
        let t = sim.step(dt)?;
        bar.set_message(format!("DBG {} PBG {}", t.dbg_blades, t.pbg_blades));
        rec.steps.push(t.clone());
        if clamps_before == 0
            && let Some(c) = &sim.first_substep_clamp
        {
            bar.suspend(|| eprintln!("trample: warning: {c}"));
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let wall_s = clock.elapsed().as_secs_f64();

    // Everything is computed and staged before any destination is touched.
    let mut outputs = Outputs::default();
    if let Some(p) = &a.dump_blades {
        let n = sim.field.blades.segments;
        let shape = [sim.field.blades.count, n + 1, 3];
        outputs.stage(p, &npy_f32(&shape, &sim.blade_vertices()))?;
    }
    if let Some(p) = &a.dump_classes {
        let class: Vec<u8> = sim.class.iter().map(|&c| u8::from(c)).collect();
        outputs.stage(p, &npy_u8(&[class.len()], &class))?;
    }
    if let Some(p) = &a.track_png {
        outputs.stage(p, &crate::track::track_png(&sim)?)?;
    }
    let mut summary = SimSummary::new(&scene, &sim, frames, threads, build_ms, wall_s, &rec);
    if adapter.is_some() {
        summary.backend = "gpu";
        summary.adapter = adapter;
        summary.stage_timing = stage_timing;
    }
    outputs.stage(
        &summary_path,
        serde_json::to_string_pretty(&summary)?.as_bytes(),
    )?;
    outputs.commit()?;
    eprintln!(
        "trample: {frames} frames in {wall_s:.2} s; step median {:.3} ms (p90 {:.3}, p99 {:.3}, max {:.3}); {} blades touched ({} DBG, {} PBG only){}{}{}; wrote {}",
        summary.step_ms.median,
        summary.step_ms.p90,
        summary.step_ms.p99,
        summary.step_ms.max,
        summary.classes["direct"] + summary.classes["propagated"],
        summary.classes["direct"],
        summary.classes["propagated"],
        match summary.far_every {
            1 => String::new(),
            k => format!(
                "; far{} objects every {k} steps: {:.1} a step{}",
                if summary.far_outside_view {
                    " and unseen"
                } else {
                    ""
                },
                summary.far_bodies_mean,
                turn_spread(&summary.far_turns)
            ),
        },
        if summary.reused_tiles_mean > 0.0 {
            format!(
                "; objects at rest reused {:.0} tiles and {:.0} blades a step",
                summary.reused_tiles_mean, summary.reused_blades_mean
            )
        } else {
            String::new()
        },
        match sim.substep_clamps {
            0 => String::new(),
            n => format!("; {n} step(s) clamped by sim.max_substeps"),
        },
        summary_path.display()
    );
    Ok(())
}

/// The range of the far turns' median step times, in words (", turns'
/// median steps 17.1–23.9 ms"); empty when a phase has no step.
fn turn_spread(turns: &[crate::summary::FarPhase]) -> String {
    if turns.is_empty() || turns.iter().any(|t| t.steps == 0) {
        return String::new();
    }
    let medians = turns.iter().map(|t| t.step_ms.median);
    let lo = medians.clone().fold(f64::INFINITY, f64::min);
    let hi = medians.fold(f64::NEG_INFINITY, f64::max);
    format!(", turns' median steps {lo:.1}–{hi:.1} ms")
}
