//! `trample simulate`: run a scene without rendering.

use crate::common::{load_scene, out_dir, override_sim, set_threads, write_f32, write_u8};
use crate::summary::{Recorder, SimSummary, write_json};
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
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
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
}

/// Runs the subcommand.
pub fn run(a: &Args) -> Result<()> {
    let threads = set_threads(a.threads)?;
    let mut scene = load_scene(a.scene.as_deref())?;
    override_sim(&mut scene, a.precision, a.dt)?;
    let out = out_dir(&a.out)?;
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
    let clock = Instant::now();
    for _ in 0..frames {
        let t = sim.step(dt)?;
        bar.set_message(format!("DBG {} PBG {}", t.dbg_blades, t.pbg_blades));
        rec.steps.push(t.clone());
        bar.inc(1);
    }
    bar.finish_and_clear();
    let wall_s = clock.elapsed().as_secs_f64();

    if let Some(p) = &a.dump_blades {
        let n = sim.field.blades.segments;
        write_f32(
            p,
            &[sim.field.blades.count, n + 1, 3],
            &sim.blade_vertices(),
        )?;
    }
    if let Some(p) = &a.dump_classes {
        write_u8(p, &[sim.class.len()], &sim.class)?;
    }
    if let Some(p) = &a.track_png {
        crate::track::write_track_png(&sim, p)?;
    }
    let summary = SimSummary::new(&scene, &sim, frames, threads, build_ms, wall_s, &rec);
    write_json(&out.join("summary.json"), &summary)?;
    eprintln!(
        "trample: {frames} frames in {wall_s:.2} s; step median {:.3} ms (max {:.3}); {} blades touched ({} DBG, {} PBG only); wrote {}",
        summary.step_ms.median,
        summary.step_ms.max,
        summary.classes["direct"] + summary.classes["propagated"],
        summary.classes["direct"],
        summary.classes["propagated"],
        out.join("summary.json").display()
    );
    Ok(())
}
