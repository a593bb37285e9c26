//! `trample bench`: the paper's pressure test (Fig. 12) on the simulation
//! alone, collision accuracy against the exact reference, (with
//! `--scaling`) step time against blade and triangle counts, and (with
//! `--objects`) step time against the number of objects.

mod chart;
mod machine;
mod objects;
mod precisions;
mod pressure;
mod scaling;

use crate::common::{SimOverrides, load_scene, out_dir, set_threads};
use anyhow::{Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use trample::Simulation;
use trample::StepTimings;

pub use precisions::parse_precisions;

/// Frames per precision of the pressure test: the paper sampled 5000.
const PRESSURE_FRAMES: u64 = 5000;
/// Frames per point of `--scaling` (5 s of the default scene's 12 s path).
const SCALING_FRAMES: u64 = 300;

/// Which implementation to time.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// The CPU reference path.
    Cpu,
    /// The GPU path (`trample-gpu`) on the adapter of `WGPU_BACKEND`.
    Gpu,
    /// Both, side by side in one run.
    Both,
}

impl Backend {
    /// The flag's spelling.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Cpu => "cpu",
            Self::Gpu => "gpu",
            Self::Both => "both",
        }
    }
}

/// Arguments of `trample bench` (a contract: later tools and checks rely on them).
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML); none = the embedded default scene (the paper's
    /// 262,144-blade field and a rolling ball).
    pub scene: Option<PathBuf>,
    /// Frames per precision (default 5000, as in the paper); with --scaling,
    /// frames per point (default 300).
    #[arg(long)]
    pub frames: Option<u64>,
    /// Precisions to run: a range A..B (inclusive), a number or a comma list
    /// (default 1..7, the paper's; with --scaling, 7).
    #[arg(long)]
    pub precisions: Option<String>,
    /// Which path to time: cpu, gpu (on the adapter of `WGPU_BACKEND`), or
    /// both side by side (also with --scaling).
    #[arg(long, value_enum, default_value_t = Backend::Cpu)]
    pub backend: Backend,
    /// Also render every frame offscreen at --size (on the adapter of
    /// `WGPU_BACKEND`) and report the frame rate of simulation + rendering,
    /// as the paper's Fig. 12 did. On a software driver a 1280x720 frame
    /// takes seconds: use a few --frames.
    #[arg(long)]
    pub render: bool,
    /// With --render: wait for each frame to be drawn but do not read it
    /// back (what an application that presents its frames pays); without
    /// it each frame is also copied to the CPU.
    #[arg(long, requires = "render")]
    pub no_readback: bool,
    /// Image size with --render, WIDTHxHEIGHT (default 1280x720, the paper's
    /// comparison size).
    #[arg(long, default_value = "1280x720", value_parser = crate::common::parse_size)]
    pub size: (u32, u32),
    /// Output folder: bench.json, bench.png, accuracy.png (with --scaling:
    /// scaling.json, scaling_blades.png, scaling_triangles.png; with
    /// --objects: objects.json, objects.png).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Instead of the pressure test: step time against blade count (a larger
    /// and a denser field) and against the object's triangle count.
    #[arg(long)]
    pub scaling: bool,
    /// With --scaling: leave out blade-count points over this many blades
    /// (default: all that fit half of this machine's memory).
    #[arg(long)]
    pub max_blades: Option<u64>,
    /// With --scaling: leave out triangle-count points over this many
    /// triangles (default: all, up to 1,310,720).
    #[arg(long)]
    pub max_triangles: Option<usize>,
    /// Instead of the pressure test: step time against the number of
    /// objects, the scene's first 1, 2, 4, … of them up to all (for
    /// `scenes/herd.toml`: 1 … 128), on --backend (default 300 frames a
    /// point, precision 7).
    #[arg(long, conflicts_with = "scaling")]
    pub objects: bool,
    /// Step objects far from the camera (beyond `[sim] far_beyond_m`) only
    /// every K-th step, taking turns (overrides `[sim] far_every`, for every
    /// run of the bench; 1 = every object every step).
    #[arg(long, value_name = "K")]
    pub far_every: Option<u32>,
    /// With far objects taking turns (`--far-every` or `[sim] far_every`
    /// above 1), objects out of the camera's view take turns too, however
    /// near (sets `[sim] far_outside_view`).
    #[arg(long)]
    pub far_outside_view: bool,
    /// Worker threads, 1..=1024 (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// Runs the subcommand.
pub fn run(a: &Args) -> Result<()> {
    if !a.scaling && (a.max_blades.is_some() || a.max_triangles.is_some()) {
        bail!("--max-blades / --max-triangles: only with --scaling");
    }
    if a.render && (a.scaling || a.objects) {
        bail!("--render: not with --scaling or --objects (they time the simulation alone)");
    }
    let series = a.scaling || a.objects;
    let frames = a.frames.unwrap_or(if series {
        SCALING_FRAMES
    } else {
        PRESSURE_FRAMES
    });
    if frames == 0 {
        bail!("--frames 0: the bench needs at least 1 frame");
    }
    let precisions =
        parse_precisions(
            a.precisions
                .as_deref()
                .unwrap_or(if series { "7" } else { "1..7" }),
        )?;
    let threads = set_threads(a.threads)?;
    let flags = SimOverrides {
        far_every: a.far_every,
        far_outside_view: a.far_outside_view,
        ..SimOverrides::default()
    };
    let scene = load_scene(a.scene.as_deref(), flags)?;
    let out = out_dir(&a.out)?;
    let setup = Setup {
        frames,
        precisions,
        threads,
        out,
        render: a.render.then_some(a.size),
        read_back: !a.no_readback,
        backend: a.backend,
        max_blades: a.max_blades,
        max_triangles: a.max_triangles,
    };
    if a.scaling {
        scaling::run(&scene, &setup)
    } else if a.objects {
        objects::run(&scene, &setup)
    } else {
        pressure::run(&scene, &setup)
    }
}

/// What both modes share.
pub struct Setup {
    /// Frames per precision or per point.
    pub frames: u64,
    /// Precisions, ascending.
    pub precisions: Vec<u32>,
    /// Worker threads.
    pub threads: usize,
    /// Output folder.
    pub out: PathBuf,
    /// Render each frame at this size too (`--render`).
    pub render: Option<(u32, u32)>,
    /// With `render`: read each frame back (not with `--no-readback`).
    pub read_back: bool,
    /// Which paths to time (`--backend`).
    pub backend: Backend,
    /// `--max-blades` (scaling).
    pub max_blades: Option<u64>,
    /// `--max-triangles` (scaling).
    pub max_triangles: Option<usize>,
}

impl Setup {
    /// The backends to time, in order (`cpu` before `gpu`).
    fn backends(&self) -> &'static [&'static str] {
        match self.backend {
            Backend::Cpu => &["cpu"],
            Backend::Gpu => &["gpu"],
            Backend::Both => &["cpu", "gpu"],
        }
    }
}

