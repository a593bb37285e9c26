//! What the subcommands share: loading a scene with command-line overrides,
//! the worker count, the output folder, `.npy` encoding.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use trample::npy::{Dtype, encode};
use trample::scene::{DEFAULT_SCENE_TOML, Scene};

/// Command-line flags that override the scene's `[sim]` table.
#[derive(Clone, Copy, Debug, Default)]
pub struct SimOverrides {
    /// `--precision`.
    pub precision: Option<u32>,
    /// `--dt`.
    pub dt: Option<f32>,
    /// `--memory-limit-gib`.
    pub memory_limit_gib: Option<f32>,
    /// `--far-every`.
    pub far_every: Option<u32>,
    /// `--far-outside-view` (given: `true`).
    pub far_outside_view: bool,
}

impl SimOverrides {
    /// Checks each flag on its own, so that a message names the flag only
    /// when the flag is what is wrong.
    fn check(&self) -> Result<()> {
        if let Some(p) = self.precision
            && !(1..=trample::step::params::MAX_PRECISION).contains(&p)
        {
            bail!("--precision {p}: must be 1..=32 (the paper uses 1..=7)");
        }
        if let Some(dt) = self.dt
            && let Err(e) = trample::step::params::check_dt(dt)
        {
            bail!("--dt {dt}: {}", e.allowed);
        }
        if let Some(g) = self.memory_limit_gib
            && !(g.is_finite() && g > 0.0)
        {
            bail!("--memory-limit-gib {g}: must be a finite number of GiB > 0");
        }
        if let Some(k) = self.far_every
            && !(1..=64).contains(&k)
        {
            bail!("--far-every {k}: must be 1..=64 (1: every object every step)");
        }
        Ok(())
    }
}

/// Loads SCENE (or the embedded default scene when none is given), applies
/// the flags, then validates: a scene too large for its own
/// `sim.memory_limit_gib` runs when `--memory-limit-gib` allows it.
pub fn load_scene(path: Option<&Path>, flags: SimOverrides) -> Result<Scene> {
    flags.check()?;
    let mut scene = match path {
        Some(p) => Scene::read_unvalidated(p)?,
        None => Scene::parse_unvalidated(DEFAULT_SCENE_TOML, "<default scene>", Path::new("."))?,
    };
    let sim = &mut scene.file.sim;
    if let Some(p) = flags.precision {
        sim.precision = p;
    }
    if let Some(dt) = flags.dt {
        sim.dt_s = dt;
    }
    if let Some(g) = flags.memory_limit_gib {
        sim.memory_limit_gib = g;
    }
    if let Some(k) = flags.far_every {
        sim.far_every = k;
    }
    if flags.far_outside_view {
        sim.far_outside_view = true;
    }
    scene.validate()?;
    Ok(scene)
}

/// Most worker threads `--threads` accepts: far more than any machine's
/// cores (with 100,000, three frames of the default scene had not finished
/// in two minutes).
pub const MAX_THREADS: usize = 1024;

/// Sets the number of worker threads (`--threads`); none = one per core.
pub fn set_threads(threads: Option<usize>) -> Result<usize> {
    if let Some(t) = threads {
        if !(1..=MAX_THREADS).contains(&t) {
            bail!("--threads {t}: must be 1..={MAX_THREADS}");
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
        .with_context(|| format!("--out {}: cannot create the output folder", dir.display()))?;
    Ok(dir.to_path_buf())
}

/// The bytes of a float32 `.npy` file.
pub fn npy_f32(shape: &[usize], values: &[f32]) -> Vec<u8> {
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    encode(Dtype::F32, shape, &bytes)
}

/// The bytes of a uint8 `.npy` file.
pub fn npy_u8(shape: &[usize], values: &[u8]) -> Vec<u8> {
    encode(Dtype::U8, shape, values)
}

/// Parses an image size `WIDTHxHEIGHT` (`--size`), both sides 16..=8192.
///
/// # Errors
/// A message that shows the expected form.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("{s:?}: expected WIDTHxHEIGHT, e.g. 1280x720, both sides 16..=8192");
    let (w, h) = s.split_once('x').ok_or_else(bad)?;
    let (w, h): (u32, u32) = (w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?);
    if !(16..=8192).contains(&w) || !(16..=8192).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}
