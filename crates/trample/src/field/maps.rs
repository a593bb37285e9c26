//! Grass maps (issue 14, ours): where grass grows, how tall and what
//! colour, per position on the field.
//!
//! - **density** in [0, 1]: the share of blades that grow there (0 = no
//!   grass: under a road, inside a house). Blade `b` grows when
//!   `u_b < density(root_b)`, `u_b` a seeded uniform number of its own, so
//!   0.5 keeps every other blade on average and the choice is the same on
//!   every run and thread count.
//! - **height** ≥ 0: a factor on `field.blade_height_m` (0 = mown to the
//!   ground).
//! - **tint** in [0, 1]: the renderer's colour of the blade's tip, from
//!   lush green (0) to dry straw (1) ([`super::Blades::tint`]); without a
//!   tint map each blade draws its own at random.
//!
//! # Why absent blades stay in storage
//! A blade that does not grow keeps its slot: it is stored with zero
//! height (every vertex at its root, `seg_len` 0, width 0, see
//! [`super::Blades::is_present`]) and the step never tests, bends or
//! propagates through it. The alternative — storing only the blades that
//! grow — would break what everything else relies on: blade `b` of cell
//! `c` is `c · blades_per_cell + slot`, neighbours (Definition 6) are
//! found by arithmetic, patches are equal contiguous ranges, and the GPU
//! path splits the field into chunks of whole patches on that basis. The
//! cost is the state of the absent blades (about 200 bytes a blade at 4
//! segments); the step's work memory, which the memory estimate counts
//! for every blade that could be under an object, follows the density
//! ([`super::FieldParams::memory_estimate_bytes_for`]).
//!
//! Maps come from grey images in a scene file (`[field.maps]`,
//! [`GrassMapParams`]; inside the scene's folder, stretched over the whole
//! field like the terrain's height map) or from values and closures in
//! code ([`GrassMap::Constant`], [`GrassMap::Function`]).

use super::grid_image::{GridImageError, load_grid_image};
use super::params::FieldError;
use super::terrain::HeightGrid;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// `[field.maps]` of a scene file: grey images (PNG, 8 or 16 bits), paths
/// relative to the scene file's folder and inside it. Each is stretched
/// over the whole field (left column at −x, top row at −z); values between
/// pixels are interpolated bilinearly.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GrassMapParams {
    /// Density: black = no grass, white = every blade. Default: none
    /// (grass everywhere).
    pub density: Option<PathBuf>,
    /// Height factor: black = `height_range[0]`, white = `height_range[1]`
    /// times `field.blade_height_m`. Default: none (factor 1 everywhere).
    pub height: Option<PathBuf>,
    /// The factors black and white stand for in the height map. Default
    /// `[0, 1]`: white is the field's blade height, black mown to the
    /// ground. Each in [0, 10], the first not above the second.
    pub height_range: [f32; 2],
    /// Tint: black = lush green, white = dry straw. Default: none (each
    /// blade its own random tint).
    pub tint: Option<PathBuf>,
}

impl GrassMapParams {
    /// Checks what can be checked without reading the images (part of
    /// [`super::FieldParams::validate`]).
    ///
    /// # Errors
    /// [`FieldError`] for `maps.height_range` out of [0, 10] or decreasing.
    pub fn validate(&self) -> Result<(), FieldError> {
        let [lo, hi] = self.height_range;
        let ok = |v: f32| v.is_finite() && (0.0..=MAX_HEIGHT_FACTOR).contains(&v);
        if ok(lo) && ok(hi) && lo <= hi {
            Ok(())
        } else {
            Err(FieldError {
                key: "maps.height_range",
                value: format!("[{lo}, {hi}]"),
                allowed: "each must be in [0, 10] and the first not above the second",
            })
        }
    }

    /// True when no map is named.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.density.is_none() && self.height.is_none() && self.tint.is_none()
    }
}

/// Largest height factor a map may give: ten times the field's blade height
/// (a 4.5 m blade at the default height), far beyond grass.
pub const MAX_HEIGHT_FACTOR: f32 = 10.0;

/// Why a grass map was refused. Messages start with the scene key.
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    /// A value out of range (see [`GrassMapParams::validate`]).
    #[error(transparent)]
    Value(#[from] FieldError),
    /// An image could not be used.
    #[error("field.maps.{key} = {source}")]
    Image {
        /// `density`, `height` or `tint`.
        key: &'static str,
        /// What went wrong with the file.
        source: GridImageError,
    },
}