/// A progress bar over `len` units of work.
fn progress(len: u64) -> ProgressBar {
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {percent:>3}% {msg} [{elapsed}, eta {eta}]")
            .expect("static template"),
    );
    bar
}

/// Simulation time at which every object has finished its path, seconds;
/// `None` when one never does (a circle) or none moves.
fn motion_end_s(sim: &Simulation) -> Option<f32> {
    let mut end: f32 = 0.0;
    for b in &sim.bodies {
        let m = &b.object.motion;
        let path_end = m.path().end_time()?;
        end = end.max(m.start_s() + path_end);
    }
    (end > 0.0).then_some(end)
}

/// Frames of one lap of the predefined path: after this many frames the
/// run starts again from the scene's first frame (laps keep the object
/// moving for the paper's 5000 frames; a 12 s path lasts 720). `None`: no
/// restart (an endless or static path).
fn lap_frames(sim: &Simulation) -> Option<u64> {
    let end = motion_end_s(sim)?;
    let frames = (f64::from(end) / f64::from(sim.params.dt_s)).ceil() as u64;
    (frames > 0).then_some(frames)
}

/// Times `sim` for `frames` frames on `backend` (`cpu`, or `gpu` on
/// `gpu`'s device), advancing `bar` by one a step. `None`, with the reason
/// pushed to `skipped` (`what` names the scene) and `bar` advanced by
/// `frames`, when the GPU path refuses the scene.
fn time_on(
    backend: &str,
    gpu: Option<&trample_render::headless::Gpu>,
    sim: Simulation,
    frames: u64,
    what: &str,
    skipped: &mut Vec<String>,
    bar: &ProgressBar,
) -> Result<Option<crate::summary::Recorder>> {
    let tick = |_: Stepped<'_>, _: &StepTimings| {
        bar.inc(1);
        Ok(())
    };
    let steps = match (backend, gpu) {
        ("gpu", Some(g)) => {
            if let Err(e) = trample_gpu::GpuSimulation::supports(&g.device, &sim) {
                skipped.push(format!("gpu {what}: {e}"));
                bar.inc(frames);
                return Ok(None);
            }
            time_frames_gpu(g, sim, frames, tick)?
        }
        _ => time_frames(sim, frames, tick)?,
    };
    Ok(Some(crate::summary::Recorder { steps }))
}

