//! The ground the blades stand on: flat, value noise, or a height map
//! (DESIGN §2). Blades' roots sit on it; the ground guard of the deformation
//! keeps every vertex above it.

use super::grid_image::{GridImageError, load_grid_image};
use super::params::TerrainParams;
use std::path::Path;

/// Ground height as a function of (x, z).
#[derive(Clone, Debug, PartialEq)]
pub enum Terrain {
    /// A plane at this height.
    Flat(f32),
    /// Smooth value noise.
    Noise {
        /// Peak-to-mean height, metres.
        amplitude: f32,
        /// Lattice spacing, metres.
        wavelength: f32,
        /// Seed of the lattice values.
        seed: u64,
    },
    /// Heights sampled on a grid stretched over the field, bilinear between samples.
    Heightmap(HeightGrid),
}

/// A grid of values (heights, or the grass maps' values) covering the
/// rectangle `origin .. origin + size`, sampled bilinearly.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightGrid {
    /// Samples along x and z.
    pub dims: [usize; 2],
    /// Row-major (z then x) heights, metres.
    pub heights: Vec<f32>,
    /// World (x, z) of sample (0, 0).
    pub origin: [f32; 2],
    /// World size (x, z) covered by the grid.
    pub size: [f32; 2],
}

/// Why a terrain could not be made. Messages start with the scene key.
#[derive(Debug, thiserror::Error)]
pub enum TerrainError {
    /// The height-map path leaves the scene's folder ([`crate::paths`]).
    #[error("field.terrain.path = {path:?}: {reason}")]
    Outside {
        /// The path as written.
        path: std::path::PathBuf,
        /// How it leaves the folder.
        reason: crate::paths::PathEscape,
    },
    /// The height-map image could not be read.
    #[error("field.terrain: {path}: cannot read height map: {reason}")]
    Unreadable {
        /// The image file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// The height-map image is too small to interpolate.
    #[error("field.terrain: {path}: height map is {w}x{h} pixels; at least 2x2 are needed")]
    TooSmall {
        /// The image file.
        path: String,
        /// Width in pixels.
        w: u32,
        /// Height in pixels.
        h: u32,
    },
}

impl Terrain {
    /// Builds the terrain of `params` over a field of `extent` (x, z) metres
    /// centred on the origin. `base_dir` (the scene's folder) resolves a
    /// height map's relative path, which must stay inside it
    /// ([`crate::paths::resolve_inside`]).
    pub fn from_params(
        params: &TerrainParams,
        extent: [f32; 2],
        base_dir: &Path,
    ) -> Result<Self, TerrainError> {
        Ok(match params {
            TerrainParams::Flat { height_m } => Terrain::Flat(*height_m),
            TerrainParams::Noise {
                amplitude_m,
                wavelength_m,
                seed,
            } => Terrain::Noise {
                amplitude: *amplitude_m,
                wavelength: *wavelength_m,
                seed: *seed,
            },
            TerrainParams::Heightmap {
                path,
                height_scale_m,
            } => {
                let mut grid = load_grid_image(base_dir, path, extent).map_err(|e| match e {
                    GridImageError::Outside { path, reason } => {
                        TerrainError::Outside { path, reason }
                    }
                    GridImageError::Unreadable { path, reason } => {
                        TerrainError::Unreadable { path, reason }
                    }
                    GridImageError::TooSmall { path, w, h } => {
                        TerrainError::TooSmall { path, w, h }
                    }
                })?;
                for v in &mut grid.heights {
                    *v *= height_scale_m;
                }
                Terrain::Heightmap(grid)
            }
        })
    }

