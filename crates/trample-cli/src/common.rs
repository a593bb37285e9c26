//! What the subcommands share: loading a scene with command-line overrides,
//! the worker count, output folders.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use trample::scene::Scene;
use trample::step::SimParams;

/// Loads SCENE, or the embedded default scene when none is given.
pub fn load_scene(path: Option<&Path>) -> Result<Scene> {
    Ok(match path {
        Some(p) => Scene::load(p)?,
        None => Scene::default_scene()?,
    })
}

/// Applies `--precision` and `--dt` to the scene, checking them as flags.
pub fn override_sim(scene: &mut Scene, precision: Option<u32>, dt: Option<f32>) -> Result<()> {
    let mut sim: SimParams = scene.file.sim.clone();
    if let Some(p) = precision {
        sim.precision = p;
        if let Err(e) = sim.validate() {
            bail!("--precision {p}: {}", e.allowed);
        }
    }
    if let Some(dt) = dt {
        sim.dt_s = dt;
        if let Err(e) = trample::step::params::check_dt(dt) {
            bail!("--dt {dt}: {}", e.allowed);
        }
    }
    scene.file.sim = sim;
    Ok(())
}

/// Sets the number of worker threads (`--threads`); none = one per core.
pub fn set_threads(threads: Option<usize>) -> Result<usize> {
    if let Some(t) = threads {
        if t == 0 {
            bail!("--threads 0: must be at least 1");
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
            .context("--threads: cannot start the worker pool")?;
    }
    Ok(rayon::current_num_threads())
}

/// Creates the output folder.
pub fn out_dir(dir: &Path) -> Result<PathBuf> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create output folder", dir.display()))?;
    Ok(dir.to_path_buf())
}

/// Writes a float32 `.npy` dump, naming the file on failure.
pub fn write_f32(path: &Path, shape: &[usize], values: &[f32]) -> Result<()> {
    trample::npy::write_f32(path, shape, values)
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// Writes a uint8 `.npy` dump, naming the file on failure.
pub fn write_u8(path: &Path, shape: &[usize], values: &[u8]) -> Result<()> {
    trample::npy::write_u8(path, shape, values)
        .with_context(|| format!("{}: cannot write", path.display()))
}
