//! `trample collide`: hit flags of every blade segment at rest, objects posed at one time.

use crate::backend::Backend;
use crate::common::{SimOverrides, load_scene, npy_f32, npy_u8, set_threads};
use crate::output::Outputs;
use anyhow::{Result, bail};
use std::path::PathBuf;
use trample::step::query::HitMode;

/// Arguments of `trample collide` (a contract).
#[derive(clap::Args, Debug)]
#[command(group = clap::ArgGroup::new("mode").required(true).args(["precision", "exact"]))]
pub struct Args {
    /// Scene file (TOML); none = the embedded default scene.
    pub scene: Option<PathBuf>,
    /// Time at which the objects are posed, seconds.
    #[arg(long, allow_negative_numbers = true)]
    pub time: f32,
    /// OBB-tree depth of the test (root = 1).
    #[arg(long)]
    pub precision: Option<u32>,
    /// Use the exact reference: a segment hits when it crosses a triangle or
    /// lies inside a closed mesh.
    #[arg(long)]
    pub exact: bool,
    /// Output: .npy uint8 (blades, n): 1 where segment k of blade b hits.
    #[arg(long)]
    pub dump_hits: PathBuf,
    /// Output: .npy float32 (blades, n+1, 3): the blades at rest.
    #[arg(long)]
    pub dump_blades: Option<PathBuf>,
    /// Output: .npy float32 (triangles, 3, 3): every object's triangles in world space at TIME.
    #[arg(long)]
    pub dump_object: Option<PathBuf>,
    /// Worker threads, 1..=1024 (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Largest memory the field may take, GiB (overrides `[sim] memory_limit_gib`).
    #[arg(long, allow_negative_numbers = true)]
    pub memory_limit_gib: Option<f32>,
    /// Collision path: cpu = the reference (default, see `simulate
    /// --backend`); auto = the GPU on a hardware adapter, else the CPU;
    /// gpu = the GPU path (also on a software adapter; not with --exact).
    #[arg(long, value_enum, default_value_t = Backend::Cpu)]
    pub backend: Backend,
}

/// Runs the subcommand.
pub fn run(a: &Args) -> Result<()> {
    set_threads(a.threads)?;
    if !a.time.is_finite() {
        bail!("--time {}: must be a finite number of seconds", a.time);
    }
    let mode = match a.precision {
        Some(p) if !(1..=trample::step::params::MAX_PRECISION).contains(&p) => {
            bail!("--precision {p}: must be 1..=32 (the paper uses 1..=7)")
        }
        Some(p) => HitMode::Precision(p),
        None => HitMode::Exact,
    };
    let flags = SimOverrides {
        memory_limit_gib: a.memory_limit_gib,
        ..SimOverrides::default()
    };
    let scene = load_scene(a.scene.as_deref(), flags)?;
    let mut paths: Vec<(&str, &std::path::Path)> = vec![("--dump-hits", &a.dump_hits)];
    for (flag, p) in [
        ("--dump-blades", &a.dump_blades),
        ("--dump-object", &a.dump_object),
    ] {
        if let Some(p) = p {
            paths.push((flag, p));
        }
    }
    Outputs::preflight(&paths)?;
    let sim = scene.build()?;
    let n = sim.field.blades.segments;
    let gpu = match mode {
        HitMode::Exact if a.backend == Backend::Gpu => {
            bail!("--backend gpu: --exact runs on the CPU only (f64 triangle tests)")
        }
        HitMode::Exact => None,
        HitMode::Precision(_) => crate::backend::choose(a.backend)?,
    };
    let hits = match (gpu, mode) {
        (Some(gpu), HitMode::Precision(p)) => {
            match trample_gpu::query::segment_hits_at_rest(&gpu.device, &gpu.queue, &sim, a.time, p)
            {
                Ok(h) => h,
                Err(e) if a.backend == Backend::Auto => {
                    eprintln!("trample: GPU path: {e}; falling back to the CPU path");
                    sim.segment_hits_at_rest(a.time, mode)
                }
                Err(e) => bail!("--backend gpu: {e}"),
            }
        }
        _ => sim.segment_hits_at_rest(a.time, mode),
    };
    let mut outputs = Outputs::default();
    outputs.stage(&a.dump_hits, &npy_u8(&[sim.field.blades.count, n], &hits))?;
    if let Some(p) = &a.dump_blades {
        let shape = [sim.field.blades.count, n + 1, 3];
        outputs.stage(p, &npy_f32(&shape, &sim.blade_vertices()))?;
    }
    if let Some(p) = &a.dump_object {
        let tris = sim.object_triangles_at(a.time);
        let flat: Vec<f32> = tris
            .iter()
            .flat_map(|t| t.iter().flat_map(|v| v.to_array()))
            .collect();
        outputs.stage(p, &npy_f32(&[tris.len(), 3, 3], &flat))?;
    }
    outputs.commit()?;
    let segs = hits.iter().filter(|&&h| h != 0).count();
    let blades = hits.chunks(n).filter(|c| c.iter().any(|&h| h != 0)).count();
    eprintln!(
        "trample: t = {} s, {}: {segs} segments of {blades} blades hit; wrote {}",
        a.time,
        match mode {
            HitMode::Exact => "exact".to_string(),
            HitMode::Precision(p) => format!("precision {p}"),
        },
        a.dump_hits.display()
    );
    Ok(())
}