    /// Ground height at world (x, z), metres.
    #[must_use]
    pub fn height_at(&self, x: f32, z: f32) -> f32 {
        match self {
            Terrain::Flat(h) => *h,
            Terrain::Noise {
                amplitude,
                wavelength,
                seed,
            } => {
                // Two octaves of value noise, smoothstep-interpolated.
                let n1 = value_noise(x / wavelength, z / wavelength, *seed);
                let n2 = value_noise(
                    x * 2.0 / wavelength,
                    z * 2.0 / wavelength,
                    seed ^ SECOND_OCTAVE_SEED,
                );
                amplitude * (0.75 * n1 + 0.25 * n2)
            }
            Terrain::Heightmap(g) => g.sample(x, z),
        }
    }
}

impl HeightGrid {
    /// Bilinear sample at world (x, z), clamped to the grid.
    #[must_use]
    pub fn sample(&self, x: f32, z: f32) -> f32 {
        let [w, h] = self.dims;
        let fx = ((x - self.origin[0]) / self.size[0] * (w - 1) as f32).clamp(0.0, (w - 1) as f32);
        let fz = ((z - self.origin[1]) / self.size[1] * (h - 1) as f32).clamp(0.0, (h - 1) as f32);
        let (x0, z0) = ((fx as usize).min(w - 2), (fz as usize).min(h - 2));
        let (tx, tz) = (fx - x0 as f32, fz - z0 as f32);
        let at = |i: usize, j: usize| self.heights[j * w + i];
        let a = at(x0, z0) + (at(x0 + 1, z0) - at(x0, z0)) * tx;
        let b = at(x0, z0 + 1) + (at(x0 + 1, z0 + 1) - at(x0, z0 + 1)) * tx;
        a + (b - a) * tz
    }
}

/// Value noise in [-1, 1] on the unit lattice, smoothstep-interpolated.
fn value_noise(x: f32, z: f32, seed: u64) -> f32 {
    let (xf, zf) = (x.floor(), z.floor());
    let (ix, iz) = (xf as i64, zf as i64);
    let (tx, tz) = (smooth(x - xf), smooth(z - zf));
    let v = |i: i64, j: i64| lattice(i, j, seed);
    let a = v(ix, iz) + (v(ix + 1, iz) - v(ix, iz)) * tx;
    let b = v(ix, iz + 1) + (v(ix + 1, iz + 1) - v(ix, iz + 1)) * tx;
    a + (b - a) * tz
}

fn smooth(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

/// XORed into the seed of [`Terrain::Noise`]'s second octave.
pub const SECOND_OCTAVE_SEED: u64 = 0x9E37;

/// Deterministic lattice value in [-1, 1] (splitmix64 of the coordinates):
/// the value of [`Terrain::Noise`]'s octave with `seed` at lattice point
/// (i, j). Public for the GPU path, which tabulates it.
#[must_use]
pub fn lattice(i: i64, j: i64, seed: u64) -> f32 {
    let mut h = seed
        ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (j as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    h = (h ^ (h >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^= h >> 31;
    (h >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_is_flat() {
        let t = Terrain::Flat(0.3);
        assert_eq!(t.height_at(10.0, -4.0), 0.3);
    }

    #[test]
    fn noise_is_bounded_continuous_and_seeded() {
        let t = Terrain::Noise {
            amplitude: 2.0,
            wavelength: 8.0,
            seed: 7,
        };
        let mut prev = t.height_at(0.0, 3.0);
        for i in 1..2000 {
            let h = t.height_at(i as f32 * 0.01, 3.0);
            assert!(h.abs() <= 2.0 + 1e-4);
            assert!((h - prev).abs() < 0.05, "noise jumps at step {i}");
            prev = h;
        }
        let u = Terrain::Noise {
            amplitude: 2.0,
            wavelength: 8.0,
            seed: 8,
        };
        assert_ne!(t.height_at(1.3, 2.7), u.height_at(1.3, 2.7));
    }

    #[test]
    fn heightmap_is_bilinear() {
        let g = HeightGrid {
            dims: [2, 2],
            heights: vec![0.0, 1.0, 2.0, 3.0],
            origin: [0.0, 0.0],
            size: [1.0, 1.0],
        };
        assert!((g.sample(0.5, 0.5) - 1.5).abs() < 1e-6);
        assert!((g.sample(1.0, 0.0) - 1.0).abs() < 1e-6);
        assert!((g.sample(-5.0, 9.0) - 2.0).abs() < 1e-6, "clamped outside");
    }
}
