//! `trample run`: simulate a scene and render it along its camera path,
//! headless, to PNG frames, an optional GIF and a summary.

use crate::common::{SimOverrides, load_scene, out_dir, set_threads};
use crate::summary::{Recorder, SimSummary, Stats, write_json};
use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;
use trample_render::{DebugView, RenderParams, Renderer};

/// Arguments of `trample run`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML); none = the embedded default scene.
    pub scene: Option<PathBuf>,
    /// Frames to simulate and render (default: the scene's `[run] frames`, 300).
    #[arg(long)]
    pub frames: Option<u64>,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = crate::common::parse_size)]
    pub size: (u32, u32),
    /// Output folder: frame_NNNN.png, run.gif, summary.json.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Render and write every K-th frame as PNG (and into the GIF); every
    /// frame is simulated. Default 5: a software driver renders the default
    /// scene at 1280x720 in seconds per frame; use 1 on a GPU.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..))]
    pub every: u64,
    /// Also write DIR/run.gif (at most 480 pixels wide).
    #[arg(long)]
    pub gif: bool,
    /// Also write DIR/run.mp4 (H.264, full size) through the `ffmpeg` on
    /// the PATH; without one the run stops before it starts.
    #[arg(long)]
    pub mp4: bool,
    /// Debug view: none; classes (DBG red, PBG blue by generation,
    /// billboards yellow, Texture-LOD ground grey); obb (the OBB-tree nodes
    /// at the current precision over the scene); patches (the patch grid).
    #[arg(long, default_value = "none")]
    pub debug_view: DebugView,
    /// Render density: blades drawn per simulated blade near the camera
    /// (1 = the simulated blades alone; default 6, `RenderParams::near_density`).
    /// The simulation is the same; drawing costs more.
    #[arg(long, default_value_t = RenderParams::default().near_density, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub near_density: u32,
    /// Blend band past `lod.geometry_m`, metres: there the blades of
    /// billboard cells thin out while the billboards fade in (0 = the
    /// paper's hard switch; default 4, `RenderParams::lod_blend_m`; at most
    /// half the billboard band).
    #[arg(long, default_value_t = RenderParams::default().lod_blend_m, value_parser = non_negative_metres, allow_negative_numbers = true)]
    pub lod_blend: f32,
    /// Blend band before `lod.billboard_m`, metres: the billboards thin
    /// out over the ground (0 = none; default 6, `RenderParams::texture_blend_m`).
    #[arg(long, default_value_t = RenderParams::default().texture_blend_m, value_parser = non_negative_metres, allow_negative_numbers = true)]
    pub texture_blend: f32,
    /// Shadow strength of the bodies' shadows on the grass, 0..=1 (0 = no
    /// shadow pass; default 1, `RenderParams::shadow_strength`).
    #[arg(long, default_value_t = RenderParams::default().shadow_strength, value_parser = unit_interval, allow_negative_numbers = true)]
    pub shadows: f32,
    /// Ambient-occlusion strength of the grass (0 = none; default 1,
    /// `RenderParams::ambient_occlusion`).
    #[arg(long, default_value_t = RenderParams::default().ambient_occlusion, value_parser = non_negative, allow_negative_numbers = true)]
    pub ambient_occlusion: f32,
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
    /// Simulation path: auto = the GPU on a hardware adapter, else the CPU;
    /// gpu = the GPU path (also on a software adapter); cpu = the reference.
    /// On the GPU path the state is read back for each rendered frame (the
    /// renderer does not draw from the GPU buffers yet).
    #[arg(long, value_enum, default_value_t = crate::backend::Backend::Auto)]
    pub backend: crate::backend::Backend,
}

/// A number `s` that `ok` accepts, or the one-line error clap prints:
/// "`s` is not `what`: expected `expected`".
fn number_where(
    s: &str,
    ok: impl Fn(f32) -> bool,
    what: &str,
    expected: &str,
) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if ok(x) => Ok(x),
        _ => Err(format!("{s:?} is not {what}: expected {expected}")),
    }
}