/// What a bench sees after a step: the simulation on the path that
/// stepped it (to draw it, say).
pub enum Stepped<'a> {
    /// The CPU path's simulation.
    Cpu(&'a Simulation),
    /// The GPU path's (its `sim` is not brought up to date each frame).
    Gpu(&'a mut trample_gpu::GpuSimulation),
}

/// Steps `sim` for `frames` frames of its `dt`, restarting from its
/// first state after every lap (a copy is kept only then), and returns each
/// step's timings. Calls `tick` after each step with the simulation and the
/// step's timings.
fn time_frames(
    mut sim: Simulation,
    frames: u64,
    mut tick: impl FnMut(Stepped<'_>, &StepTimings) -> Result<()>,
) -> Result<Vec<StepTimings>> {
    let lap = lap_frames(&sim).filter(|&l| l < frames);
    let start = lap.map(|_| sim.clone());
    let dt = sim.params.dt_s;
    let mut steps = Vec::with_capacity(frames as usize);
    for i in 0..frames {
        if let (Some(lap), Some(start)) = (lap, &start)
            && i > 0
            && i % lap == 0
        {
            sim.clone_from(start);
        }
        let t = sim.step(dt)?.clone();
        tick(Stepped::Cpu(&sim), &t)?;
        steps.push(t);
    }
    Ok(steps)
}

/// [`time_frames`] on the GPU path: `GpuSimulation::step`, then the step's
/// counters read back (32 bytes; the read-back waits for the GPU, so
/// `total_ms` is the step's GPU time plus that wait). Restarts from the
/// first state after every lap by uploading it again (not timed).
fn time_frames_gpu(
    gpu: &trample_render::headless::Gpu,
    sim: Simulation,
    frames: u64,
    mut tick: impl FnMut(Stepped<'_>, &StepTimings) -> Result<()>,
) -> Result<Vec<StepTimings>> {
    use trample_gpu::GpuSimulation;
    let (device, queue) = (&gpu.device, &gpu.queue);
    GpuSimulation::supports(device, &sim)?;
    let lap = lap_frames(&sim).filter(|&l| l < frames);
    let start = lap.map(|_| sim.clone());
    let dt = sim.params.dt_s;
    let mut g = GpuSimulation::new(device, queue, sim)?;
    let mut steps = Vec::with_capacity(frames as usize);
    for i in 0..frames {
        if let (Some(lap), Some(start)) = (lap, &start)
            && i > 0
            && i % lap == 0
        {
            g = GpuSimulation::new(device, queue, start.clone())?;
        }
        let clock = std::time::Instant::now();
        g.step(device, queue, dt)?;
        g.sync_counters(device, queue)?;
        let mut t = g.sim.timings.clone();
        t.total_ms = clock.elapsed().as_secs_f64() * 1e3;
        tick(Stepped::Gpu(&mut g), &t)?;
        steps.push(t);
    }
    Ok(steps)
}