/// One map: a value at every (x, z) of the field.
#[derive(Clone)]
pub enum GrassMap {
    /// The same value everywhere.
    Constant(f32),
    /// A grid of values over the field (an image), bilinear.
    Grid(HeightGrid),
    /// A function of world (x, z), metres; called once per blade while the
    /// field is generated (from several threads).
    Function(Arc<dyn Fn(f32, f32) -> f32 + Send + Sync>),
}

impl std::fmt::Debug for GrassMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GrassMap::Constant(v) => f.debug_tuple("Constant").field(v).finish(),
            GrassMap::Grid(g) => f.debug_tuple("Grid").field(&g.dims).finish(),
            GrassMap::Function(_) => f.write_str("Function(..)"),
        }
    }
}

impl GrassMap {
    /// A map given by `f(x, z)` (world metres).
    pub fn function(f: impl Fn(f32, f32) -> f32 + Send + Sync + 'static) -> Self {
        GrassMap::Function(Arc::new(f))
    }

    /// The value at world (x, z); NaN counts as 0.
    #[must_use]
    pub fn value_at(&self, x: f32, z: f32) -> f32 {
        let v = match self {
            GrassMap::Constant(v) => *v,
            GrassMap::Grid(g) => g.sample(x, z),
            GrassMap::Function(f) => f(x, z),
        };
        if v.is_nan() { 0.0 } else { v }
    }

    /// True for a constant map of value `v`.
    #[must_use]
    pub fn is_constant(&self, v: f32) -> bool {
        matches!(self, GrassMap::Constant(c) if *c == v)
    }
}

/// The three maps of a field (see the module docs). The default grows
/// every blade at the field's height with random tints: a field without
/// maps.
#[derive(Clone, Debug)]
pub struct GrassMaps {
    /// Share of blades that grow, clamped to [0, 1]. Default 1.
    pub density: GrassMap,
    /// Factor on `field.blade_height_m`, clamped to [0, 10]. Default 1.
    pub height: GrassMap,
    /// Tint in [0, 1] (clamped); `None`: random per blade. Default `None`.
    pub tint: Option<GrassMap>,
}

impl Default for GrassMaps {
    fn default() -> Self {
        Self {
            density: GrassMap::Constant(1.0),
            height: GrassMap::Constant(1.0),
            tint: None,
        }
    }
}

impl GrassMaps {
    /// The maps a scene's `[field.maps]` names, read from `base_dir` (the
    /// scene's folder) and stretched over a field of `extent` (x, z) metres.
    ///
    /// # Errors
    /// [`MapError`] naming the key when a range is out of bounds or an image
    /// cannot be used.
    pub fn from_params(
        params: &GrassMapParams,
        extent: [f32; 2],
        base_dir: &Path,
    ) -> Result<Self, MapError> {
        params.validate()?;
        let load = |key: &'static str, path: &Path| {
            load_grid_image(base_dir, path, extent)
                .map_err(|source| MapError::Image { key, source })
        };
        let mut maps = GrassMaps::default();
        if let Some(p) = &params.density {
            maps.density = GrassMap::Grid(load("density", p)?);
        }
        if let Some(p) = &params.height {
            let mut grid = load("height", p)?;
            let [lo, hi] = params.height_range;
            for v in &mut grid.heights {
                *v = lo + (hi - lo) * *v;
            }
            maps.height = GrassMap::Grid(grid);
        }
        if let Some(p) = &params.tint {
            maps.tint = Some(GrassMap::Grid(load("tint", p)?));
        }
        Ok(maps)
    }

    /// Density at (x, z), in [0, 1].
    #[must_use]
    pub fn density_at(&self, x: f32, z: f32) -> f32 {
        self.density.value_at(x, z).clamp(0.0, 1.0)
    }

    /// Height factor at (x, z), in [0, [`MAX_HEIGHT_FACTOR`]].
    #[must_use]
    pub fn height_at(&self, x: f32, z: f32) -> f32 {
        self.height.value_at(x, z).clamp(0.0, MAX_HEIGHT_FACTOR)
    }

    /// Tint at (x, z), in [0, 1], if there is a tint map.
    #[must_use]
    pub fn tint_at(&self, x: f32, z: f32) -> Option<f32> {
        self.tint.as_ref().map(|t| t.value_at(x, z).clamp(0.0, 1.0))
    }

    /// True when every blade grows (density the constant 1): no blade is
    /// left out whatever the height map says, except where it says 0.
    #[must_use]
    pub fn grows_everywhere(&self) -> bool {
        self.density.is_constant(1.0)
    }
}