/// Finite and ≥ 0.
fn finite_non_negative(x: f32) -> bool {
    x.is_finite() && x >= 0.0
}

/// A `--shadows` value: a strength from 0 to 1.
fn unit_interval(s: &str) -> Result<f32, String> {
    let unit = |x: f32| (0.0..=1.0).contains(&x);
    number_where(s, unit, "a strength", "a number from 0 to 1, e.g. 0.8")
}

/// An `--ambient-occlusion` value: a finite strength ≥ 0.
fn non_negative(s: &str) -> Result<f32, String> {
    number_where(
        s,
        finite_non_negative,
        "a strength",
        "a number >= 0, e.g. 1",
    )
}

/// A `--lod-blend`/`--texture-blend` value: a finite distance ≥ 0 metres.
fn non_negative_metres(s: &str) -> Result<f32, String> {
    number_where(s, finite_non_negative, "a distance", "metres >= 0, e.g. 4")
}

/// Frames per second of the rendered frames, each timed over its simulation
/// step + render + read-back (PNG/GIF encoding excluded); `avg` = rendered
/// frames / their summed time.
#[derive(Serialize)]
struct Fps {
    min: f64,
    avg: f64,
    max: f64,
}

#[derive(Serialize)]
struct RunSummary {
    #[serde(flatten)]
    sim: SimSummary,
    adapter: String,
    size: [u32; 2],
    msaa: u32,
    debug_view: String,
    /// Blades drawn per simulated blade near the camera (`--near-density`).
    near_density: u32,
    /// Shadow strength (`--shadows`).
    shadows: f32,
    /// Ambient-occlusion strength (`--ambient-occlusion`).
    ambient_occlusion: f32,
    /// Render + read-back time per rendered frame, ms.
    render_ms: Stats,
    render_ms_per_frame: Vec<f64>,
    fps: Fps,
    pngs_written: usize,
    gif: Option<String>,
    mp4: Option<String>,
}

/// Streams frames into a GIF (written under a temporary name, renamed at the end).
struct GifOut {
    encoder: gif::Encoder<std::io::BufWriter<std::fs::File>>,
    tmp: PathBuf,
    path: PathBuf,
    size: (u32, u32),
    delay_cs: u16,
}

impl GifOut {
    fn new(path: &Path, frame: (u32, u32), delay_s: f64) -> Result<Self> {
        let scale = (480.0 / frame.0 as f64).min(1.0);
        let size = (
            ((frame.0 as f64 * scale).round() as u32).max(1),
            ((frame.1 as f64 * scale).round() as u32).max(1),
        );
        let tmp = path.with_extension("gif.tmp");
        let file = std::fs::File::create(&tmp)
            .with_context(|| format!("{}: cannot write", tmp.display()))?;
        let mut encoder = gif::Encoder::new(
            std::io::BufWriter::new(file),
            size.0 as u16,
            size.1 as u16,
            &[],
        )
        .context("gif: cannot start")?;
        encoder.set_repeat(gif::Repeat::Infinite)?;
        Ok(Self {
            encoder,
            tmp,
            path: path.to_path_buf(),
            size,
            delay_cs: ((delay_s * 100.0).round() as u16).max(2),
        })
    }

    fn push(&mut self, img: &image::RgbaImage) -> Result<()> {
        let small = image::imageops::resize(
            img,
            self.size.0,
            self.size.1,
            image::imageops::FilterType::Triangle,
        );
        let mut rgba = small.into_raw();
        let mut frame =
            gif::Frame::from_rgba_speed(self.size.0 as u16, self.size.1 as u16, &mut rgba, 20);
        frame.delay = self.delay_cs;
        self.encoder
            .write_frame(&frame)
            .context("gif: cannot write frame")
    }

    fn finish(self) -> Result<()> {
        let writer = self.encoder.into_inner().context("gif: cannot finish")?;
        writer
            .into_inner()
            .map_err(|e| e.into_error())
            .and_then(|f| f.sync_all())
            .with_context(|| format!("{}: cannot write", self.tmp.display()))?;
        std::fs::rename(&self.tmp, &self.path)
            .with_context(|| format!("{}: cannot write", self.path.display()))
    }
}

fn write_png(path: &Path, img: &image::RgbaImage) -> Result<()> {
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .context("png: cannot encode")?;
    trample::npy::write_atomic(path, &bytes)
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// Runs the subcommand.
pub fn run(a: &Args) -> Result<()> {
    let threads = set_threads(a.threads)?;
    if a.mp4 {
        // Before the (long) run, not after it.
        crate::mp4::find_ffmpeg()?;
    }
    let flags = SimOverrides {
        precision: a.precision,
        memory_limit_gib: a.memory_limit_gib,
        far_every: a.far_every,
        far_outside_view: a.far_outside_view,
        ..SimOverrides::default()
    };
    let mut scene = load_scene(a.scene.as_deref(), flags)?;
    let (width, height) = a.size;
    // Cull and look with the image's aspect.
    scene.file.camera.aspect = width as f32 / height as f32;
    let out = out_dir(&a.out)?;
    let frames = a.frames.unwrap_or(scene.file.run.frames);

    let clock = Instant::now();
    let mut sim = scene.build()?;
    let build_ms = clock.elapsed().as_secs_f64() * 1e3;

    let gpu = trample_render::headless::create_device()?;
    let adapter = gpu.adapter_name();
    let samples = gpu.msaa(4);
    let params = RenderParams {
        width,
        height,
        samples,
        debug: a.debug_view,
        near_density: a.near_density,
        lod_blend_m: a.lod_blend,
        texture_blend_m: a.texture_blend,
        shadow_strength: a.shadows.clamp(0.0, 1.0),
        ambient_occlusion: a.ambient_occlusion.max(0.0),
        ..RenderParams::default()
    };
    eprintln!(
        "trample: {} — {} blades x {} segments, {} object(s), precision {}, {} thread(s); rendering {width}x{height} on {adapter}, MSAA {samples}x",
        scene.source,
        sim.field.blades.count,
        sim.field.blades.segments,
        sim.bodies.len(),
        sim.params.precision,
        threads
    );
    if frames == 0 {
        bail!(
            "--frames 0: nothing to render (use `trample simulate --frames 0` for the rest state)"
        );
    }

    let dt = sim.params.dt_s;
    let mut mp4 = if a.mp4 {
        Some(crate::mp4::Mp4Out::new(
            &out.join("run.mp4"),
            a.size,
            1.0 / (f64::from(dt) * a.every as f64),
        )?)
    } else {
        None
    };
    let mut on_gpu = if crate::backend::simulate_on(a.backend, &gpu) {
        match trample_gpu::GpuSimulation::supports(&gpu.device, &sim) {
            Ok(()) => {
                crate::backend::note_far_turns(sim.params.far_every);
                Some(trample_gpu::GpuSimulation::new(
                    &gpu.device,
                    &gpu.queue,
                    sim.clone(),
                )?)
            }
            Err(e) if a.backend == crate::backend::Backend::Auto => {
                eprintln!("trample: GPU path: {e}; simulating on the CPU path");
                None
            }
            Err(e) => bail!("--backend gpu: {e}"),
        }
    } else {
        None
    };
    // The GPU path is drawn straight from its buffers: no field read-back.
    let mut renderer = match &on_gpu {
        Some(g) => Renderer::new_gpu(&gpu.device, &gpu.queue, g, params)?,
        None => Renderer::new(&gpu.device, &gpu.queue, &sim, params)?,
    };
    let mut gif = if a.gif {
        Some(GifOut::new(
            &out.join("run.gif"),
            a.size,
            f64::from(dt) * a.every as f64,
        )?)
    } else {
        None
    };
    let bar = ProgressBar::new(frames);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames, {per_sec}, eta {eta} {msg}")
            .expect("static template"),
    );
    let mut rec = Recorder::default();
    let mut render_ms = Vec::with_capacity(frames as usize);
    let mut frame_s = Vec::with_capacity(frames as usize);
    let mut pngs = 0;
    let clock = Instant::now();
    for i in 0..frames {
        let start = Instant::now();
        let t = match on_gpu.as_mut() {
            Some(g) => {
                g.step(&gpu.device, &gpu.queue, dt)?;
                g.sim.timings.clone()
            }
            None => sim.step(dt)?.clone(),
        };
        let msg = format!(
            "step {:.1} ms, DBG {} PBG {}",
            t.total_ms, t.dbg_blades, t.pbg_blades
        );
        rec.steps.push(t);
        // Only the frames that are written are rendered.
        if i % a.every == 0 {
            let r = Instant::now();
            let img = match on_gpu.as_mut() {
                Some(g) => renderer.render_gpu(&gpu.device, &gpu.queue, g)?,
                None => renderer.render(&gpu.device, &gpu.queue, &sim)?,
            };
            render_ms.push(r.elapsed().as_secs_f64() * 1e3);
            frame_s.push(start.elapsed().as_secs_f64());
            bar.set_message(format!(
                "{msg}, render {:.1} ms",
                render_ms[render_ms.len() - 1]
            ));
            write_png(&out.join(format!("frame_{i:04}.png")), &img)?;
            pngs += 1;
            if let Some(g) = gif.as_mut() {
                g.push(&img)?;
            }
            if let Some(m) = mp4.as_mut() {
                m.push(&img)?;
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let wall_s = clock.elapsed().as_secs_f64();
    let backend = if let Some(mut g) = on_gpu {
        g.sync_to_cpu(&gpu.device, &gpu.queue)?;
        sim = g.sim;
        "gpu"
    } else {
        "cpu"
    };
    if let Some(g) = gif {
        g.finish()?;
    }
    if let Some(m) = mp4 {
        m.finish()?;
    }

    let total: f64 = frame_s.iter().sum();
    let fps_of = |s: f64| if s > 0.0 { 1.0 / s } else { 0.0 };
    let mut summary = RunSummary {
        sim: SimSummary::new(&scene, &sim, frames, threads, build_ms, wall_s, &rec),
        adapter: adapter.clone(),
        size: [width, height],
        msaa: samples,
        debug_view: format!("{:?}", a.debug_view).to_lowercase(),
        near_density: a.near_density,
        shadows: a.shadows.clamp(0.0, 1.0),
        ambient_occlusion: a.ambient_occlusion.max(0.0),
        render_ms: Stats::of(&render_ms),
        render_ms_per_frame: render_ms,
        fps: Fps {
            min: fps_of(frame_s.iter().copied().fold(0.0, f64::max)),
            avg: if total > 0.0 {
                frame_s.len() as f64 / total
            } else {
                0.0
            },
            max: fps_of(frame_s.iter().copied().fold(f64::INFINITY, f64::min)),
        },
        pngs_written: pngs,
        gif: a.gif.then(|| "run.gif".to_string()),
        mp4: a.mp4.then(|| "run.mp4".to_string()),
    };
    // The run summary names the adapter itself (`adapter`).
    summary.sim.backend = backend;
    if backend == "gpu" {
        // `run` does not profile the GPU path: its stages read 0.
        summary.sim.stage_timing = "none";
    }
    write_json(&out.join("summary.json"), &summary)?;
    eprintln!(
        "trample: {frames} frames in {wall_s:.2} s on {adapter}; step median {:.2} ms, render median {:.1} ms, {:.1} fps avg; wrote {pngs} PNG(s){} and {}",
        summary.sim.step_ms.median,
        summary.render_ms.median,
        summary.fps.avg,
        match (a.gif, a.mp4) {
            (true, true) => ", run.gif, run.mp4",
            (true, false) => ", run.gif",
            (false, true) => ", run.mp4",
            (false, false) => "",
        },
        out.join("summary.json").display()
    );
    Ok(())
}
